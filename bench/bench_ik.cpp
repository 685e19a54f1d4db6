// kiloloop_bench_ik: position IK on seeded random reachable poses (FK of random in-limit
// configurations), each solver from the same random in-limit seed configuration, side by side
// with KDL's ChainIkSolverPos_LMA and ChainIkSolverPos_NR_JL in the same run.
//   kiloloop_bench_ik <ur5.urdf> <7dof.urdf> [--poses N] [--quick] [--json]
// Success = the returned q is within the joint limits and its pose error is <= 1e-6 m and
// <= 1e-6 rad, judged by one check for every solver (not by each solver's own status).
// Times cover the whole solve, failures included. Solvers take turns pose by pose, the order
// rotating, so that they see the same machine state.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <functional>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/chainiksolverpos_lma.hpp>
#include <kdl/chainiksolverpos_nr_jl.hpp>
#include <kdl/chainiksolvervel_pinv.hpp>

#include "alloc_counter.hpp"
#include "kiloloop/arm/cartesian_tracking.hpp"
#include "kiloloop/kinematics/arm_ik.hpp"
#include "kiloloop/trajectory/cartesian_line.hpp"
#include "kiloloop/rt/latency_stats.hpp"
#include "kiloloop/urdf/urdf_loader.hpp"

namespace {

using Clock = std::chrono::steady_clock;
using namespace kiloloop;

constexpr double kPi = 3.14159265358979323846;
constexpr double kPosTol = 1e-6, kRotTol = 1e-6;
constexpr unsigned kSeed = 20261122;

struct Problem {
  std::vector<Eigen::Isometry3d> targets;
  std::vector<Eigen::VectorXd> seeds;
};

struct SolverRun {
  std::string name;
  // Solves target from seed into q; returns nothing, success is judged outside.
  std::function<void(const Eigen::Isometry3d&, const Eigen::VectorXd&, Eigen::VectorXd&)> solve;
  LatencyStats stats;
  long success = 0, pose_ok = 0;
  std::size_t allocations = 0;
  LatencySummary summary;
  SolverRun(std::string n, decltype(solve) f, std::size_t cap)
      : name(std::move(n)), solve(std::move(f)), stats(cap) {}
};

Eigen::VectorXd random_in_limits(const RobotModel& m, std::mt19937& rng) {
  Eigen::VectorXd q(m.nq());
  for (int i = 0; i < m.nq(); ++i) {
    // Revolute joints with limits wider than a turn sample one turn: the poses repeat anyway.
    const double lo = std::max(m.lower()[i], -kPi), hi = std::min(m.upper()[i], kPi);
    q[i] = std::uniform_real_distribution<double>(lo, hi)(rng);
  }
  return q;
}

KDL::Frame to_kdl(const Eigen::Isometry3d& T) {
  KDL::Frame f;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) f.M(r, c) = T.linear()(r, c);
    f.p[r] = T.translation()[r];
  }
  return f;
}

// Radical inverse of `index` in `base` (the Halton sequence), as NumericIk's restarts use.
double halton(int index, int base) {
  double f = 1.0, r = 0.0;
  while (index > 0) {
    f /= base;
    r += f * (index % base);
    index /= base;
  }
  return r;
}

// A KDL solver given the same restart scheme as ours, so the comparison is like for like: attempts
// of `per_attempt` iterations, the first from the seed, then from Halton points over the joint
// range (capped at +-pi, the same primes), until `budget` iterations are spent. An attempt counts
// when its pose error meets the tolerances and, after shifting joints by whole turns, it is
// within the limits (KDL's LMA does not know the limits).
class KdlWithRestarts {
 public:
  using Attempt = std::function<void(const KDL::JntArray&, const KDL::Frame&, KDL::JntArray&)>;
  KdlWithRestarts(const RobotModel& m, ChainKinematics& kin, Attempt attempt, int per_attempt,
                  int budget)
      : model_(m), kin_(kin), attempt_(std::move(attempt)), attempts_(budget / per_attempt),
        in_(m.nq()), out_(m.nq()) {}

