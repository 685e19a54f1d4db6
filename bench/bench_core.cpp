// kiloloop_bench_core: per-call latency and heap allocations of the dynamics, the joint torque
// controllers and the quintic trajectory on the UR5, each beside the raw KDL call it wraps.
//   kiloloop_bench_core <path/to/ur5.urdf> [--calls N] [--quick] [--json]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <random>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <kdl/chaindynparam.hpp>
#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/chainidsolver_recursive_newton_euler.hpp>
#include <kdl/chainjnttojacsolver.hpp>

#include "alloc_counter.hpp"
#include "kiloloop/control/computed_torque.hpp"
#include "kiloloop/control/joint_pd_gravity.hpp"
#include "kiloloop/dynamics/dynamics.hpp"
#include "kiloloop/quadruped/quadruped_controller.hpp"
#include "kiloloop/rt/latency_stats.hpp"
#include "kiloloop/trajectory/quintic.hpp"
#include "kiloloop/urdf/urdf_loader.hpp"

namespace {

using Clock = std::chrono::steady_clock;
using kiloloop::LatencyStats;
using kiloloop::LatencySummary;

constexpr int kStates = 1024;  // distinct inputs, cycled: realistic cache use, same on both sides
constexpr long kBlock = 1000;  // ours and raw alternate in blocks of this many calls
constexpr long kWarmUp = 2000;  // untimed calls per side first: caches, branch predictors, clocks
constexpr unsigned kSeed = 20240601;

struct Side {
  Side(std::string side_name, std::size_t calls) : name(std::move(side_name)), stats(calls) {}
  std::string name;
  LatencyStats stats;
  std::size_t allocations = 0, failures = 0;
  LatencySummary summary;  // filled once timing is over
};

struct Result {
  Side ours, raw;
  bool has_raw = false;
};

// Times calls [first, first + count) one at a time; `call(i)` returns false on a failed status.
// The clock reads and the sample store lie outside each measured interval. The allocation scope
// spans the block, whose bookkeeping never allocates: the sample buffer is sized beforehand.
template <class Call>
void time_block(Call& call, long first, long count, Side& side) {
  kiloloop::testing::AllocationScope scope;
  for (long i = first; i < first + count; ++i) {
    const auto t0 = Clock::now();
    const bool ok = call(static_cast<int>(i % kStates));
    const auto t1 = Clock::now();
    side.stats.record(std::chrono::duration_cast<std::chrono::nanoseconds>(t1 - t0).count());
    side.failures += !ok;
  }
  side.allocations += scope.count();
}

template <class Call>
void warm_up(Call& call) {
  for (long i = 0; i < kWarmUp; ++i) call(static_cast<int>(i % kStates));
}

// raw_name == nullptr: no raw counterpart, only ours is timed.
template <class Ours, class Raw>
Result run_pair(const char* name, Ours ours, const char* raw_name, Raw raw, long n) {
  const bool has_raw = raw_name != nullptr;
  Result r{Side(name, n), Side(has_raw ? raw_name : "", has_raw ? n : 0), has_raw};
  warm_up(ours);
  if (has_raw) warm_up(raw);
  // Alternating blocks, and which side leads each one, give both sides the same machine state
  // (frequency, other load) without making them evict each other's caches on every call.
  for (long first = 0, b = 0; first < n; first += kBlock, ++b) {
    const long count = std::min(kBlock, n - first);
    if (b % 2 == 0) time_block(ours, first, count, r.ours);
    if (has_raw) time_block(raw, first, count, r.raw);
    if (b % 2 == 1) time_block(ours, first, count, r.ours);
  }
  r.ours.summary = r.ours.stats.summarize();
  r.raw.summary = r.raw.stats.summarize();
  return r;
}

// The same seeded random states as Eigen columns (kiloloop's API) and KDL arrays (raw calls),
// all filled before any timing.
struct States {
  Eigen::MatrixXd q, qd, qdd;  // (nq, kStates) [rad], [rad/s], [rad/s^2]
  std::vector<KDL::JntArray> kq, kqd, kqdd;
  std::vector<kiloloop::JointControlInput> inputs;
  std::vector<double> t;  // [s] trajectory sample times
};

States make_states(int nq, double duration) {
  std::mt19937 rng(kSeed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const auto random = [&](int rows, double scale) {
    return Eigen::MatrixXd(
        Eigen::MatrixXd::NullaryExpr(rows, kStates, [&] { return scale * u(rng); }));
  };
  States s;
  s.q = random(nq, 3.14);
  s.qd = random(nq, 2.0);
  s.qdd = random(nq, 5.0);
  const Eigen::MatrixXd dq = random(nq, 0.05), dqd = random(nq, 0.2);
  for (int i = 0; i < kStates; ++i) {
    for (auto* v : {&s.kq, &s.kqd, &s.kqdd}) v->emplace_back(nq);
    s.kq[i].data = s.q.col(i);
    s.kqd[i].data = s.qd.col(i);
    s.kqdd[i].data = s.qdd.col(i);
    // A tracking error of a few centiradians, as a controller sees while following a trajectory.
    kiloloop::JointControlInput in = kiloloop::make_joint_input(nq);
    in.t = in.stamp = 0.001 * i;
    in.q = s.q.col(i);
    in.qd = s.qd.col(i);
    in.q_ref = s.q.col(i) + dq.col(i);
    in.qd_ref = s.qd.col(i) + dqd.col(i);
    in.qdd_ref = s.qdd.col(i);
    s.inputs.push_back(std::move(in));
    s.t.push_back(duration * 0.5 * (1.0 + u(rng)));
  }
  return s;
}

std::string cpu_model() {
  std::ifstream f("/proc/cpuinfo");
  for (std::string line; std::getline(f, line);) {
    if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
  }
  return "unknown";
}

// What the compiler tells us about the flags (CMake does not pass the flag string itself).
std::string build_flags() {
  std::string s = "optimized";
#ifndef __OPTIMIZE__
  s = "unoptimized";
#endif
#ifdef NDEBUG
  s += " NDEBUG";
#endif
#ifdef __FAST_MATH__
  s += " fast-math";
#endif
#ifdef __AVX2__
  s += " AVX2";
#endif
  return s;
}

// Median cost of two back-to-back clock reads: included in every sample on both sides.
std::int64_t timer_overhead_ns() {
  Side side("timer", 100000);
  auto nothing = [](int) { return true; };
  time_block(nothing, 0, 100000, side);
  return side.stats.summarize().median_ns;
}

std::string compiler() {
#if defined(__GNUC__) && !defined(__clang__)
  return std::string("gcc ") + __VERSION__;
#else
  return __VERSION__;
#endif
}

std::string json_escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    if (static_cast<unsigned char>(c) >= 0x20) out += c;
  }
  return out;
}

