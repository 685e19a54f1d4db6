// The UR closed form on UR-style arms written as the real ur_description packages write them
// (not kiloloop's own DH-shaped frames): the ROS-Industrial UR10 (zero pose pointing up, axes
// along y, ee/tool0 frames rotated) and the newer e-series layout (UR16e: base_link_inertia
// rotated by pi, joint origins rotated by pi/2, tool0 behind a flange). The geometry is
// identified from the joint axes; every solution must reach the target through the chain's own
// FK, and the configuration that generated the target must be among them.
#include <cmath>
#include "test_values.hpp"
#include <random>

#include <gtest/gtest.h>

#include "kiloloop/kinematics/arm_ik.hpp"
#include "kiloloop/kinematics/chain_kinematics.hpp"
#include "kiloloop/urdf/urdf_loader.hpp"
#include "test_models.hpp"

namespace kiloloop {
namespace {


std::string link(const char* name) {
  return std::string("<link name=\"") + name +
         "\"><inertial><mass value=\"2\"/><inertia ixx=\"0.01\" iyy=\"0.01\" izz=\"0.01\" ixy=\"0\" ixz=\"0\" iyz=\"0\"/></inertial></link>";
}

std::string joint(const char* name, const char* type, const char* parent, const char* child,
                  const char* xyz, const char* rpy, const char* axis = "0 0 1") {
  std::string j = std::string("<joint name=\"") + name + "\" type=\"" + type + "\"><parent link=\"" + parent +
                  "\"/><child link=\"" + child + "\"/><origin xyz=\"" + xyz + "\" rpy=\"" + rpy + "\"/>";
  if (std::string(type) != "fixed")
    j += std::string("<axis xyz=\"") + axis + "\"/><limit lower=\"-6.2832\" upper=\"6.2832\" velocity=\"2\" effort=\"100\"/>";
  return j + "</joint>";
}

// ROS-Industrial ur_description 1.x, ur10.urdf.xacro (also example-robot-data's ur10_robot.urdf).
std::string ur10_ros_industrial() {
  std::string x = "<robot name=\"ur10\">";
  for (const char* l : {"base_link", "shoulder_link", "upper_arm_link", "forearm_link", "wrist_1_link",
                        "wrist_2_link", "wrist_3_link"})
    x += link(l);
  x += "<link name=\"ee_link\"/><link name=\"tool0\"/><link name=\"base\"/>";
  x += joint("shoulder_pan_joint", "revolute", "base_link", "shoulder_link", "0 0 0.1273", "0 0 0");
  x += joint("shoulder_lift_joint", "revolute", "shoulder_link", "upper_arm_link", "0 0.220941 0", "0 1.570796325 0", "0 1 0");
  x += joint("elbow_joint", "revolute", "upper_arm_link", "forearm_link", "0 -0.1719 0.612", "0 0 0", "0 1 0");
  x += joint("wrist_1_joint", "revolute", "forearm_link", "wrist_1_link", "0 0 0.5723", "0 1.570796325 0", "0 1 0");
  x += joint("wrist_2_joint", "revolute", "wrist_1_link", "wrist_2_link", "0 0.1149 0", "0 0 0", "0 0 1");
  x += joint("wrist_3_joint", "revolute", "wrist_2_link", "wrist_3_link", "0 0 0.1157", "0 0 0", "0 1 0");
  x += joint("ee_fixed_joint", "fixed", "wrist_3_link", "ee_link", "0 0.0922 0", "0 0 1.570796325");
  x += joint("wrist_3_link-tool0_fixed_joint", "fixed", "wrist_3_link", "tool0", "0 0.0922 0", "-1.570796325 0 0");
  x += joint("base_link-base_fixed_joint", "fixed", "base_link", "base", "0 0 0", "0 0 -3.14159265");
  return x + "</robot>";
}

// ur_description 2.x (e-series), UR16e numbers. The package writes pi/2 as 1.570796327 (2e-10 rad
// off, so its FK deviates from exact UR geometry by ~1e-9); here pi/2 is written in full so that
// the closed form can be held to 1e-9.
std::string ur16e_current() {
  std::string x = "<robot name=\"ur16e\"><link name=\"base_link\"/>";
  for (const char* l : {"base_link_inertia", "shoulder_link", "upper_arm_link", "forearm_link", "wrist_1_link",
                        "wrist_2_link", "wrist_3_link"})
    x += link(l);
  x += "<link name=\"flange\"/><link name=\"tool0\"/>";
  x += joint("base_link-base_link_inertia", "fixed", "base_link", "base_link_inertia", "0 0 0", "0 0 3.141592653589793");
  x += joint("shoulder_pan_joint", "revolute", "base_link_inertia", "shoulder_link", "0 0 0.1807", "0 0 0");
  x += joint("shoulder_lift_joint", "revolute", "shoulder_link", "upper_arm_link", "0 0 0", "1.5707963267948966 0 0");
  x += joint("elbow_joint", "revolute", "upper_arm_link", "forearm_link", "-0.4784 0 0", "0 0 0");
  x += joint("wrist_1_joint", "revolute", "forearm_link", "wrist_1_link", "-0.36 0 0.17415", "0 0 0");
  x += joint("wrist_2_joint", "revolute", "wrist_1_link", "wrist_2_link", "0 -0.11985 -2.458e-11", "1.5707963267948966 0 0");
  x += joint("wrist_3_joint", "revolute", "wrist_2_link", "wrist_3_link", "0 0.11655 -2.390e-11",
             "1.5707963267948966 3.141592653589793 3.141592653589793");
  x += joint("wrist_3-flange", "fixed", "wrist_3_link", "flange", "0 0 0", "0 -1.5707963267948966 -1.5707963267948966");
  x += joint("flange-tool0", "fixed", "flange", "tool0", "0 0 0", "1.5707963267948966 0 1.5707963267948966");
  return x + "</robot>";
}

RobotModelPtr load_string(const std::string& xml) {
  auto model = std::make_shared<RobotModel>();
  std::string why;
  EXPECT_EQ(model_from_urdf_string(xml, "base_link", "tool0", model.get(), &why), Status::kOk) << why;
  return model;
}

struct Expected {
  double d1, a2, a3, d4, d5, d6;  // magnitudes [m]
};

class UrStyleArms : public ::testing::TestWithParam<int> {};

TEST_P(UrStyleArms, ClosedFormIsIdentifiedAndEverySolutionReachesTheTarget) {
  RobotModelPtr model;
  Expected e{};
  if (GetParam() == 0) model = testing::load_ur5(), e = {0.089159, 0.425, 0.39225, 0.10915, 0.09465, 0.0823};
  if (GetParam() == 1) model = load_string(ur10_ros_industrial()), e = {0.1273, 0.612, 0.5723, 0.163941, 0.1157, 0.0922};
  if (GetParam() == 2) model = load_string(ur16e_current()), e = {0.1807, 0.4784, 0.36, 0.17415, 0.11985, 0.11655};
  UrAnalyticIk ik;
  std::string why;
  ASSERT_EQ(UrAnalyticIk::from_model(*model, &ik, &why), Status::kOk) << why;
  const UrDhParameters& p = ik.parameters();
  EXPECT_NEAR(p.d1, e.d1, 1e-8);
  EXPECT_NEAR(std::abs(p.a2), e.a2, 1e-8);
  EXPECT_NEAR(std::abs(p.a3), e.a3, 1e-8);
  EXPECT_NEAR(std::abs(p.d4), e.d4, 1e-8);
  EXPECT_NEAR(std::abs(p.d5), e.d5, 1e-8);
  EXPECT_NEAR(std::abs(p.d6), e.d6, 1e-8);
  EXPECT_LE(ik.deviation(), 1e-10);
  ArmIk arm;
  ASSERT_EQ(ArmIk::configure(ArmIkConfig{}, *model, &arm, &why), Status::kOk) << why;
  EXPECT_STREQ(arm.solver(), "ur_analytic");
  EXPECT_EQ(arm.analytic_reason(), "");

  ChainKinematics kin;
  ASSERT_EQ(ChainKinematics::configure(*model, &kin, &why), Status::kOk) << why;
  std::mt19937 rng(83);
  std::uniform_real_distribution<double> u(-kPi, kPi);
  for (int k = 0; k < 300; ++k) {
    Eigen::Matrix<double, 6, 1> q_true, seed;
    for (int i = 0; i < 6; ++i) q_true[i] = u(rng), seed[i] = u(rng);
    Eigen::Isometry3d target;
    kin.forward(q_true, target);
    UrAnalyticIk::Solutions sols;
    int count = 0;
    ASSERT_EQ(ik.solve(target, seed, sols, &count), Status::kOk) << "seed 83 k " << k;
    double found = 1e9;
    for (int s = 0; s < count; ++s) {
      Eigen::Isometry3d T;
      kin.forward(sols.col(s), T);
      const Vector6d err = pose_error(target, T);
      EXPECT_LT(err.head<3>().norm(), 1e-9) << "seed 83 k " << k << " solution " << s;
      EXPECT_LT(err.tail<3>().norm(), 1e-9) << "seed 83 k " << k << " solution " << s;
      Eigen::Matrix<double, 6, 1> diff = sols.col(s) - q_true;
      for (int i = 0; i < 6; ++i) diff[i] = std::remainder(diff[i], 2 * kPi);
      found = std::min(found, diff.cwiseAbs().maxCoeff());
    }
    EXPECT_LT(found, 1e-7) << "seed 83 k " << k;
  }
}

INSTANTIATE_TEST_SUITE_P(Ur5Ur10Ur16e, UrStyleArms, ::testing::Values(0, 1, 2));

TEST(UrStyleArms, ANonUrChainSaysWhyTheClosedFormIsNotUsed) {
  // The UR10 with its elbow axis tilted: joints 2 and 3 are no longer parallel.
  std::string xml = ur10_ros_industrial();
  const std::string from = "<origin xyz=\"0 -0.1719 0.612\" rpy=\"0 0 0\"/>";
  const auto pos = xml.find(from);
  ASSERT_NE(pos, std::string::npos);
  xml.replace(pos, from.size(), "<origin xyz=\"0 -0.1719 0.612\" rpy=\"0.3 0 0\"/>");
  const RobotModelPtr model = load_string(xml);
  ArmIk arm;
  std::string why;
  ASSERT_EQ(ArmIk::configure(ArmIkConfig{}, *model, &arm, &why), Status::kOk) << why;
  EXPECT_STREQ(arm.solver(), "numeric");
  EXPECT_NE(arm.analytic_reason().find("joint 3 ('elbow_joint') axis not parallel to joint 2 "
                                       "('shoulder_lift_joint')"),
            std::string::npos)
      << arm.analytic_reason();
  ArmIkConfig off;
  off.use_analytic = false;
  ASSERT_EQ(ArmIk::configure(off, *testing::load_ur5(), &arm, &why), Status::kOk) << why;
  EXPECT_STREQ(arm.solver(), "numeric");
  EXPECT_NE(arm.analytic_reason().find("disabled"), std::string::npos);
}

}  // namespace
}  // namespace kiloloop
