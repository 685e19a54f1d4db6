#include "kiloloop/urdf/urdf_loader.hpp"

#include <gtest/gtest.h>

#include "test_models.hpp"

namespace kiloloop {
namespace {

// A trunk with two legs: the root link carries most of the mass, which kdl_parser alone drops.
const char* kTrunkUrdf = R"(<robot name="trunk">
  <link name="trunk"><inertial><origin xyz="0.01 0 0"/><mass value="10"/>
    <inertia ixx="0.1" iyy="0.2" izz="0.15" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="leg_a"><inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="leg_b"><inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="hip_a" type="revolute"><parent link="trunk"/><child link="leg_a"/>
    <origin xyz="0.2 0.1 0"/><axis xyz="0 1 0"/><limit lower="-1" upper="1" velocity="10" effort="30"/></joint>
  <joint name="hip_b" type="continuous"><parent link="trunk"/><child link="leg_b"/>
    <origin xyz="-0.2 0.1 0"/><axis xyz="0 1 0"/></joint>
</robot>)";

TEST(UrdfLoader, Ur5IsASixJointChainWithLimits) {
  const RobotModelPtr model = testing::load_ur5();
  ASSERT_TRUE(model->has_chain());
  EXPECT_EQ(model->nq(), 6);
  EXPECT_EQ(model->joint_names().front(), "shoulder_pan_joint");
  EXPECT_EQ(model->joint_names().back(), "wrist_3_joint");
  EXPECT_EQ(model->root_name(), "base_link");
  EXPECT_EQ(model->tip_name(), "tool0");
  EXPECT_DOUBLE_EQ(model->effort_limit()[0], 150.0);
  EXPECT_DOUBLE_EQ(model->effort_limit()[5], 28.0);
  EXPECT_GT(model->upper()[0], 6.0);
}

TEST(UrdfLoader, RestoresRootLinkInertiaThatKdlParserDrops) {
  RobotModel model;
  std::string why;
  ASSERT_EQ(model_from_urdf_string(kTrunkUrdf, "", "", &model, &why), Status::kOk) << why;
  EXPECT_TRUE(model.root_inertia_restored());
  EXPECT_NEAR(model.total_mass(), 12.0, 1e-12);
  const auto trunk = model.tree().getSegment("trunk");
  ASSERT_NE(trunk, model.tree().getSegments().end());
  const KDL::RigidBodyInertia& I = GetTreeElementSegment(trunk->second).getInertia();
  EXPECT_DOUBLE_EQ(I.getMass(), 10.0);
  EXPECT_NEAR(I.getCOG().x(), 0.01, 1e-15);
  // A branching tree has no default chain; its joints come in KDL's order with their limits.
  EXPECT_FALSE(model.has_chain());
  EXPECT_EQ(model.nq(), 2);
  EXPECT_EQ(model.root_name(), "trunk");
}

TEST(UrdfLoader, AMasslessRootInertialIsDroppedNotRestored) {
  // As in many vendor URDFs (Kinova's 'base'): an <inertial> of mass 0 on the root link.
  std::string xml = kTrunkUrdf;
  xml.replace(xml.find(R"(<mass value="10"/>)"), 18, R"(<mass value="0"/>)");
  RobotModel model;
  std::string why;
  ASSERT_EQ(model_from_urdf_string(xml, "", "leg_a", &model, &why), Status::kOk) << why;
  EXPECT_FALSE(model.root_inertia_restored());
  EXPECT_EQ(model.tree().getRootSegment()->first, "trunk");
  EXPECT_NEAR(model.total_mass(), 2.0, 1e-12);
}

TEST(UrdfLoader, ContinuousJointHasInfiniteLimits) {
  RobotModel model;
  std::string why;
  ASSERT_EQ(model_from_urdf_string(kTrunkUrdf, "trunk", "leg_b", &model, &why), Status::kOk) << why;
  ASSERT_EQ(model.nq(), 1);
  EXPECT_TRUE(std::isinf(model.upper()[0]));
  EXPECT_TRUE(std::isinf(model.effort_limit()[0]));
}

TEST(UrdfLoader, MalformedXmlNamesTheSourceAndReason) {
  RobotModel model;
  std::string why;
  EXPECT_EQ(model_from_urdf_string("<robot name='x'><link name='a'>", "", "", &model, &why),
            Status::kModelError);
  EXPECT_NE(why.find("invalid URDF <string>"), std::string::npos) << why;
}

TEST(UrdfLoader, MissingFileIsNamed) {
  RobotModel model;
  std::string why;
  EXPECT_EQ(model_from_urdf_file("/no/such/robot.urdf", "", "", &model, &why), Status::kModelError);
  EXPECT_NE(why.find("/no/such/robot.urdf"), std::string::npos) << why;
}

TEST(UrdfLoader, UnknownTipIsNamed) {
  RobotModel model;
  std::string why;
  EXPECT_EQ(model_from_urdf_string(kTrunkUrdf, "", "nose", &model, &why), Status::kModelError);
  EXPECT_NE(why.find("'nose'"), std::string::npos) << why;
}

}  // namespace
}  // namespace kiloloop
