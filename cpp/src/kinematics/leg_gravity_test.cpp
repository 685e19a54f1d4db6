// LegGravity: the closed form over the kinematics' sines and cosines equals the Newton-Euler
// gravity pass (ChainRne, itself checked against KDL in chain_rne_test.cpp) on our quadruped's
// legs and on a leg with every centre of mass off its axes, a tilted knee frame and a massive
// fixed foot; allocation-free.
#include "kiloloop/kinematics/leg_gravity.hpp"

#include <random>

#include <gtest/gtest.h>

#include "alloc_counter.hpp"
#include "test_models.hpp"

namespace kiloloop {
namespace {

const char* kGravityFeet[4] = {"FL_foot", "FR_foot", "RL_foot", "RR_foot"};

const char* kOffAxisLeg = R"(<robot name="off_axis">
  <link name="trunk"><inertial><mass value="5"/><inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="abd" type="revolute"><parent link="trunk"/><child link="hip"/><origin xyz="0.2 0.1 0.02"/>
    <axis xyz="1 0 0"/><limit lower="-1" upper="1" effort="20" velocity="10"/></joint>
  <link name="hip"><inertial><origin xyz="0.01 0.03 -0.005"/><mass value="0.5"/><inertia ixx="1e-3" iyy="1e-3" izz="1e-3" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="pitch" type="revolute"><parent link="hip"/><child link="thigh"/><origin xyz="0 0.08 0"/>
    <axis xyz="0 1 0"/><limit lower="-3" upper="3" effort="20" velocity="10"/></joint>
  <link name="thigh"><inertial><origin xyz="0.005 0.01 -0.1"/><mass value="1.0"/><inertia ixx="1e-2" iyy="1e-2" izz="1e-3" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="knee" type="revolute"><parent link="thigh"/><child link="shank"/><origin xyz="0 0 -0.2" rpy="0 0.3 0"/>
    <axis xyz="0 1 0"/><limit lower="-2.7" upper="-0.3" effort="20" velocity="10"/></joint>
  <link name="shank"><inertial><origin xyz="0.01 -0.005 -0.09"/><mass value="0.3"/><inertia ixx="1e-3" iyy="1e-3" izz="1e-4" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="foot_fixed" type="fixed"><parent link="shank"/><child link="foot"/><origin xyz="0 0 -0.2"/></joint>
  <link name="foot"><inertial><origin xyz="0 0.002 0"/><mass value="0.05"/><inertia ixx="1e-5" iyy="1e-5" izz="1e-5" ixy="0" ixz="0" iyz="0"/></inertial></link>
</robot>)";

struct Leg {
  LegKinematics kinematics;
  LegGravity gravity;
  ChainRne rne;
};

Leg make_leg(const RobotModel& model, const char* foot) {
  Leg leg;
  LegGeometry g;
  std::string why;
  EXPECT_EQ(leg_geometry_from_model(model, "trunk", foot, &g, &why), Status::kOk) << why;
  leg.kinematics = LegKinematics(g);
  EXPECT_EQ(LegGravity::configure(model, "trunk", foot, leg.kinematics, &leg.gravity, &why), Status::kOk) << why;
  KDL::Chain chain;
  EXPECT_TRUE(model.tree().getChain("trunk", foot, chain));
  EXPECT_EQ(ChainRne::configure(chain, &leg.rne, &why), Status::kOk) << why;
  return leg;
}

void expect_newton_euler_torques(Leg& leg, int seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-3.2, 3.2);
  for (int k = 0; k < 2000; ++k) {
    const Eigen::Vector3d q(u(rng), u(rng), u(rng));
    const Eigen::Vector3d gravity = 9.81 * Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized();
    Eigen::Vector3d ref;
    leg.rne.gravity_torque(q.data(), gravity, ref.data());
    Eigen::Vector3d foot;
    Eigen::Matrix3d J;
    LegKinematics::Trig trig;
    leg.kinematics.foot_and_jacobian(q, &foot, &J, &trig);
    const Eigen::Vector3d tau = leg.gravity.torque(trig, gravity);
    EXPECT_LT((tau - ref).lpNorm<Eigen::Infinity>(), 1e-12 * (1.0 + ref.lpNorm<Eigen::Infinity>()))
        << q.transpose() << " | " << tau.transpose() << " vs " << ref.transpose();
    EXPECT_EQ(tau, leg.gravity.torque(q, gravity));
  }
}

TEST(LegGravity, EqualsTheNewtonEulerPassOnOurLegs) {
  const RobotModel model = *testing::load_quadruped();
  for (int i = 0; i < 4; ++i) {
    Leg leg = make_leg(model, kGravityFeet[i]);
    expect_newton_euler_torques(leg, 10 + i);
  }
}

TEST(LegGravity, EqualsTheNewtonEulerPassWithEveryMassOffItsAxes) {
  RobotModel model;
  std::string why;
  ASSERT_EQ(model_from_urdf_string(kOffAxisLeg, "", "", &model, &why), Status::kOk) << why;
  Leg leg = make_leg(model, "foot");
  expect_newton_euler_torques(leg, 3);
}

TEST(LegGravity, RejectsAChainThatIsNotThreeJoints) {
  const RobotModel model = *testing::load_quadruped();
  LegGravity g;
  std::string why;
  EXPECT_EQ(LegGravity::configure(model, "trunk", "trunk", LegKinematics(), &g, &why), Status::kModelError);
  EXPECT_NE(why.find("3-joint"), std::string::npos) << why;
}

TEST(LegGravity, TorquesAreAllocationFree) {
  const RobotModel model = *testing::load_quadruped();
  Leg leg = make_leg(model, "FL_foot");
  LegKinematics::Trig trig;
  Eigen::Vector3d foot, sum = Eigen::Vector3d::Zero();
  Eigen::Matrix3d J;
  leg.kinematics.foot_and_jacobian(Eigen::Vector3d(0.1, 0.8, -1.6), &foot, &J, &trig);
  testing::AllocationScope scope;
  for (int k = 0; k < 1000; ++k) sum += leg.gravity.torque(trig, Eigen::Vector3d(0, 0.01 * k, -9.81));
  EXPECT_EQ(scope.count(), 0u);
  EXPECT_TRUE(sum.allFinite());
}

}  // namespace
}  // namespace kiloloop