  void solve(const Eigen::Isometry3d& T, const Eigen::VectorXd& seed, Eigen::VectorXd& q) {
    static constexpr int kPrimes[] = {2, 3, 5, 7, 11, 13, 17, 19};
    const KDL::Frame target = to_kdl(T);
    const int nq = model_.nq();
    for (int a = 0; a < attempts_; ++a) {
      if (a == 0) {
        in_.data = seed;
      } else {
        for (int i = 0; i < nq; ++i) {
          const double lo = std::max(model_.lower()[i], -kPi), hi = std::min(model_.upper()[i], kPi);
          in_.data[i] = lo + halton(a, kPrimes[i % 8]) * (hi - lo);
        }
      }
      attempt_(in_, target, out_);
      q = out_.data;
      if (!q.allFinite()) continue;
      for (int i = 0; i < nq; ++i) {
        while (q[i] > model_.upper()[i] && q[i] - 2 * kPi >= model_.lower()[i]) q[i] -= 2 * kPi;
        while (q[i] < model_.lower()[i] && q[i] + 2 * kPi <= model_.upper()[i]) q[i] += 2 * kPi;
      }
      Eigen::Isometry3d F;
      kin_.forward(q, F);
      const Eigen::Matrix<double, 6, 1> e = pose_error(T, F);
      const bool within = (q.array() >= model_.lower().array()).all() &&
                          (q.array() <= model_.upper().array()).all();
      if (within && e.head<3>().norm() <= kPosTol && e.tail<3>().norm() <= kRotTol) return;
    }
  }

 private:
  const RobotModel& model_;
  ChainKinematics& kin_;  // FK scratch (its own copy)
  Attempt attempt_;
  int attempts_;
  KDL::JntArray in_, out_;
};

struct RobotReport {
  std::string robot;
  int nq = 0;
  long poses = 0;
  std::vector<std::unique_ptr<SolverRun>> solvers;
};

