// kiloloop_bench_aerial: per-call latency and heap allocations of the aerial manipulator's
// controller step and its parts, on seeded states around hover with the arm moving; the step and
// the allocation also with 6 and 8 rotors (a ring of radius 0.25 m, alternating spin, on the same
// body and arm) to show the cost of the rotor count.
//   kiloloop_bench_aerial <path/to/aerial_manipulator.urdf> [--calls N] [--quick] [--json]
// Prints median, p99 and max [ns] and allocations per call for each; the SIL real-time factor is
// measured by the Python side (kiloloop bench).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <memory>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "alloc_counter.hpp"
#include "kiloloop/aerial/aerial_controller.hpp"
#include "kiloloop/rt/latency_stats.hpp"
#include "kiloloop/urdf/urdf_loader.hpp"

namespace {

using Clock = std::chrono::steady_clock;
constexpr int kStates = 1024;
constexpr long kWarmUp = 2000;
constexpr unsigned kSeed = 20261122;

struct Row {
  std::string name;
  kiloloop::LatencySummary summary;
  double allocations_per_call = 0.0;
  long failures = 0;
};

std::string cpu_model() {
  std::ifstream f("/proc/cpuinfo");
  std::string line;
  while (std::getline(f, line))
    if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
  return "unknown";
}

// Times `call(i)` one call at a time; the allocation scope spans the whole run (the sample buffer
// is sized beforehand, so the bookkeeping itself never allocates).
// n rotors on a ring of radius 0.25 m, alternating spin, 8 N each.
kiloloop::RotorAllocationConfig ring(int n) {
  kiloloop::RotorAllocationConfig c;
  c.positions.resize(3, n);
  c.spin.resize(n);
  for (int i = 0; i < n; ++i) {
    const double a = 2.0 * 3.14159265358979323846 * (i + 0.5) / n;
    c.positions.col(i) << 0.25 * std::cos(a), 0.25 * std::sin(a), 0.0;
    c.spin[i] = i % 2 ? 1.0 : -1.0;
  }
  return c;
}

Row time_calls(const char* name, const std::function<bool(int)>& call, long n) {
  for (long i = 0; i < kWarmUp; ++i) call(static_cast<int>(i % kStates));
  kiloloop::LatencyStats stats(static_cast<std::size_t>(n));
  Row row{name, {}, 0.0, 0};
  kiloloop::testing::AllocationScope scope;
  for (long i = 0; i < n; ++i) {
    const auto t0 = Clock::now();
    const bool ok = call(static_cast<int>(i % kStates));
    const auto t1 = Clock::now();
    stats.record(std::chrono::duration_cast<std::chrono::nanoseconds>(t1 - t0).count());
    row.failures += !ok;
  }
  row.allocations_per_call = double(scope.count()) / double(n);
  row.summary = stats.summarize();
  return row;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace kiloloop;
  std::string urdf;
  long n = 100000;
  bool json = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--json") json = true;
    else if (a == "--quick") n = 10000;
    else if (a == "--calls" && i + 1 < argc) n = std::atol(argv[++i]);
    else if (a.rfind("--", 0) != 0 && urdf.empty()) urdf = a;
    else {
      std::fprintf(stderr, "usage: kiloloop_bench_aerial <urdf> [--calls N] [--quick] [--json]\n");
      return 2;
    }
  }
  if (urdf.empty() || n <= 0) {
    std::fprintf(stderr, "usage: kiloloop_bench_aerial <urdf> [--calls N] [--quick] [--json]\n");
    return 2;
  }
  auto model = std::make_shared<RobotModel>();
  std::string why;
  AerialConfig config;  // defaults, plus the options that cost the most
  config.attitude.gains.ki << 50.0, 50.0, 10.0;
  config.arm_coulomb = Eigen::VectorXd::Constant(1, 0.01);
  AerialConfig lee = config;
  lee.attitude.law = AttitudeLawType::kGeometricSo3;
  AerialConfig hexa = config, octo = config;
  hexa.rotors = ring(6);
  octo.rotors = ring(8);
  AerialController ctrl, ctrl_lee, ctrl6, ctrl8;
  FloatingBaseRne rne;
  RotorAllocation alloc, alloc6, alloc8;
  if (failed(model_from_urdf_file(urdf, "", "ee_link", model.get(), &why)) ||
      failed(AerialController::configure(config, model, &ctrl, &why)) ||
      failed(AerialController::configure(lee, model, &ctrl_lee, &why)) ||
      failed(FloatingBaseRne::configure(model, &rne, &why)) ||
      failed(AerialController::configure(hexa, model, &ctrl6, &why)) ||
      failed(AerialController::configure(octo, model, &ctrl8, &why)) ||
      failed(RotorAllocation::configure(config.rotors, &alloc, &why)) ||
      failed(RotorAllocation::configure(hexa.rotors, &alloc6, &why)) ||
      failed(RotorAllocation::configure(octo.rotors, &alloc8, &why))) {
    std::fprintf(stderr, "kiloloop_bench_aerial: %s\n", why.c_str());
    return 1;
  }
  const int nq = model->nq();
  // Seeded states near hover: small attitude and position errors, noisy rates, the arm moving.
  std::mt19937 rng(kSeed);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<AerialInput> in(kStates, ctrl.make_input()), ee_in;
  for (auto& x : in) {
    x.position << 0.01 * g(rng), 0.01 * g(rng), 1.0 + 0.01 * g(rng);
    x.velocity << 0.05 * g(rng), 0.05 * g(rng), 0.05 * g(rng);
    const Eigen::Vector3d rv(0.03 * g(rng), 0.03 * g(rng), 0.03 * g(rng));
    const Eigen::Quaterniond q(Eigen::AngleAxisd(rv.norm(), rv.normalized()));
    x.quat << q.w(), q.x(), q.y(), q.z();
    x.gyro << 0.1 * g(rng), 0.1 * g(rng), 0.1 * g(rng);
    x.accel << 0.1 * g(rng), 0.1 * g(rng), 9.81 + 0.1 * g(rng);
    x.position_ref << 0.0, 0.0, 1.0;
    for (int j = 0; j < nq; ++j) {
      x.q[j] = 0.5 * g(rng);
      x.qd[j] = 0.5 * g(rng);
      x.q_ref[j] = x.q[j] + 0.01 * g(rng);
      x.qd_ref[j] = 0.5 * g(rng);
      x.qdd_ref[j] = 2.0 * g(rng);
    }
  }
  ee_in = in;
  for (auto& x : ee_in) {
    x.arm_mode = ArmMode::kEndEffector;
    x.ee_position_ref << 0.15 + 0.02 * g(rng), 0.05 + 0.02 * g(rng), 0.72 + 0.02 * g(rng);
  }
  AerialOutput out = ctrl.make_output(), out6 = ctrl6.make_output(), out8 = ctrl8.make_output();
  long tick = 0;
  auto step = [&](AerialController& c, std::vector<AerialInput>& inputs, AerialOutput& o) {
    return [&c, &inputs, &o, &tick](int i) {
      AerialInput& x = inputs[i];
      x.t = x.stamp = 0.001 * static_cast<double>(tick++);
      return !failed(c.step(x, o));
    };
  };
  Eigen::VectorXd tau(nq);
  Vector6d W;
  std::vector<Eigen::Vector4d> wrenches(kStates);
  for (auto& w : wrenches) w << 17.7 + g(rng), 0.2 * g(rng), 0.2 * g(rng), 0.05 * g(rng);
  Eigen::VectorXd thrust(4), thrust6(6), thrust8(8);