double ratio(const Result& r) {
  const double raw = static_cast<double>(std::max<std::int64_t>(1, r.raw.summary.median_ns));
  return static_cast<double>(r.ours.summary.median_ns) / raw;
}

void print_table(const std::vector<Result>& results, long n, std::int64_t overhead) {
  std::printf("kiloloop_bench_core: UR5, %ld timed calls per benchmark, times in ns\n", n);
  std::printf("%-28s %7s %7s %8s %6s  %-23s %7s %7s %8s %6s\n", "benchmark", "median", "p99",
              "max", "alloc", "raw KDL", "median", "p99", "max", "ratio");
  for (const Result& r : results) {
    const LatencySummary& o = r.ours.summary;
    std::printf("%-28s %7lld %7lld %8lld %6.2f", r.ours.name.c_str(), (long long)o.median_ns,
                (long long)o.p99_ns, (long long)o.max_ns, double(r.ours.allocations) / n);
    const LatencySummary& w = r.raw.summary;
    if (r.has_raw) {
      std::printf("  %-23s %7lld %7lld %8lld %6.2f", r.raw.name.c_str(), (long long)w.median_ns,
                  (long long)w.p99_ns, (long long)w.max_ns, ratio(r));
    }
    std::printf("\n");
  }
  std::printf("ratio: ours/raw medians (goal <= 1.2). alloc: heap allocations per call.\n"
              "Every sample includes ~%lld ns of clock reads.\n", (long long)overhead);
}

void print_json(const std::vector<Result>& results, long n, std::int64_t overhead) {
  std::printf("{\"machine\": {\"cpu\": \"%s\", \"nproc\": %u, \"compiler\": \"%s\", "
              "\"build\": \"%s\", \"timer_overhead_ns\": %lld},\n \"calls\": %ld, \"results\": [",
              json_escape(cpu_model()).c_str(), std::thread::hardware_concurrency(),
              json_escape(compiler()).c_str(), build_flags().c_str(), (long long)overhead, n);
  for (std::size_t k = 0; k < results.size(); ++k) {
    const Result& r = results[k];
    const LatencySummary& o = r.ours.summary;
    std::printf("%s\n  {\"name\": \"%s\", \"median_ns\": %lld, \"p99_ns\": %lld, \"max_ns\": %lld, "
                "\"allocations_per_call\": %g, \"calls\": %ld, ", k ? "," : "", r.ours.name.c_str(),
                (long long)o.median_ns, (long long)o.p99_ns, (long long)o.max_ns,
                double(r.ours.allocations) / n, n);
    const LatencySummary& w = r.raw.summary;
    if (r.has_raw) {
      std::printf("\"raw_name\": \"%s\", \"raw_median_ns\": %lld, \"raw_p99_ns\": %lld, "
                  "\"raw_max_ns\": %lld, \"ratio_median\": %.3f}", r.raw.name.c_str(),
                  (long long)w.median_ns, (long long)w.p99_ns, (long long)w.max_ns, ratio(r));
    } else {
      std::printf("\"raw_name\": null, \"raw_median_ns\": null, \"raw_p99_ns\": null, "
                  "\"raw_max_ns\": null, \"ratio_median\": null}");
    }
  }
  std::printf("\n]}\n");
}