RobotReport bench_robot(const std::string& name, const std::string& urdf, long n) {
  RobotReport rep;
  rep.robot = name;
  auto model = std::make_shared<RobotModel>();
  std::string why;
  if (model_from_urdf_file(urdf, "", "", model.get(), &why) != Status::kOk) {
    std::fprintf(stderr, "%s: %s\n", urdf.c_str(), why.c_str());
    std::exit(2);
  }
  const int nq = model->nq();
  rep.nq = nq;
  rep.poses = n;
  ChainKinematics kin;
  ChainKinematics::configure(*model, &kin, &why);
  std::mt19937 rng(kSeed);
  Problem p;
  for (long k = 0; k < n; ++k) {
    Eigen::Isometry3d T;
    kin.forward(random_in_limits(*model, rng), T);
    p.targets.push_back(T);
    p.seeds.push_back(random_in_limits(*model, rng));
  }

  // Ours: the arm IK (closed form + refinement where it exists), and the numeric solver alone.
  auto arm = std::make_shared<ArmIk>();
  ArmIk::configure(ArmIkConfig{}, *model, arm.get(), &why);
  ArmIkConfig numeric_only;
  numeric_only.use_analytic = false;
  auto num = std::make_shared<ArmIk>();
  ArmIk::configure(numeric_only, *model, num.get(), &why);
  // KDL: tolerances set so that their own stopping test implies ours (LMA: weighted 6-norm with
  // unit weights <= eps; NR_JL: every twist component <= eps).
  const KDL::Chain& chain = model->chain();
  Eigen::Matrix<double, 6, 1> L = Eigen::Matrix<double, 6, 1>::Ones();
  auto lma = std::make_shared<KDL::ChainIkSolverPos_LMA>(chain, L, kPosTol, 500, 1e-15);
  auto fk = std::make_shared<KDL::ChainFkSolverPos_recursive>(chain);
  auto vel = std::make_shared<KDL::ChainIkSolverVel_pinv>(chain);
  KDL::JntArray qmin(nq), qmax(nq);
  qmin.data = model->lower();
  qmax.data = model->upper();
  auto nrjl = std::make_shared<KDL::ChainIkSolverPos_NR_JL>(chain, qmin, qmax, *fk, *vel, 100,
                                                             kPosTol / std::sqrt(3.0));
  auto kq_in = std::make_shared<KDL::JntArray>(nq), kq_out = std::make_shared<KDL::JntArray>(nq);

  const std::string ours = arm->has_analytic() ? "kiloloop ArmIk (analytic + LM)" : "kiloloop ArmIk (LM)";
  rep.solvers.push_back(std::make_unique<SolverRun>(
      ours, [arm](const Eigen::Isometry3d& T, const Eigen::VectorXd& s, Eigen::VectorXd& q) { arm->solve(T, s, q); }, n));
  if (arm->has_analytic()) {
    rep.solvers.push_back(std::make_unique<SolverRun>(
        "kiloloop NumericIk (LM only)",
        [num](const Eigen::Isometry3d& T, const Eigen::VectorXd& s, Eigen::VectorXd& q) { num->solve(T, s, q); }, n));
  }
  rep.solvers.push_back(std::make_unique<SolverRun>(
      "KDL ChainIkSolverPos_LMA",
      [lma, kq_in, kq_out](const Eigen::Isometry3d& T, const Eigen::VectorXd& s, Eigen::VectorXd& q) {
        kq_in->data = s;
        lma->CartToJnt(*kq_in, to_kdl(T), *kq_out);
        q = kq_out->data;
      }, n));
  rep.solvers.push_back(std::make_unique<SolverRun>(
      "KDL ChainIkSolverPos_NR_JL",
      [nrjl, fk, vel, kq_in, kq_out](const Eigen::Isometry3d& T, const Eigen::VectorXd& s, Eigen::VectorXd& q) {
        kq_in->data = s;
        nrjl->CartToJnt(*kq_in, to_kdl(T), *kq_out);
        q = kq_out->data;
      }, n));

  // The same two KDL solvers with our restart scheme (15 iterations an attempt, 500 in all).
  const ArmIkConfig ours_config;
  const int per_attempt = ours_config.numeric.restart_after, budget = ours_config.numeric.max_iterations;
  auto lma_short = std::make_shared<KDL::ChainIkSolverPos_LMA>(chain, L, kPosTol, per_attempt, 1e-15);
  auto nrjl_short = std::make_shared<KDL::ChainIkSolverPos_NR_JL>(chain, qmin, qmax, *fk, *vel, per_attempt,
                                                                   kPosTol / std::sqrt(3.0));
  auto kin_shared = std::make_shared<ChainKinematics>(kin);
  auto lma_restarts = std::make_shared<KdlWithRestarts>(
      *model, *kin_shared,
      [lma_short](const KDL::JntArray& a, const KDL::Frame& f, KDL::JntArray& b) { lma_short->CartToJnt(a, f, b); },
      per_attempt, budget);
  auto nrjl_restarts = std::make_shared<KdlWithRestarts>(
      *model, *kin_shared,
      [nrjl_short](const KDL::JntArray& a, const KDL::Frame& f, KDL::JntArray& b) { nrjl_short->CartToJnt(a, f, b); },
      per_attempt, budget);
  rep.solvers.push_back(std::make_unique<SolverRun>(
      "KDL LMA + our restarts",
      [lma_restarts, kin_shared](const Eigen::Isometry3d& T, const Eigen::VectorXd& s, Eigen::VectorXd& q) {
        lma_restarts->solve(T, s, q);
      }, n));
  rep.solvers.push_back(std::make_unique<SolverRun>(
      "KDL NR_JL + our restarts",
      [nrjl_restarts, kin_shared](const Eigen::Isometry3d& T, const Eigen::VectorXd& s, Eigen::VectorXd& q) {
        nrjl_restarts->solve(T, s, q);
      }, n));

  const int m = static_cast<int>(rep.solvers.size());
  Eigen::VectorXd q(nq);
  // Warm-up: caches and branch predictors, untimed.
  for (long k = 0; k < std::min<long>(n, 200); ++k)
    for (auto& s : rep.solvers) s->solve(p.targets[k], p.seeds[k], q);
  for (long k = 0; k < n; ++k) {
    for (int j = 0; j < m; ++j) {
      SolverRun& s = *rep.solvers[(j + k) % m];
      q.setZero();
      testing::AllocationScope scope;
      const auto t0 = Clock::now();
      s.solve(p.targets[k], p.seeds[k], q);
      const auto t1 = Clock::now();
      s.allocations += scope.count();
      s.stats.record(std::chrono::duration_cast<std::chrono::nanoseconds>(t1 - t0).count());
      Eigen::Isometry3d T;
      const bool finite = q.allFinite();
      if (finite) kin.forward(q, T);
      const Vector6d e = finite ? pose_error(p.targets[k], T) : Vector6d::Constant(1e9);
      const bool pose = e.head<3>().norm() <= kPosTol && e.tail<3>().norm() <= kRotTol;
      const bool limits = (q.array() >= model->lower().array()).all() &&
                          (q.array() <= model->upper().array()).all();
      s.pose_ok += pose;
      s.success += pose && limits;
    }
  }
  for (auto& s : rep.solvers) s->summary = s->stats.summarize();
  return rep;
}

