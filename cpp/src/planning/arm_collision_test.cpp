// The edge check of the arm collision checker is conservative: the per-joint reach bounds how far
// capsule points move, and segment_free finds an obstacle thinner than the spacing of fixed samples.
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "kiloloop/planning/arm_collision.hpp"
#include "kiloloop/planning/rrt_connect.hpp"
#include "kiloloop/urdf/collision_capsules.hpp"
#include "test_models.hpp"

namespace kiloloop {
namespace {

Eigen::VectorXd ur5_q(double pan) {
  return (Eigen::VectorXd(6) << pan, -1.2, 1.6, -1.97, -1.57, 0.0).finished();
}

ArmCollisionChecker make_checker(const RobotModelPtr& model, std::vector<LinkCapsule> caps,
                                 std::vector<OrientedBox> boxes, double margin) {
  ArmCollisionConfig cfg;
  cfg.capsules = std::move(caps);
  cfg.boxes = std::move(boxes);
  cfg.margin = margin;
  ArmCollisionChecker checker;
  std::string why;
  EXPECT_EQ(ArmCollisionChecker::configure(cfg, model, &checker, &why), Status::kOk) << why;
  return checker;
}

TEST(ArmCollision, ReachBoundsHowFarCapsuleEndsMove) {
  const RobotModelPtr model = testing::load_ur5();
  std::vector<LinkCapsule> caps;
  std::string why;
  ASSERT_EQ(capsules_from_urdf_file(testing::ur5_urdf_path(), *model, &caps, &why), Status::kOk) << why;
  ArmCollisionChecker checker = make_checker(model, caps, {}, 0.0);
  const Eigen::Index n = static_cast<Eigen::Index>(caps.size());
  Eigen::Matrix3Xd a0(3, n), b0(3, n), a1(3, n), b1(3, n);
  const std::uint64_t seed = 20261122;
  std::printf("seed %llu\n", static_cast<unsigned long long>(seed));
  SplitMix64 rng(seed);
  double worst_ratio = 0.0;  // moved distance / bound, over all trials: must stay <= 1
  for (int trial = 0; trial < 500; ++trial) {
    Eigen::VectorXd q(6), dq(6);
    for (int j = 0; j < 6; ++j) {
      q[j] = M_PI * (2.0 * rng.uniform() - 1.0);
      dq[j] = 0.3 * (2.0 * rng.uniform() - 1.0);
    }
    ASSERT_EQ(checker.capsules_at(q, a0, b0), Status::kOk);
    ASSERT_EQ(checker.capsules_at(q + dq, a1, b1), Status::kOk);
    const double bound = checker.reach().dot(dq.cwiseAbs());
    const double moved = std::fmax((a1 - a0).colwise().norm().maxCoeff(), (b1 - b0).colwise().norm().maxCoeff());
    worst_ratio = std::fmax(worst_ratio, moved / bound);
  }
  EXPECT_LE(worst_ratio, 1.0);
  EXPECT_GT(worst_ratio, 0.3) << "the bound should not be vacuous";
}

TEST(ArmCollision, SegmentFreeFindsABoxThinnerThanTheFixedSampleSpacing) {
  const RobotModelPtr model = testing::load_ur5();
  LinkCapsule tool;  // a 1 mm ball at the wrist: nothing else of the arm is modelled
  tool.link = "wrist_3_link";
  tool.radius = 0.001;
  const Eigen::VectorXd q0 = ur5_q(-0.5), q1 = ur5_q(0.5);
  const int steps = 50;  // what the old fixed 0.02 rad check sampled on this 1 rad edge
  auto q_at = [&](double s) { return Eigen::VectorXd(q0 + s * (q1 - q0)); };

  // A 1 mm plate across the wrist's path, halfway between two fixed samples.
  ArmCollisionChecker free_space = make_checker(model, {tool}, {}, 0.0);
  Eigen::Matrix3Xd pa(3, 1), pb(3, 1), pm(3, 1), unused(3, 1);
  ASSERT_EQ(free_space.capsules_at(q_at(25.0 / steps), pa, unused), Status::kOk);
  ASSERT_EQ(free_space.capsules_at(q_at(26.0 / steps), pb, unused), Status::kOk);
  ASSERT_EQ(free_space.capsules_at(q_at(25.5 / steps), pm, unused), Status::kOk);
  OrientedBox plate;
  const Eigen::Vector3d u = (pb.col(0) - pa.col(0)).normalized();
  const Eigen::Vector3d w = (Eigen::Vector3d::UnitZ() - u.z() * u).normalized();
  plate.rotation.col(0) = u;
  plate.rotation.col(1) = w.cross(u);
  plate.rotation.col(2) = w;
  plate.center = pm.col(0);
  plate.half_extents = Eigen::Vector3d(0.0005, 0.05, 0.05);
  ArmCollisionChecker checker = make_checker(model, {tool}, {plate}, 0.0);

  // The fixed samples all see clearance: the plate lies between two of them.
  for (int i = 0; i <= steps; ++i) ASSERT_GT(checker.clearance(q_at(static_cast<double>(i) / steps)), 0.0) << i;
  ASSERT_LT(checker.clearance(q_at(25.5 / steps)), 0.0);
  EXPECT_FALSE(checker.segment_free(q0, q1, 0.02));
  EXPECT_FALSE(checker.segment_free(q1, q0, 0.02));

  // Lifted 20 cm above the wrist's path, the same plate leaves the edge free.
  plate.center += 0.2 * w;
  ArmCollisionChecker lifted = make_checker(model, {tool}, {plate}, 0.0);
  const unsigned long long before = lifted.checks();
  EXPECT_TRUE(lifted.segment_free(q0, q1, 0.02));
  // Far from it the steps are max_step: the old grid's count (+1 for rounding of the running s).
  EXPECT_LE(lifted.checks() - before, static_cast<unsigned long long>(steps + 2));
}

TEST(ArmCollision, AnEdgeGrazingTheMarginIsRejectedInBoundedWork) {
  const RobotModelPtr model = testing::load_ur5();
  LinkCapsule tool;
  tool.link = "wrist_3_link";
  tool.radius = 0.001;
  ArmCollisionChecker free_space = make_checker(model, {tool}, {}, 0.0);
  Eigen::Matrix3Xd p(3, 1), unused(3, 1);
  ASSERT_EQ(free_space.capsules_at(ur5_q(0.0), p, unused), Status::kOk);
  // A box whose top is 1 um under the ball, whose height does not change with the pan angle:
  // every configuration is free, but the edge grazes the box over a long stretch.
  OrientedBox box;
  box.half_extents = Eigen::Vector3d(0.5, 0.5, 0.5);
  box.center = p.col(0) - Eigen::Vector3d(0, 0, 0.5 + 0.001 + 1e-6);
  const Eigen::VectorXd q0 = ur5_q(-0.3), q1 = ur5_q(0.3);
  for (const double tolerance : {1e-4, 1e-12}) {  // rejected by the tolerance, then by the cap
    ArmCollisionConfig cfg;
    cfg.capsules = {tool};
    cfg.boxes = {box};
    cfg.margin = 0.0;
    cfg.edge_tolerance = tolerance;
    cfg.max_edge_samples = 200;
    ArmCollisionChecker checker;
    std::string why;
    ASSERT_EQ(ArmCollisionChecker::configure(cfg, model, &checker, &why), Status::kOk) << why;
    ASSERT_TRUE(checker.is_free(ur5_q(0.0)));
    const unsigned long long before = checker.checks();
    EXPECT_FALSE(checker.segment_free(q0, q1, 0.02)) << tolerance;
    EXPECT_LE(checker.checks() - before, 200u) << tolerance;
  }
}

}  // namespace
}  // namespace kiloloop
