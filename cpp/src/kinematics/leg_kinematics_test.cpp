#include "kiloloop/kinematics/leg_kinematics.hpp"

#include <random>

#include <gtest/gtest.h>
#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/jntarray.hpp>

#include "alloc_counter.hpp"
#include "kiloloop/urdf/urdf_loader.hpp"

namespace kiloloop {
namespace {

const char* kFeet[4] = {"FL_foot", "FR_foot", "RL_foot", "RR_foot"};

RobotModel quadruped() {
  RobotModel model;
  std::string why;
  EXPECT_EQ(model_from_urdf_file(std::string(KILOLOOP_MODELS_DIR) + "/quadruped/quadruped.urdf", "", "",
                                 &model, &why),
            Status::kOk)
      << why;
  return model;
}

// The closed form agrees with KDL's chain FK from the same URDF, and the Jacobian with its
// finite difference, on random configurations of every leg.
TEST(LegKinematics, MatchesKdlAndFiniteDifferences) {
  const RobotModel model = quadruped();
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (const char* foot : kFeet) {
    LegGeometry g;
    std::string why;
    ASSERT_EQ(leg_geometry_from_model(model, "trunk", foot, &g, &why), Status::kOk) << why;
    const LegKinematics leg(g);
    KDL::Chain chain;
    ASSERT_TRUE(model.tree().getChain("trunk", foot, chain));
    KDL::ChainFkSolverPos_recursive fk(chain);
    KDL::JntArray qk(3);
    for (int k = 0; k < 100; ++k) {
      const Eigen::Vector3d q(0.5 * u(rng), 0.9 + u(rng), -1.6 + 0.8 * u(rng));
      for (int j = 0; j < 3; ++j) qk(j) = q[j];
      KDL::Frame T;
      fk.JntToCart(qk, T);
      const Eigen::Vector3d p = leg.foot_position(q);
      EXPECT_LT((p - Eigen::Vector3d(T.p.x(), T.p.y(), T.p.z())).norm(), 1e-12) << foot;
      const Eigen::Matrix3d J = leg.jacobian(q);
      for (int j = 0; j < 3; ++j) {
        Eigen::Vector3d qh = q;
        qh[j] += 1e-7;
        EXPECT_LT(((leg.foot_position(qh) - p) / 1e-7 - J.col(j)).norm(), 1e-5) << foot;
      }
    }
  }
}

TEST(LegKinematics, InverseRoundTripsAndReportsUnreachable) {
  const RobotModel model = quadruped();
  LegGeometry g;
  std::string why;
  ASSERT_EQ(leg_geometry_from_model(model, "trunk", "RR_foot", &g, &why), Status::kOk) << why;
  const LegKinematics leg(g);
  std::mt19937 rng(23);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int k = 0; k < 500; ++k) {
    const Eigen::Vector3d q(0.6 * u(rng), 0.9 + 0.8 * u(rng), -1.6 + 0.9 * u(rng));
    Eigen::Vector3d sol(9, 9, 9);
    ASSERT_EQ(leg.inverse(leg.foot_position(q), sol), Status::kOk) << q.transpose();
    EXPECT_LT((sol - q).norm(), 1e-9) << q.transpose();
  }
  Eigen::Vector3d keep(0.1, 0.2, -0.3);
  EXPECT_EQ(leg.inverse(g.abd_origin + Eigen::Vector3d(0, 0, -2.0), keep), Status::kUnreachable);
  EXPECT_EQ(keep, Eigen::Vector3d(0.1, 0.2, -0.3));  // untouched on failure
  testing::AllocationScope scope;
  Eigen::Vector3d q(0, 0.9, -1.8);
  for (int k = 0; k < 10000; ++k) leg.inverse(leg.foot_position(q), q);
  EXPECT_EQ(scope.count(), 0u);
}

TEST(LegKinematics, RejectsAnArmChain) {
  RobotModel ur5;
  std::string why;
  ASSERT_EQ(model_from_urdf_file(std::string(KILOLOOP_MODELS_DIR) + "/ur5/ur5.urdf", "", "", &ur5, &why),
            Status::kOk);
  LegGeometry g;
  EXPECT_EQ(leg_geometry_from_model(ur5, "base_link", "tool0", &g, &why), Status::kModelError);
  EXPECT_NE(why.find("tool0"), std::string::npos);
}

}  // namespace
}  // namespace kiloloop