struct StepLatency {
  std::string name;
  LatencySummary summary;
  double allocations_per_call = 0.0;
  long failures = 0;
};

// The 1 kHz path of arm-line on the UR5: CartesianLine::sample + CartesianTrackingController::step
// (differential IK + computed torque), the measured state following the reference (open loop),
// and the UR closed form alone.
std::vector<StepLatency> bench_steps(const std::string& urdf, long n) {
  auto model = std::make_shared<RobotModel>();
  std::string why;
  model_from_urdf_file(urdf, "", "", model.get(), &why);
  CartesianTrackingController c;
  CartesianTrackingController::configure(CartesianTrackingConfig{}, model, &c, &why);
  ChainKinematics kin;
  ChainKinematics::configure(*model, &kin, &why);
  Eigen::VectorXd q0(6);
  q0 << 0.0, -kPi / 2, kPi / 2, -kPi / 2, -kPi / 2, 0.0;
  Eigen::Isometry3d a, b;
  kin.forward(q0, a);
  b = a;
  b.translation() += Eigen::Vector3d(0.15, 0.2, -0.15);
  b.linear() = Eigen::AngleAxisd(0.6, Eigen::Vector3d(0, 0.6, 0.8)).toRotationMatrix() * a.linear();
  CartesianLine line;
  CartesianLine::configure(a, b, 0.0, n * 1e-3, &line, &why);
  CartesianTrackingInput in = c.make_input();
  CartesianTrackingOutput out = c.make_output();
  in.q = q0;
  std::vector<StepLatency> res;
  {
    LatencyStats stats(n);
    StepLatency r{"CartesianLine.sample + CartesianTrackingController.step", {}, 0.0, 0};
    testing::AllocationScope scope;
    for (long k = 0; k < n; ++k) {
      const auto t0 = Clock::now();
      in.t = in.stamp = k * 1e-3;
      Eigen::Isometry3d T;
      Vector6d acc;
      line.sample(in.t, T, in.twist_ref, acc);
      in.pose_ref = T.matrix();
      const Status s = c.step(in, out);
      const auto t1 = Clock::now();
      stats.record(std::chrono::duration_cast<std::chrono::nanoseconds>(t1 - t0).count());
      r.failures += failed(s);
      in.q = out.q_ref;  // the arm follows its reference
      in.qd = out.qd_ref;
    }
    r.allocations_per_call = double(scope.count()) / n;
    r.summary = stats.summarize();
    res.push_back(r);
  }
  {
    UrAnalyticIk ik;
    UrAnalyticIk::from_model(*model, &ik, &why);
    std::mt19937 rng(kSeed + 1);
    std::vector<Eigen::Isometry3d> targets;
    std::vector<Eigen::Matrix<double, 6, 1>> seeds;
    for (int k = 0; k < 1024; ++k) {
      Eigen::Isometry3d T;
      kin.forward(random_in_limits(*model, rng), T);
      targets.push_back(T);
      seeds.push_back(random_in_limits(*model, rng));
    }
    LatencyStats stats(n);
    StepLatency r{"UrAnalyticIk.solve (all solutions)", {}, 0.0, 0};
    UrAnalyticIk::Solutions sols;
    int count = 0;
    testing::AllocationScope scope;
    for (long k = 0; k < n; ++k) {
      const auto t0 = Clock::now();
      const Status s = ik.solve(targets[k % 1024], seeds[k % 1024], sols, &count);
      const auto t1 = Clock::now();
      stats.record(std::chrono::duration_cast<std::chrono::nanoseconds>(t1 - t0).count());
      r.failures += failed(s);
    }
    r.allocations_per_call = double(scope.count()) / n;
    r.summary = stats.summarize();
    res.push_back(r);
  }
  return res;
}