  std::vector<Row> rows;
  rows.push_back(time_calls("aerial.step (quaternion PD, joints)", step(ctrl, in, out), n));
  rows.push_back(time_calls("aerial.step (Lee SO(3), joints)", step(ctrl_lee, in, out), n));
  rows.push_back(time_calls("aerial.step (end-effector IK)", step(ctrl, ee_in, out), n));
  rows.push_back(time_calls("aerial.step (6 rotors, joints)", step(ctrl6, in, out6), n));
  rows.push_back(time_calls("aerial.step (8 rotors, joints)", step(ctrl8, in, out8), n));
  rows.push_back(time_calls("floating_base_rne.compute", [&](int i) {
    BaseMotion b;
    b.omega = in[i].gyro;
    b.specific_force = in[i].accel;
    return ok(rne.compute(in[i].q, in[i].qd, in[i].qdd_ref, b, tau, &W));
  }, n));
  rows.push_back(time_calls("rotor_allocation.allocate (4 rotors)", [&](int i) {
    return !failed(alloc.allocate(wrenches[i], thrust));
  }, n));
  rows.push_back(time_calls("rotor_allocation.allocate (6 rotors)", [&](int i) {
    return !failed(alloc6.allocate(wrenches[i], thrust6));
  }, n));
  rows.push_back(time_calls("rotor_allocation.allocate (8 rotors)", [&](int i) {
    return !failed(alloc8.allocate(wrenches[i], thrust8));
  }, n));
  for (const Row& r : rows) {
    if (r.failures > 0) {
      std::fprintf(stderr, "kiloloop_bench_aerial: %s failed %ld of %ld calls\n", r.name.c_str(),
                   r.failures, n);
      return 1;
    }
  }
  if (json) {
    std::printf("{\"machine\": {\"cpu\": \"%s\", \"nproc\": %u}, \"calls\": %ld, \"results\": [",
                cpu_model().c_str(), std::thread::hardware_concurrency(), n);
    for (std::size_t k = 0; k < rows.size(); ++k) {
      const Row& r = rows[k];
      std::printf("%s{\"name\": \"%s\", \"median_ns\": %lld, \"p99_ns\": %lld, \"max_ns\": %lld, "
                  "\"allocations_per_call\": %g}",
                  k ? ", " : "", r.name.c_str(), (long long)r.summary.median_ns,
                  (long long)r.summary.p99_ns, (long long)r.summary.max_ns,
                  r.allocations_per_call);
    }
    std::printf("]}\n");
  } else {
    std::printf("aerial manipulator, %ld calls each [%s, %u cores]\n", n, cpu_model().c_str(),
                std::thread::hardware_concurrency());
    std::printf("  %-40s%9s%9s%10s%8s\n", "call", "median", "p99", "max", "alloc");
    for (const Row& r : rows)
      std::printf("  %-40s%9lld%9lld%10lld%8.2f\n", r.name.c_str(), (long long)r.summary.median_ns,
                  (long long)r.summary.p99_ns, (long long)r.summary.max_ns, r.allocations_per_call);
    std::printf("  times in ns; alloc = heap allocations per call\n");
  }
  return 0;
}
