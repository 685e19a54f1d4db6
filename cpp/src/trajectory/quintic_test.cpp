#include "kiloloop/trajectory/quintic.hpp"

#include <gtest/gtest.h>

#include "alloc_counter.hpp"

namespace kiloloop {
namespace {

QuinticTrajectory three_waypoints() {
  Eigen::MatrixXd w(2, 3);
  w << 0.0, 1.0, 0.5,   //
      0.0, 0.5, 1.5;
  Eigen::VectorXd t(3);
  t << 0.0, 1.0, 3.0;
  QuinticTrajectory traj;
  std::string why;
  EXPECT_EQ(QuinticTrajectory::configure(w, t, &traj, &why), Status::kOk) << why;
  return traj;
}

TEST(Quintic, PassesThroughWaypointsAtRestAtTheEnds) {
  const QuinticTrajectory traj = three_waypoints();
  Eigen::VectorXd q(2), qd(2), qdd(2);
  traj.sample(0.0, q, qd, qdd);
  EXPECT_EQ(q, Eigen::Vector2d(0.0, 0.0));
  EXPECT_EQ(qd, Eigen::Vector2d::Zero());
  EXPECT_EQ(qdd, Eigen::Vector2d::Zero());
  traj.sample(1.0, q, qd, qdd);
  EXPECT_NEAR(q[0], 1.0, 1e-12);
  EXPECT_NEAR(q[1], 0.5, 1e-12);
  EXPECT_NEAR(qd[0], 0.0, 1e-12);  // slope changes sign: Craig's heuristic stops there
  EXPECT_NEAR(qd[1], 0.5 * (0.5 + 0.5), 1e-12);
  traj.sample(10.0, q, qd, qdd);  // after the end: hold at rest
  EXPECT_NEAR(q[0], 0.5, 1e-12);
  EXPECT_NEAR(q[1], 1.5, 1e-12);
  EXPECT_NEAR(qd.norm() + qdd.norm(), 0.0, 1e-12);
}

// Derivatives are consistent (finite differences) and continuous across the via point.
TEST(Quintic, DerivativesAreConsistentAndContinuous) {
  const QuinticTrajectory traj = three_waypoints();
  Eigen::VectorXd q0(2), qd0(2), qdd0(2), q1(2), qd1(2), qdd1(2);
  const double h = 1e-6;
  for (double t = 0.01; t < 3.0; t += 0.0137) {
    traj.sample(t, q0, qd0, qdd0);
    traj.sample(t + h, q1, qd1, qdd1);
    EXPECT_LT(((q1 - q0) / h - qd0).norm(), 1e-4) << t;
    EXPECT_LT(((qd1 - qd0) / h - qdd0).norm(), 1e-3) << t;
  }
  traj.sample(1.0 - 1e-9, q0, qd0, qdd0);
  traj.sample(1.0 + 1e-9, q1, qd1, qdd1);
  EXPECT_LT((qd1 - qd0).norm() + (qdd1 - qdd0).norm(), 1e-6);
}

TEST(Quintic, RejectsBadConfigurationAndNonFiniteTime) {
  QuinticTrajectory traj;
  std::string why;
  Eigen::MatrixXd w = Eigen::MatrixXd::Zero(2, 2);
  EXPECT_EQ(QuinticTrajectory::configure(w, Eigen::Vector2d(1.0, 1.0), &traj, &why),
            Status::kInvalidConfig);
  EXPECT_NE(why.find("increasing"), std::string::npos);
  const QuinticTrajectory good = three_waypoints();
  Eigen::VectorXd q(2), qd(2), qdd(2), bad(3);
  EXPECT_EQ(good.sample(std::numeric_limits<double>::quiet_NaN(), q, qd, qdd),
            Status::kNonFiniteReference);
  EXPECT_TRUE(q.allFinite());
  EXPECT_EQ(good.sample(0.5, bad, qd, qdd), Status::kBadSize);
}

TEST(Quintic, SamplingIsAllocationFree) {
  const QuinticTrajectory traj = three_waypoints();
  Eigen::VectorXd q(2), qd(2), qdd(2);
  testing::AllocationScope scope;
  for (int k = 0; k < 10000; ++k) traj.sample(k * 0.0003, q, qd, qdd);
  EXPECT_EQ(scope.count(), 0u);
}

}  // namespace
}  // namespace kiloloop