std::string cpu_model() {
  std::ifstream f("/proc/cpuinfo");
  for (std::string line; std::getline(f, line);)
    if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
  return "unknown";
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: %s <ur5.urdf> <7dof.urdf> [--poses N] [--quick] [--json]\n", argv[0]);
    return 2;
  }
  long n = 10000;
  bool json = false;
  for (int i = 3; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--json")) json = true;
    else if (!std::strcmp(argv[i], "--quick")) n = 1000;
    else if (!std::strcmp(argv[i], "--poses") && i + 1 < argc) n = std::atol(argv[++i]);
  }
  std::vector<RobotReport> reps;
  reps.push_back(bench_robot("ur5", argv[1], n));
  reps.push_back(bench_robot("7dof", argv[2], n));
  const std::vector<StepLatency> steps = bench_steps(argv[1], std::max(2L * n, 2000L));
  if (json) {
    std::printf("{\"cpu\": \"%s\", \"seed\": %u, \"position_tolerance\": %g, \"orientation_tolerance\": %g, \"robots\": [",
                cpu_model().c_str(), kSeed, kPosTol, kRotTol);
    for (std::size_t r = 0; r < reps.size(); ++r) {
      const RobotReport& rep = reps[r];
      std::printf("%s{\"robot\": \"%s\", \"nq\": %d, \"poses\": %ld, \"solvers\": [", r ? ", " : "",
                  rep.robot.c_str(), rep.nq, rep.poses);
      for (std::size_t j = 0; j < rep.solvers.size(); ++j) {
        const SolverRun& s = *rep.solvers[j];
        std::printf("%s{\"name\": \"%s\", \"success\": %ld, \"success_rate\": %.6f, \"pose_ok\": %ld, "
                    "\"median_us\": %.3f, \"p99_us\": %.3f, \"max_us\": %.3f, \"allocations_per_call\": %.3f}",
                    j ? ", " : "", s.name.c_str(), s.success, double(s.success) / rep.poses, s.pose_ok,
                    s.summary.median_ns * 1e-3, s.summary.p99_ns * 1e-3, s.summary.max_ns * 1e-3,
                    double(s.allocations) / rep.poses);
      }
      std::printf("]}");
    }
    std::printf("], \"step_latency\": [");
    for (std::size_t j = 0; j < steps.size(); ++j) {
      const StepLatency& st = steps[j];
      std::printf("%s{\"name\": \"%s\", \"calls\": %zu, \"median_us\": %.3f, \"p99_us\": %.3f, "
                  "\"max_us\": %.3f, \"allocations_per_call\": %.3f, \"failures\": %ld}",
                  j ? ", " : "", st.name.c_str(), st.summary.count, st.summary.median_ns * 1e-3,
                  st.summary.p99_ns * 1e-3, st.summary.max_ns * 1e-3, st.allocations_per_call, st.failures);
    }
    std::printf("]}\n");
    return 0;
  }
  std::printf("kiloloop_bench_ik: %ld random reachable poses per robot, seed %u, success at %g m / %g rad"
              " within joint limits\n", n, kSeed, kPosTol, kRotTol);
  for (const RobotReport& rep : reps) {
    std::printf("%s (%d joints)\n", rep.robot.c_str(), rep.nq);
    std::printf("  %-32s %9s %10s %10s %10s %7s\n", "solver", "success", "pose-only", "median us",
                "p99 us", "alloc");
    for (const auto& s : rep.solvers)
      std::printf("  %-32s %8.2f%% %9.2f%% %10.2f %10.2f %7.2f\n", s->name.c_str(),
                  100.0 * s->success / rep.poses, 100.0 * s->pose_ok / rep.poses,
                  s->summary.median_ns * 1e-3, s->summary.p99_ns * 1e-3,
                  double(s->allocations) / rep.poses);
  }
  std::printf("UR5 1 kHz path\n  %-56s %10s %10s %7s\n", "call", "median us", "p99 us", "alloc");
  for (const StepLatency& st : steps)
    std::printf("  %-56s %10.2f %10.2f %7.2f\n", st.name.c_str(), st.summary.median_ns * 1e-3,
                st.summary.p99_ns * 1e-3, st.allocations_per_call);
  return 0;
}
