// StanceForceQp: the ground reaction forces that realize a trunk wrench within friction pyramids,
// normal-force bounds and the per-foot load share; allocation-free solves.
#include "kiloloop/quadruped/stance_force.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "alloc_counter.hpp"

namespace kiloloop {
namespace {

using Vector12d = Eigen::Matrix<double, 12, 1>;
using Wrench = Eigen::Matrix<double, 6, 1>;

// Feet of a 0.4 m x 0.3 m stance, 0.3 m below the CoM.
const std::array<Eigen::Vector3d, 4> kFeet{Eigen::Vector3d(0.2, 0.15, -0.3), Eigen::Vector3d(0.2, -0.15, -0.3),
                                           Eigen::Vector3d(-0.2, 0.15, -0.3),
                                           Eigen::Vector3d(-0.2, -0.15, -0.3)};
constexpr double kWeight = 17.6 * 9.81;

StanceForceQp make_qp(StanceForceConfig config = {}) {
  StanceForceQp qp;
  std::string why;
  EXPECT_EQ(StanceForceQp::configure(config, &qp, &why), Status::kOk) << why;
  return qp;
}

Wrench resultant(const Vector12d& f) {
  Wrench w = Wrench::Zero();
  for (int i = 0; i < 4; ++i) {
    w.head<3>() += f.segment<3>(3 * i);
    w.tail<3>() += kFeet[i].cross(f.segment<3>(3 * i));
  }
  return w;
}

// The former formulation, kept as the reference: H = A^T S A through Eigen's product, C zeroed
// whole each tick, all 12 forces as variables (a swing leg's fixed at zero by its bounds), always
// the dense QP. The closed-form unconstrained optimum and the structured QP over the stance legs'
// forces must give the same forces to rounding over a long random sequence (stance sets changing,
// warm starts carried over).
class ReferenceStanceForce {
 public:
  explicit ReferenceStanceForce(const StanceForceConfig& cfg) : cfg_(cfg) {
    qp::QpSettings settings;
    settings.max_iterations = cfg.max_iterations;
    std::string why;
    EXPECT_EQ(qp::DenseQpSolver::configure(12, 0, 24, settings, &solver_, &why), Status::kOk) << why;
    A_.setZero();
    for (int i = 0; i < 4; ++i) A_.block<3, 3>(0, 3 * i).setIdentity();
    f_prev_.setZero();
    C_ = Eigen::MatrixXd::Zero(24, 12);
    d_ = Eigen::VectorXd::Zero(24);
    lb_ = Eigen::VectorXd::Zero(12);
    ub_ = Eigen::VectorXd::Zero(12);
  }
  Status solve(const Wrench& wrench, const std::array<Eigen::Vector3d, 4>& feet,
               const std::array<bool, 4>& stance, const std::array<double, 4>& load,
               const Eigen::Vector3d& normal, Vector12d& f) {
    for (int i = 0; i < 4; ++i) {
      const Eigen::Vector3d& v = feet[i];
      A_.block<3, 3>(3, 3 * i) << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
    }
    const auto S = cfg_.wrench_weight.asDiagonal();
    Eigen::Matrix<double, 12, 12> H;
    H.noalias() = A_.transpose() * S * A_;
    H.diagonal().array() += cfg_.regularization + cfg_.smoothing;
    Vector12d g;
    g.noalias() = -(A_.transpose() * (S * wrench));
    g -= cfg_.smoothing * f_prev_;
    const Eigen::Vector3d n = normal.normalized();
    const Eigen::Vector3d helper = std::abs(n.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
    const Eigen::Vector3d t1 = (helper - helper.dot(n) * n).normalized(), t2 = n.cross(t1);
    int n_in = 0;
    C_.setZero();
    constexpr double kInf = std::numeric_limits<double>::infinity();
    for (int i = 0; i < 4; ++i) {
      lb_.segment<3>(3 * i).setConstant(stance[i] ? -kInf : 0.0);
      ub_.segment<3>(3 * i).setConstant(stance[i] ? kInf : 0.0);
      if (!stance[i]) continue;
      const Eigen::Vector3d rows[4] = {t1 - cfg_.mu * n, -t1 - cfg_.mu * n, t2 - cfg_.mu * n,
                                       -t2 - cfg_.mu * n};
      for (const auto& row : rows) {
        C_.block<1, 3>(n_in, 3 * i) = row.transpose();
        d_[n_in++] = 0.0;
      }
      C_.block<1, 3>(n_in, 3 * i) = -n.transpose();
      d_[n_in++] = -cfg_.fz_min;
      C_.block<1, 3>(n_in, 3 * i) = n.transpose();
      const double share = std::isfinite(load[i]) ? std::clamp(load[i], 0.0, 1.0) : 1.0;
      d_[n_in++] = cfg_.fz_min + share * (cfg_.fz_max - cfg_.fz_min);
    }
    Vector12d x;
    const Eigen::MatrixXd none_rows = Eigen::MatrixXd::Zero(0, 12);
    const Eigen::VectorXd none = Eigen::VectorXd::Zero(0);
    const qp::QpResult r = solver_.solve(H, g, none_rows, none, C_.topRows(n_in), d_.head(n_in), lb_, ub_, x);
    iterations_ = r.iterations;
    if (r.status != qp::QpStatus::kOptimal || !x.allFinite()) {
      f = f_prev_;
      return Status::kSolverFailed;
    }
    f = x;
    f_prev_ = x;
    return Status::kOk;
  }
  int iterations() const { return iterations_; }

 private:
  StanceForceConfig cfg_;
  qp::DenseQpSolver solver_;
  int iterations_ = 0;
  Eigen::Matrix<double, 6, 12> A_;
  Vector12d f_prev_;
  Eigen::MatrixXd C_;
  Eigen::VectorXd d_, lb_, ub_;
};

TEST(StanceForceQp, SameForcesAsTheProductFormulation) {
  StanceForceConfig cfg;
  cfg.wrench_weight << 1.0, 1.0, 1.0, 250.0, 120.0, 60.0;
  StanceForceQp qp = make_qp(cfg);
  ReferenceStanceForce ref(cfg);
  std::mt19937 rng(21);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int solved = 0, closed_form = 0, constrained = 0;
  double worst = 0.0;
  for (int tick = 0; tick < 3000; ++tick) {
    std::array<Eigen::Vector3d, 4> feet = kFeet;
    for (auto& p : feet) p += 0.05 * Eigen::Vector3d(u(rng), u(rng), u(rng));
    // Trot-like: a diagonal pair, sometimes all four, sometimes three.
    const int phase = (tick / 150) % 4;
    std::array<bool, 4> stance{phase != 1, phase != 0, phase != 0, phase != 1};
    if (phase == 3) stance[tick % 4] = u(rng) > 0.0;
    const std::array<double, 4> load{0.5 + 0.5 * u(rng), 1.0, 0.7, 0.5 + 0.5 * u(rng)};
    Wrench w;
    w << 20.0 * u(rng), 20.0 * u(rng), kWeight * (1.0 + 0.2 * u(rng)), 5.0 * u(rng), 5.0 * u(rng), 2.0 * u(rng);
    const Eigen::Vector3d normal = Eigen::Vector3d(0.1 * u(rng), 0.1 * u(rng), 1.0);
    Vector12d f, f_ref;
    const Status st = qp.solve(w, feet, stance, load, normal, f);
    const Status st_ref = ref.solve(w, feet, stance, load, normal, f_ref);
    ASSERT_EQ(st, st_ref) << tick;
    solved += st == Status::kOk;
    // Forces of 10-200 N: rounding of a 12x12 or 6x6 solve, far below a millinewton.
    const double error = (f - f_ref).lpNorm<Eigen::Infinity>();
    worst = std::max(worst, error);
    ASSERT_LT(error, 1e-9 * (1.0 + f_ref.lpNorm<Eigen::Infinity>())) << "tick " << tick;
    if (qp.last_closed_form()) {
      ++closed_form;
      ASSERT_EQ(ref.iterations(), 0) << tick;  // no constraint was active at the optimum
    } else {
      constrained += ref.iterations() > 0;
    }
  }
  EXPECT_GT(solved, 2900);
  // Both paths taken: the closed form where no constraint binds, the QP where one does.
  EXPECT_GT(closed_form, 1000);
  EXPECT_GT(constrained, 100);
  std::printf("closed form %d, constrained %d of 3000 ticks, largest difference %.3g N\n", closed_form,
              constrained, worst);
}

TEST(StanceForceQp, FourFeetCarryTheWeightEvenly) {
  StanceForceQp qp = make_qp();
  Wrench w;
  w << 0, 0, kWeight, 0, 0, 0;
  Vector12d f;
  ASSERT_EQ(qp.solve(w, kFeet, {true, true, true, true}, {1, 1, 1, 1}, Eigen::Vector3d::UnitZ(), f),
            Status::kOk);
  EXPECT_LT((resultant(f) - w).norm(), 0.1);
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(f[3 * i + 2], kWeight / 4, 0.5);
}

TEST(StanceForceQp, DiagonalSupportBuysTheRollMomentWithASidewaysForce) {
  // Two diagonal feet cannot produce a moment about the line through them from vertical forces;
  // with the default weights the QP still realizes the roll moment, using horizontal forces.
  StanceForceQp qp = make_qp();
  Wrench w;
  w << 0, 0, kWeight, 3.0, 0, 0;
  Vector12d f;
  ASSERT_EQ(qp.solve(w, kFeet, {true, false, false, true}, {1, 1, 1, 1}, Eigen::Vector3d::UnitZ(), f),
            Status::kOk);
  EXPECT_EQ(f.segment<3>(3).norm(), 0.0);  // swing feet carry nothing
  EXPECT_EQ(f.segment<3>(6).norm(), 0.0);
  const Wrench got = resultant(f);
  EXPECT_GT(got[3], 0.9 * 3.0);
  EXPECT_LT(got[3], 3.0 + 1e-9);
  EXPECT_GT(std::abs(got[1]), 5.0);  // the sideways force that pays for it (~ moment / height)
  // Moments weighted like forces x10 (the old default) leave most of the roll moment undone.
  StanceForceConfig light;
  light.wrench_weight << 1, 1, 1, 10, 10, 10;
  StanceForceQp qp_light = make_qp(light);
  ASSERT_EQ(qp_light.solve(w, kFeet, {true, false, false, true}, {1, 1, 1, 1}, Eigen::Vector3d::UnitZ(), f),
            Status::kOk);
  EXPECT_LT(resultant(f)[3], got[3] - 0.5);
}

TEST(StanceForceQp, LoadShareCapsTheNormalForceAndFrictionHolds) {
  StanceForceConfig config;
  StanceForceQp qp = make_qp(config);
  Wrench w;
  w << 20.0, 0, kWeight, 0, 0, 0;
  Vector12d f;
  const std::array<double, 4> load{0.1, 1.0, 1.0, 0.0};
  ASSERT_EQ(qp.solve(w, kFeet, {true, true, true, true}, load, Eigen::Vector3d::UnitZ(), f), Status::kOk);
  const double cap0 = config.fz_min + 0.1 * (config.fz_max - config.fz_min);
  EXPECT_LE(f[2], cap0 + 1e-9);
  EXPECT_LE(f[11], config.fz_min + 1e-9);  // load 0: down to the minimum normal force
  EXPECT_GE(f[11], config.fz_min - 1e-9);
  for (int i = 0; i < 4; ++i) {
    EXPECT_LE(std::abs(f[3 * i]), config.mu * f[3 * i + 2] + 1e-9);
    EXPECT_LE(std::abs(f[3 * i + 1]), config.mu * f[3 * i + 2] + 1e-9);
  }
}

TEST(StanceForceQp, SolvesAreAllocationFree) {
  StanceForceQp qp = make_qp();
  Vector12d f;
  Wrench w;
  std::size_t allocations = 0;
  for (int k = 0; k < 4000; ++k) {
    w << 5.0 * std::sin(0.01 * k), 3.0 * std::cos(0.013 * k), kWeight, 2.0 * std::sin(0.02 * k), 1.0, 0.5;
    const bool pair = (k / 300) % 2 == 0;
    const std::array<bool, 4> stance{pair || k % 300 < 30, !pair || k % 300 < 30, !pair || k % 300 < 30,
                                     pair || k % 300 < 30};
    const double ramp = std::min(1.0, (k % 300) / 30.0);
    testing::AllocationScope scope;
    const Status s = qp.solve(w, kFeet, stance, {ramp, ramp, ramp, ramp}, Eigen::Vector3d::UnitZ(), f);
    allocations += scope.count();
    ASSERT_EQ(s, Status::kOk) << "tick " << k;
    ASSERT_TRUE(f.allFinite());
  }
  EXPECT_EQ(allocations, 0u);
}

}  // namespace
}  // namespace kiloloop
