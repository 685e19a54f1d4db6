// Trapezoid: limits respected, joints synchronized, continuity of position and velocity, the
// minimum-time profile of the slowest joint, allocation-free sampling.
#include "kiloloop/trajectory/trapezoid.hpp"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "alloc_counter.hpp"

namespace kiloloop {
namespace {

TEST(Trapezoid, SingleJointHitsTheTextbookTimes) {
  TrapezoidTrajectory traj;
  std::string why;
  Eigen::MatrixXd w(1, 2);
  w << 0.0, 2.0;  // d = 2 with v = 1, a = 2: 0.5 s ramps, 1.5 s cruise -> 2.5 s
  ASSERT_EQ(TrapezoidTrajectory::configure(w, Eigen::VectorXd::Constant(1, 1.0),
                                           Eigen::VectorXd::Constant(1, 2.0), 0.0, &traj, &why),
            Status::kOk);
  EXPECT_NEAR(traj.end_time(), 2.5, 1e-12);
  Eigen::VectorXd q(1), qd(1), qdd(1);
  traj.sample(0.25, q, qd, qdd);
  EXPECT_NEAR(q[0], 0.0625, 1e-12);
  EXPECT_NEAR(qd[0], 0.5, 1e-12);
  traj.sample(1.25, q, qd, qdd);
  EXPECT_NEAR(q[0], 1.0, 1e-12);
  EXPECT_NEAR(qd[0], 1.0, 1e-12);
  EXPECT_EQ(qdd[0], 0.0);
  // Triangular: d = 0.5, a = 2 never reaches v = 1: T = 2 sqrt(d / a) = 1.
  w << 0.0, -0.5;
  ASSERT_EQ(TrapezoidTrajectory::configure(w, Eigen::VectorXd::Constant(1, 1.0),
                                           Eigen::VectorXd::Constant(1, 2.0), 1.0, &traj, &why),
            Status::kOk);
  EXPECT_NEAR(traj.end_time(), 2.0, 1e-12);
  traj.sample(1.5, q, qd, qdd);
  EXPECT_NEAR(q[0], -0.25, 1e-12);
  EXPECT_NEAR(qd[0], -1.0, 1e-12);
}

TEST(Trapezoid, RandomWaypointsStayWithinLimitsAndArriveTogether) {
  const unsigned seed = 31;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-2.0, 2.0), lim(0.5, 3.0);
  for (int trial = 0; trial < 20; ++trial) {
    const int n = 6, m = 4;
    Eigen::MatrixXd w(n, m);
    Eigen::VectorXd v(n), a(n);
    for (int j = 0; j < n; ++j) {
      for (int k = 0; k < m; ++k) w(j, k) = u(rng);
      v[j] = lim(rng);
      a[j] = lim(rng);
    }
    TrapezoidTrajectory traj;
    std::string why;
    ASSERT_EQ(TrapezoidTrajectory::configure(w, v, a, 0.0, &traj, &why), Status::kOk) << why;
    Eigen::VectorXd q(n), qd(n), qdd(n), q_prev(n), qd_prev(n);
    // Waypoints are reached exactly and at rest.
    for (int k = 0; k < m; ++k) {
      traj.sample(traj.times()[k], q, qd, qdd);
      EXPECT_LT((q - w.col(k)).cwiseAbs().maxCoeff(), 1e-9) << "seed " << seed << " trial " << trial;
      EXPECT_LT(qd.cwiseAbs().maxCoeff(), 1e-9);
    }
    const double dt = 1e-4;
    traj.sample(0.0, q_prev, qd_prev, qdd);
    for (double t = dt; t <= traj.end_time() + 0.01; t += dt) {
      traj.sample(t, q, qd, qdd);
      ASSERT_TRUE(((qd.cwiseAbs() - v).array() <= 1e-9).all()) << "seed " << seed << " t " << t;
      ASSERT_TRUE(((qdd.cwiseAbs() - a).array() <= 1e-9).all());
      // Continuity: position steps are bounded by v dt, velocity steps by a dt.
      ASSERT_TRUE(((q - q_prev).cwiseAbs().array() <= v.array() * dt + 1e-9).all());
      ASSERT_TRUE(((qd - qd_prev).cwiseAbs().array() <= a.array() * dt + 1e-9).all());
      q_prev = q;
      qd_prev = qd;
    }
    // Synchronized: every joint moves until the segment ends, on the straight joint-space line.
    for (int k = 0; k + 1 < m; ++k) {
      const Eigen::VectorXd delta = w.col(k + 1) - w.col(k);
      for (double f : {0.1, 0.5, 0.999}) {
        traj.sample(traj.times()[k] + f * (traj.times()[k + 1] - traj.times()[k]), q, qd, qdd);
        const Eigen::VectorXd rel = q - w.col(k);
        const double s = rel.dot(delta) / delta.squaredNorm();
        EXPECT_GT(s, 0.0);
        EXPECT_LT((rel - s * delta).norm(), 1e-9) << "seed " << seed << " off the segment";
        for (int j = 0; j < n; ++j) EXPECT_GT(std::fabs(qd[j]), 0.0);
      }
      // And the segment takes no longer than needed: some joint reaches a limit.
      double peak_ratio = 0.0;
      for (double t = traj.times()[k]; t < traj.times()[k + 1]; t += 1e-3) {
        traj.sample(t, q, qd, qdd);
        peak_ratio = std::max({peak_ratio, (qd.cwiseAbs().cwiseQuotient(v)).maxCoeff(),
                               (qdd.cwiseAbs().cwiseQuotient(a)).maxCoeff()});
      }
      EXPECT_GT(peak_ratio, 0.99);
    }
  }
}

TEST(Trapezoid, RepeatedWaypointsGiveZeroLengthSegments) {
  Eigen::MatrixXd w(2, 4);
  w << 0.0, 1.0, 1.0, 1.0,
       0.0, -1.0, -1.0, -1.0;  // the last two segments do not move
  TrapezoidTrajectory traj;
  std::string why;
  ASSERT_EQ(TrapezoidTrajectory::configure(w, Eigen::VectorXd::Ones(2), Eigen::VectorXd::Ones(2), 0.0,
                                           &traj, &why),
            Status::kOk);
  EXPECT_NEAR(traj.end_time(), 2.0, 1e-12);  // triangular, d = 1, a = 1: 2 sqrt(1)
  EXPECT_EQ(traj.times()[1], traj.times()[3]);
  Eigen::VectorXd q(2), qd(2), qdd(2);
  for (double t : {1.999, 2.0, 2.5}) {
    ASSERT_EQ(traj.sample(t, q, qd, qdd), Status::kOk);
    EXPECT_TRUE(q.allFinite() && qd.allFinite() && qdd.allFinite());
  }
  EXPECT_EQ(q, w.col(3));
  EXPECT_EQ(qd, Eigen::VectorXd::Zero(2));
}

TEST(Trapezoid, RejectsBadSettingsAndSamplesWithoutAllocating) {
  TrapezoidTrajectory traj;
  std::string why;
  Eigen::MatrixXd w = Eigen::MatrixXd::Zero(2, 3);
  w(0, 1) = 1.0;
  EXPECT_EQ(TrapezoidTrajectory::configure(w, Eigen::VectorXd::Ones(2), Eigen::VectorXd::Zero(2), 0.0,
                                           &traj, &why),
            Status::kInvalidConfig);
  EXPECT_EQ(TrapezoidTrajectory::configure(w, Eigen::VectorXd::Ones(3), Eigen::VectorXd::Ones(2), 0.0,
                                           &traj, &why),
            Status::kInvalidConfig);
  ASSERT_EQ(TrapezoidTrajectory::configure(w, Eigen::VectorXd::Ones(2), Eigen::VectorXd::Ones(2), 0.0,
                                           &traj, &why),
            Status::kOk);
  Eigen::VectorXd q(2), qd(2), qdd(2);
  EXPECT_EQ(traj.sample(std::nan(""), q, qd, qdd), Status::kNonFiniteReference);
  EXPECT_TRUE(q.allFinite());
  Eigen::VectorXd small(1);
  EXPECT_EQ(traj.sample(0.1, small, qd, qdd), Status::kBadSize);
  testing::AllocationScope scope;
  double sum = 0.0;
  for (int k = 0; k < 5000; ++k) {
    traj.sample(k * 1e-3, q, qd, qdd);
    sum += q[0];
  }
  EXPECT_EQ(scope.count(), 0u);
  EXPECT_TRUE(std::isfinite(sum));
}

}  // namespace
}  // namespace kiloloop
