// Planning on the UR5 (capsules from its URDF collision cylinders) around a box that blocks the
// straight joint-space path: RRT-Connect + shortcutting + trapezoid is collision-free along the
// whole executed trajectory, within limits, deterministic for a seed.
#include <cstring>

#include <gtest/gtest.h>

#include "kiloloop/planning/rrt_connect.hpp"
#include "kiloloop/urdf/collision_capsules.hpp"
#include "test_models.hpp"

namespace kiloloop {
namespace {

struct Ur5Scene {
  RobotModelPtr model = testing::load_ur5();
  ArmCollisionChecker checker;
  Eigen::VectorXd q_start = (Eigen::VectorXd(6) << -1.0, -1.2, 1.6, -1.97, -1.57, 0.0).finished();
  Eigen::VectorXd q_goal = (Eigen::VectorXd(6) << 1.0, -1.2, 1.6, -1.97, -1.57, 0.0).finished();

  Ur5Scene() {
    ArmCollisionConfig cfg;
    std::string why;
    EXPECT_EQ(capsules_from_urdf_file(testing::ur5_urdf_path(), *model, &cfg.capsules, &why), Status::kOk)
        << why;
    // The fixed base cannot move: its capsule (which dips into the floor slab) is left out.
    cfg.capsules.erase(cfg.capsules.begin());
    OrientedBox box;  // on the floor, in front of the arm, between start and goal
    box.center = Eigen::Vector3d(-0.55, -0.1, 0.2);
    box.half_extents = Eigen::Vector3d(0.1, 0.1, 0.2);
    OrientedBox floor;
    floor.center = Eigen::Vector3d(0, 0, -0.5);
    floor.half_extents = Eigen::Vector3d(3, 3, 0.5);
    cfg.boxes = {box, floor};
    cfg.margin = 0.01;
    EXPECT_EQ(ArmCollisionChecker::configure(cfg, model, &checker, &why), Status::kOk) << why;
  }
};

RrtConfig rrt_config(std::uint64_t seed) {
  RrtConfig c;
  c.seed = seed;
  c.lower = Eigen::VectorXd::Constant(6, -M_PI);
  c.upper = Eigen::VectorXd::Constant(6, M_PI);
  return c;
}

TEST(ArmCollision, CapsulesComeFromTheUrdfCylinders) {
  Ur5Scene scene;
  std::vector<LinkCapsule> caps;
  std::string why;
  ASSERT_EQ(capsules_from_urdf_file(testing::ur5_urdf_path(), *scene.model, &caps, &why), Status::kOk);
  ASSERT_EQ(caps.size(), 7u);  // base + six links, one cylinder each
  EXPECT_EQ(caps[0].link, "base_link");
  EXPECT_EQ(caps[2].link, "upper_arm_link");
  // upper arm: radius 0.06, length 0.425 along link x around (-0.2125, 0, 0.11336)
  EXPECT_NEAR(caps[2].radius, 0.06, 1e-12);
  EXPECT_NEAR((caps[2].b - caps[2].a).norm(), 0.425, 1e-12);
  EXPECT_NEAR(std::fabs((caps[2].b - caps[2].a).x()), 0.425, 1e-9);
  EXPECT_NEAR(0.5 * (caps[2].a + caps[2].b).x(), -0.2125, 1e-12);
}

TEST(Planning, TheBoxBlocksTheStraightPathAndRrtGoesAround) {
  Ur5Scene scene;
  ArmCollisionChecker& checker = scene.checker;
  ASSERT_TRUE(checker.is_free(scene.q_start));
  ASSERT_TRUE(checker.is_free(scene.q_goal));
  ASSERT_FALSE(checker.segment_free(scene.q_start, scene.q_goal, 0.01)) << "the box must block";

  const RrtConfig cfg = rrt_config(7);
  const Eigen::VectorXd v = scene.model->velocity_limit() * 0.5, a = Eigen::VectorXd::Constant(6, 3.0);
  TrapezoidTrajectory traj;
  Eigen::MatrixXd path;
  PlanStats stats;
  std::string why;
  ASSERT_EQ(plan_trajectory(checker, cfg, scene.q_start, scene.q_goal, v, a, 0.0, &traj, &path, &stats, &why),
            Status::kOk)
      << why;
  std::printf("RRT-Connect seed 7: %d iterations, %d nodes, %d -> %d waypoints, length %.2f -> %.2f rad, "
              "%.2f s\n", stats.iterations, stats.tree_nodes, stats.raw_waypoints, stats.waypoints,
              stats.raw_length, stats.length, traj.end_time());
  EXPECT_LE(stats.length, stats.raw_length + 1e-12);
  EXPECT_EQ(path.col(0), scene.q_start);
  EXPECT_EQ(path.col(path.cols() - 1), scene.q_goal);
  // The executed trajectory, sampled at 1 kHz, keeps the margin everywhere (segment_free proves
  // whole segments, not samples) and respects the limits.
  Eigen::VectorXd q(6), qd(6), qdd(6);
  double min_clearance = INFINITY;
  for (double t = 0.0; t <= traj.end_time(); t += 1e-3) {
    traj.sample(t, q, qd, qdd);
    min_clearance = std::min(min_clearance, checker.clearance(q));
    ASSERT_TRUE(((qd.cwiseAbs() - v).array() <= 1e-9).all());
    ASSERT_TRUE(((qdd.cwiseAbs() - a).array() <= 1e-9).all());
  }
  EXPECT_GT(min_clearance, 0.0);
  traj.sample(traj.end_time() + 1.0, q, qd, qdd);
  EXPECT_LT((q - scene.q_goal).cwiseAbs().maxCoeff(), 1e-9);
}

TEST(Planning, SameSeedSamePathOtherSeedsAlsoSucceed) {
  Ur5Scene s1, s2;
  Eigen::MatrixXd p1, p2;
  PlanStats st;
  std::string why;
  ASSERT_EQ(plan_rrt_connect(s1.checker, rrt_config(3), s1.q_start, s1.q_goal, &p1, &st, &why), Status::kOk);
  ASSERT_EQ(plan_rrt_connect(s2.checker, rrt_config(3), s2.q_start, s2.q_goal, &p2, &st, &why), Status::kOk);
  ASSERT_EQ(p1.cols(), p2.cols());
  EXPECT_EQ(std::memcmp(p1.data(), p2.data(), sizeof(double) * p1.size()), 0);
  for (std::uint64_t seed : {11u, 12u, 13u}) {
    Eigen::MatrixXd p;
    EXPECT_EQ(plan_rrt_connect(s1.checker, rrt_config(seed), s1.q_start, s1.q_goal, &p, &st, &why),
              Status::kOk) << "seed " << seed;
    for (Eigen::Index k = 0; k + 1 < p.cols(); ++k)
      EXPECT_TRUE(s1.checker.segment_free(p.col(k), p.col(k + 1), 0.02)) << "seed " << seed;
  }
}

TEST(Planning, ReportsCollidingEndsAndTheIterationCap) {
  Ur5Scene scene;
  Eigen::MatrixXd path;
  PlanStats st;
  std::string why;
  Eigen::VectorXd inside = scene.q_start;
  inside << 0.0, -1.2, 1.6, -1.97, -1.57, 0.0;  // the wrist in the box
  ASSERT_FALSE(scene.checker.is_free(inside));
  EXPECT_EQ(plan_rrt_connect(scene.checker, rrt_config(1), scene.q_start, inside, &path, &st, &why),
            Status::kInfeasible);
  RrtConfig tiny = rrt_config(1);
  tiny.max_iterations = 2;
  EXPECT_EQ(plan_rrt_connect(scene.checker, tiny, scene.q_start, scene.q_goal, &path, &st, &why),
            Status::kIterationLimit);
  EXPECT_EQ(st.iterations, 2);
  RrtConfig bad = rrt_config(1);
  bad.extend_step = -1.0;
  EXPECT_EQ(plan_rrt_connect(scene.checker, bad, scene.q_start, scene.q_goal, &path, &st, &why),
            Status::kInvalidConfig);
}

}  // namespace
}  // namespace kiloloop