int usage(const char* why) {
  std::fprintf(stderr, "kiloloop_bench_core: %s\nusage: kiloloop_bench_core <ur5.urdf> "
               "[--calls N] [--quick] [--json]\n", why);
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace kiloloop;
  std::string urdf, quadruped_urdf;
  long n = 100000;
  bool json = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--json") json = true;
    else if (a == "--quick") n = 10000;
    else if (a == "--calls" && i + 1 < argc) n = std::atol(argv[++i]);
    else if (a == "--quadruped" && i + 1 < argc) quadruped_urdf = argv[++i];
    else if (a.rfind("--", 0) != 0 && urdf.empty()) urdf = a;
    else return usage(("unexpected argument '" + a + "'").c_str());
  }
  if (urdf.empty()) return usage("missing the URDF path");
  if (n <= 0) return usage("--calls needs a positive count");

  auto model = std::make_shared<RobotModel>();
  std::string why;
  if (failed(model_from_urdf_file(urdf, "", "", model.get(), &why))) {
    std::fprintf(stderr, "kiloloop_bench_core: cannot load URDF '%s': %s\n", urdf.c_str(),
                 why.c_str());
    return 1;
  }
  const int nq = model->nq();
  const Eigen::Vector3d gravity(0.0, 0.0, -9.81);
  Dynamics dyn;
  ComputedTorqueController ct;
  JointPdGravityController pd;
  QuinticTrajectory traj;
  const double duration = 3.0;  // [s] of the trajectory, through 3 of the random configurations
  States s = make_states(nq, duration);
  if (failed(Dynamics::configure(model, gravity, &dyn, &why)) ||
      failed(ComputedTorqueController::configure({}, model, &ct, &why)) ||
      failed(JointPdGravityController::configure({}, model, &pd, &why)) ||
      failed(QuinticTrajectory::configure(s.q.leftCols(3), Eigen::Vector3d(0.0, 1.2, duration),
                                          &traj, &why))) {
    std::fprintf(stderr, "kiloloop_bench_core: configure failed: %s\n", why.c_str());
    return 1;
  }

  // Raw KDL: the same solvers on the same chain, outputs sized here, outside any timing.
  const KDL::Chain& chain = model->chain();
  const KDL::Vector g(gravity.x(), gravity.y(), gravity.z());
  KDL::ChainIdSolver_RNE rne(chain, g);
  KDL::ChainDynParam dp(chain, g);
  KDL::ChainFkSolverPos_recursive fk(chain);
  KDL::ChainJntToJacSolver jac(chain);
  KDL::JntArray ktau(nq);
  KDL::JntSpaceInertiaMatrix kM(nq);
  KDL::Jacobian kJ(nq);
  KDL::Frame kT;
  const KDL::Wrenches no_wrench(chain.getNrOfSegments(), KDL::Wrench::Zero());

  Eigen::VectorXd tau(nq), qt(nq), qdt(nq), qddt(nq);
  Eigen::MatrixXd M(nq, nq), J(6, nq);
  Eigen::Matrix4d T;
  JointControlOutput out = ct.make_output();

  const std::int64_t overhead = timer_overhead_ns();
  // One entry per benchmark: our call, then the raw KDL call it makes (same state index i).
  auto raw_rne = [&](int i) {
    return rne.CartToJnt(s.kq[i], s.kqd[i], s.kqdd[i], no_wrench, ktau) >= 0;
  };
  auto raw_gravity = [&](int i) { return dp.JntToGravity(s.kq[i], ktau) >= 0; };
  std::vector<Result> results;
  results.push_back(run_pair("dynamics.inverse_dynamics", [&](int i) {
    return ok(dyn.inverse_dynamics(s.q.col(i), s.qd.col(i), s.qdd.col(i), tau));
  }, "ChainIdSolver_RNE", raw_rne, n));
  results.push_back(run_pair("dynamics.mass_matrix", [&](int i) {
    return ok(dyn.mass_matrix(s.q.col(i), M));
  }, "JntToMass", [&](int i) { return dp.JntToMass(s.kq[i], kM) >= 0; }, n));
  results.push_back(run_pair("dynamics.coriolis", [&](int i) {
    return ok(dyn.coriolis(s.q.col(i), s.qd.col(i), tau));
  }, "JntToCoriolis", [&](int i) { return dp.JntToCoriolis(s.kq[i], s.kqd[i], ktau) >= 0; }, n));
  results.push_back(run_pair("dynamics.gravity", [&](int i) {
    return ok(dyn.gravity(s.q.col(i), tau));
  }, "JntToGravity", raw_gravity, n));
  results.push_back(run_pair("dynamics.forward_kinematics", [&](int i) {
    return ok(dyn.forward_kinematics(s.q.col(i), T));
  }, "FkSolverPos::JntToCart", [&](int i) { return fk.JntToCart(s.kq[i], kT) >= 0; }, n));
  results.push_back(run_pair("dynamics.jacobian", [&](int i) {
    return ok(dyn.jacobian(s.q.col(i), J));
  }, "JntToJac", [&](int i) { return jac.JntToJac(s.kq[i], kJ) >= 0; }, n));
  // Each controller's step makes exactly one KDL call: the raw side is that call alone.
  // Monotonic time across the cycled inputs: a stamp older than one already used is stale.
  long joint_tick = 0;
  results.push_back(run_pair("computed_torque.step", [&](int i) {
    s.inputs[i].t = s.inputs[i].stamp = 0.001 * static_cast<double>(joint_tick++);
    return ok(ct.step(s.inputs[i], out));
  }, "ChainIdSolver_RNE", raw_rne, n));
  results.push_back(run_pair("joint_pd_gravity.step", [&](int i) {
    s.inputs[i].t = s.inputs[i].stamp = 0.001 * static_cast<double>(joint_tick++);
    return ok(pd.step(s.inputs[i], out));
  }, "JntToGravity", raw_gravity, n));
  results.push_back(run_pair("quintic.sample", [&](int i) {
    return ok(traj.sample(s.t[i], qt, qdt, qddt));
  }, nullptr, [](int) { return true; }, n));

  if (!quadruped_urdf.empty()) {
    // The full 1 kHz quadruped step (estimator, gait, contacts, wrench, 12-variable force QP,
    // swing IK, torques) on a synthetic trot: standing joints with a small seeded wobble, IMU at
    // rest with noise, trot at 0.5 m/s, time advancing 1 ms per call. No plant closes the loop
    // here, so the contact pattern follows the schedule; the closed loop is measured in SIL.
    auto qmodel = std::make_shared<RobotModel>();
    QuadrupedController quad;
    if (failed(model_from_urdf_file(quadruped_urdf, "", "", qmodel.get(), &why)) ||
        failed(QuadrupedController::configure(QuadrupedConfig{}, qmodel, &quad, &why))) {
      std::fprintf(stderr, "kiloloop_bench_core: quadruped: %s\n", why.c_str());
      return 1;
    }
    std::vector<QuadrupedInput> qin(kStates);
    std::mt19937 rng(kSeed);
    std::normal_distribution<double> noise(0.0, 1.0);
    for (auto& in : qin) {
      for (int leg = 0; leg < 4; ++leg)
        in.q.segment<3>(3 * leg) = Eigen::Vector3d(0.0, 0.9, -1.8) + 0.02 * Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
      for (int j = 0; j < 12; ++j) in.qd[j] = 0.2 * noise(rng);
      in.gyro = 0.02 * Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
      in.accel = Eigen::Vector3d(0, 0, 9.81) + 0.05 * Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
      in.gait = Gait::kTrot;
      in.velocity_command << 0.5, 0.0, 0.0;
    }
    QuadrupedOutput qout;
    long tick = 0;
    results.push_back(run_pair("quadruped.step", [&](int i) {
      QuadrupedInput& in = qin[i];
      in.t = in.stamp = 0.001 * static_cast<double>(tick++);
      return !failed(quad.step(in, qout));
    }, nullptr, [](int) { return true; }, n));
  }

  // A failing call returns early, so its timing would flatter us: refuse to report it.
  for (const Result& r : results) {
    for (const Side* side : {&r.ours, &r.raw}) {
      if (side->failures > 0) {
        std::fprintf(stderr, "kiloloop_bench_core: %s failed %zu of %ld calls\n",
                     side->name.c_str(), side->failures, n);
        return 1;
      }
    }
  }
  if (json) print_json(results, n, overhead);
  else print_table(results, n, overhead);
  return 0;
}
