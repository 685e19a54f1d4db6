// kiloloop_bench_arm: per-step latency and heap allocations of the arm toolbox's 1 kHz pieces
// (Cartesian impedance, hybrid force/position, arm supervisor, singularity monitor, trapezoid
// sampling, capsule-box collision queries) on the UR5, plus the off-line planner's time.
//   kiloloop_bench_arm <path/to/ur5.urdf> [--calls N] [--quick] [--json]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "alloc_counter.hpp"
#include "kiloloop/control/cartesian_impedance.hpp"
#include "kiloloop/control/hybrid_force_position.hpp"
#include "kiloloop/planning/rrt_connect.hpp"
#include "kiloloop/rt/latency_stats.hpp"
#include "kiloloop/safety/arm_supervisor.hpp"
#include "kiloloop/urdf/collision_capsules.hpp"
#include "kiloloop/urdf/urdf_loader.hpp"

namespace {

using Clock = std::chrono::steady_clock;
using namespace kiloloop;

constexpr int kStates = 1024;   // distinct inputs, cycled
constexpr long kWarmUp = 2000;  // untimed calls first
constexpr unsigned kSeed = 20240602;

struct Row {
  std::string name;
  LatencySummary summary;
  double allocations_per_call = 0.0;
  long failures = 0;
};

// Times `call(i)` n times one call at a time (clock reads outside the call); allocations are
// counted over all timed calls.
Row time_calls(const std::string& name, const std::function<bool(int)>& call, long n) {
  for (long i = 0; i < kWarmUp; ++i) call(static_cast<int>(i % kStates));
  LatencyStats stats(static_cast<std::size_t>(n));
  Row row{name, {}, 0.0, 0};
  testing::AllocationScope scope;
  for (long i = 0; i < n; ++i) {
    const auto t0 = Clock::now();
    const bool ok = call(static_cast<int>(i % kStates));
    const auto t1 = Clock::now();
    stats.record(std::chrono::duration_cast<std::chrono::nanoseconds>(t1 - t0).count());
    row.failures += !ok;
  }
  row.allocations_per_call = static_cast<double>(scope.count()) / static_cast<double>(n);
  row.summary = stats.summarize();
  return row;
}

Eigen::VectorXd home() { return (Eigen::VectorXd(6) << 0.0, -1.2, 1.6, -1.97, -1.57, 0.0).finished(); }

int usage(const char* why) {
  std::fprintf(stderr, "kiloloop_bench_arm: %s\nusage: kiloloop_bench_arm <ur5.urdf> [--calls N] "
               "[--quick] [--json]\n", why);
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) return usage("missing URDF path");
  const std::string urdf = argv[1];
  long n = 100000;
  bool json = false;
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--json") json = true;
    else if (a == "--quick") n = 10000;
    else if (a == "--calls" && i + 1 < argc) n = std::atol(argv[++i]);
    else return usage(("unknown argument " + a).c_str());
  }
  auto model = std::make_shared<RobotModel>();
  std::string why;
  if (failed(model_from_urdf_file(urdf, "", "", model.get(), &why))) return usage(why.c_str());

  // Inputs: states around the tool-down pose, references a little away (realistic, not trivial).
  std::mt19937 rng(kSeed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Dynamics dyn;
  Dynamics::configure(model, {0, 0, -9.81}, &dyn, &why);
  std::vector<CartesianControlInput> cin(kStates, make_cartesian_input(6));
  std::vector<SupervisorInput> sin(kStates);
  for (int k = 0; k < kStates; ++k) {
    CartesianControlInput& in = cin[k];
    for (int j = 0; j < 6; ++j) in.q[j] = home()[j] + 0.2 * u(rng), in.qd[j] = 0.3 * u(rng);
    Eigen::Matrix4d T;
    dyn.forward_kinematics(in.q, T);
    in.p_ref = T.block<3, 1>(0, 3) + 0.005 * Eigen::Vector3d(u(rng), u(rng), u(rng));
    in.R_ref = T.block<3, 3>(0, 0);
    in.t = in.stamp = k * 1e-3;
    in.wrench_ref[2] = -10.0;
    in.wrench_measured[2] = -10.0 + u(rng);
    sin[k].q = in.q;
    sin[k].qd = in.qd;
    sin[k].tau_command = Eigen::VectorXd::Constant(6, 5.0 * u(rng));
    sin[k].t = sin[k].stamp = k * 1e-3;
  }

  std::vector<Row> rows;
  {
    CartesianImpedanceController c;
    CartesianImpedanceController::configure(CartesianImpedanceConfig{}, model, &c, &why);
    CartesianControlOutput out = c.make_output();
    // Monotonic time across the cycled inputs: a stamp older than one already used is stale.
    long tick = 0;
    rows.push_back(time_calls("CartesianImpedance.step", [&](int i) {
      cin[i].t = cin[i].stamp = 1e-3 * static_cast<double>(tick++);
      return ok(c.step(cin[i], out));
    }, n));
  }
  {
    HybridForcePositionController c;
    HybridForcePositionController::configure(HybridForcePositionConfig{}, model, &c, &why);
    CartesianControlOutput out = c.make_output();
    long tick = 0;
    rows.push_back(time_calls("HybridForcePosition.step", [&](int i) {
      cin[i].t = cin[i].stamp = 1e-3 * static_cast<double>(tick++);
      return ok(c.step(cin[i], out));
    }, n));
  }
  {
    ArmSupervisor s;
    ArmSupervisor::configure(ArmSupervisorConfig{}, model, &s, &why);
    SupervisorOutput out = s.make_output();
    // Monotonic time across the cycled inputs, so that the filters see a steady 1 kHz.
    long tick = 0;
    rows.push_back(time_calls("ArmSupervisor.step (normal)", [&](int i) {
      SupervisorInput& in = sin[i];
      in.t = in.stamp = 1e-3 * static_cast<double>(tick++);
      in.qd.setZero();  // the synthetic states are not a trajectory: no limit trips
      return !failed(s.step(in, out));
    }, n));
    ArmSupervisor stopping;
    ArmSupervisor::configure(ArmSupervisorConfig{}, model, &stopping, &why);
    tick = 0;
    rows.push_back(time_calls("ArmSupervisor.step (e-stop)", [&](int i) {
      SupervisorInput& in = sin[i];
      in.t = in.stamp = 1e-3 * static_cast<double>(tick++);
      in.estop = true;
      const Status st = stopping.step(in, out);
      in.estop = false;
      return st == Status::kEmergencyStop || st == Status::kSaturated;
    }, n));
  }
  {
    SingularityMonitor mon;
    mon.configure({});
    std::vector<Eigen::MatrixXd> J(kStates, Eigen::MatrixXd(6, 6));
    for (int k = 0; k < kStates; ++k) dyn.jacobian(cin[k].q, J[k]);
    SingularityState st;
    rows.push_back(time_calls("SingularityMonitor.update", [&](int i) {
      return !failed(mon.update(J[i], 1e-3, &st));
    }, n));
  }
  {
    Eigen::MatrixXd w(6, 4);
    for (int k = 0; k < 4; ++k) w.col(k) = home() + 0.8 * Eigen::VectorXd::Random(6);
    TrapezoidTrajectory traj;
    TrapezoidTrajectory::configure(w, Eigen::VectorXd::Constant(6, 1.5), Eigen::VectorXd::Constant(6, 3.0),
                                   0.0, &traj, &why);
    Eigen::VectorXd q(6), qd(6), qdd(6);
    rows.push_back(time_calls("TrapezoidTrajectory.sample", [&](int i) {
      return ok(traj.sample(traj.end_time() * i / kStates, q, qd, qdd));
    }, n));
  }
  // The planner's collision query and the planner itself (not 1 kHz: reported for scale).
  ArmCollisionConfig ccfg;
  capsules_from_urdf_file(urdf, *model, &ccfg.capsules, &why);
  ccfg.capsules.erase(ccfg.capsules.begin());  // the fixed base
  OrientedBox box, floor;
  box.center = Eigen::Vector3d(-0.55, -0.1, 0.2);
  box.half_extents = Eigen::Vector3d(0.1, 0.1, 0.2);
  floor.center = Eigen::Vector3d(0, 0, -0.5);
  floor.half_extents = Eigen::Vector3d(5, 5, 0.5);
  ccfg.boxes = {box, floor};
  ccfg.margin = 0.02;
  ArmCollisionChecker checker;
  ArmCollisionChecker::configure(ccfg, model, &checker, &why);
  rows.push_back(time_calls("ArmCollisionChecker.clearance",
                            [&](int i) { return std::isfinite(checker.clearance(cin[i].q)); }, n));

  // RRT-Connect + shortcut + trapezoid, arm-rrt's problem, 20 seeds.
  const Eigen::VectorXd qs = (Eigen::VectorXd(6) << -1.0, -1.2, 1.6, -1.97, -1.57, 0.0).finished();
  const Eigen::VectorXd qg = (Eigen::VectorXd(6) << 1.0, -1.2, 1.6, -1.97, -1.57, 0.0).finished();
  const int seeds = n >= 100000 ? 50 : 10;
  LatencyStats plan_stats(seeds);
  std::vector<int> iterations;
  int plan_failures = 0;
  for (int seed = 1; seed <= seeds; ++seed) {
    RrtConfig rc;
    rc.seed = static_cast<std::uint64_t>(seed);
    rc.lower = Eigen::VectorXd::Constant(6, -M_PI);
    rc.upper = Eigen::VectorXd::Constant(6, M_PI);
    TrapezoidTrajectory traj;
    Eigen::MatrixXd path;
    PlanStats ps;
    const auto t0 = Clock::now();
    const Status st = plan_trajectory(checker, rc, qs, qg, model->velocity_limit() * 0.5,
                                      Eigen::VectorXd::Constant(6, 3.0), 0.0, &traj, &path, &ps, &why);
    const auto t1 = Clock::now();
    plan_stats.record(std::chrono::duration_cast<std::chrono::nanoseconds>(t1 - t0).count());
    iterations.push_back(ps.iterations);
    plan_failures += st != Status::kOk;
  }
  const LatencySummary plan = plan_stats.summarize();
  std::sort(iterations.begin(), iterations.end());

  if (json) {
    std::printf("{\"calls\": %ld, \"results\": [", n);
    for (std::size_t k = 0; k < rows.size(); ++k) {
      const Row& r = rows[k];
      std::printf("%s\n  {\"name\": \"%s\", \"median_ns\": %lld, \"p99_ns\": %lld, \"max_ns\": %lld, "
                  "\"allocations_per_call\": %g, \"failures\": %ld}", k ? "," : "", r.name.c_str(),
                  (long long)r.summary.median_ns, (long long)r.summary.p99_ns,
                  (long long)r.summary.max_ns, r.allocations_per_call, r.failures);
    }
    std::printf("],\n \"plan\": {\"problem\": \"arm-rrt\", \"seeds\": %d, \"failures\": %d, "
                "\"median_ms\": %.3f, \"p99_ms\": %.3f, \"max_ms\": %.3f, \"median_iterations\": %d, "
                "\"max_iterations\": %d}}\n", seeds, plan_failures, plan.median_ns * 1e-6,
                plan.p99_ns * 1e-6, plan.max_ns * 1e-6, iterations[iterations.size() / 2],
                iterations.back());
  } else {
    std::printf("kiloloop_bench_arm: UR5, %ld timed calls each, times in ns\n", n);
    std::printf("%-32s %8s %8s %9s %7s %5s\n", "call", "median", "p99", "max", "alloc", "fail");
    for (const Row& r : rows)
      std::printf("%-32s %8lld %8lld %9lld %7.2f %5ld\n", r.name.c_str(), (long long)r.summary.median_ns,
                  (long long)r.summary.p99_ns, (long long)r.summary.max_ns, r.allocations_per_call,
                  r.failures);
    std::printf("RRT-Connect + shortcut + trapezoid (arm-rrt problem, %d seeds): median %.2f ms, "
                "p99 %.2f ms, max %.2f ms, iterations median %d max %d, failures %d\n", seeds,
                plan.median_ns * 1e-6, plan.p99_ns * 1e-6, plan.max_ns * 1e-6,
                iterations[iterations.size() / 2], iterations.back(), plan_failures);
  }
  return 0;
}
