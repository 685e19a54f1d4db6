// URDF collision primitives -> capsules: a geometry that cannot be bounded (a mesh) must fail
// loudly rather than leave its link out of the collision model.
#include "kiloloop/urdf/collision_capsules.hpp"

#include <cmath>

#include <gtest/gtest.h>

#include "kiloloop/urdf/urdf_loader.hpp"

namespace kiloloop {
namespace {

// Two-link arm; the second link's collision is GEOMETRY (substituted per test). The base has no
// <collision> at all, which is allowed.
std::string two_link_urdf(const std::string& geometry) {
  return R"(<robot name="two">
  <link name="base"/>
  <link name="upper"><inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial>
    <collision><origin xyz="0 0 0.15"/><geometry><cylinder radius="0.05" length="0.3"/></geometry></collision></link>
  <link name="fore"><inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial>
    <collision><origin xyz="0 0 0.1"/><geometry>)" +
         geometry + R"(</geometry></collision></link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="upper"/>
    <axis xyz="0 1 0"/><limit lower="-3" upper="3" velocity="2" effort="50"/></joint>
  <joint name="j2" type="revolute"><parent link="upper"/><child link="fore"/>
    <origin xyz="0 0 0.3"/><axis xyz="0 1 0"/><limit lower="-3" upper="3" velocity="2" effort="50"/></joint>
</robot>)";
}

Status load(const std::string& geometry, std::vector<LinkCapsule>* caps, std::string* why) {
  const std::string xml = two_link_urdf(geometry);
  RobotModel model;
  const Status s = model_from_urdf_string(xml, "base", "fore", &model, why);
  EXPECT_EQ(s, Status::kOk) << *why;
  return capsules_from_urdf_string(xml, model, caps, why);
}

TEST(CollisionCapsules, PrimitivesBecomeCapsulesAndALinkWithoutCollisionIsSkipped) {
  std::vector<LinkCapsule> caps;
  std::string why;
  ASSERT_EQ(load(R"(<box size="0.04 0.06 0.2"/>)", &caps, &why), Status::kOk) << why;
  ASSERT_EQ(caps.size(), 2u);  // base has none; upper and fore one each
  EXPECT_EQ(caps[0].link, "upper");
  EXPECT_EQ(caps[1].link, "fore");
  EXPECT_NEAR((caps[1].b - caps[1].a).norm(), 0.2, 1e-12);  // along the box's longest side
  EXPECT_NEAR(caps[1].radius, std::sqrt(0.02 * 0.02 + 0.03 * 0.03), 1e-12);
}

TEST(CollisionCapsules, AMeshCollisionFailsNamingTheLinkAndTheGeometry) {
  std::vector<LinkCapsule> caps(3);  // stale content must not survive a failure
  std::string why;
  EXPECT_EQ(load(R"(<mesh filename="package://two/fore.stl"/>)", &caps, &why), Status::kModelError);
  EXPECT_NE(why.find("'fore'"), std::string::npos) << why;
  EXPECT_NE(why.find("mesh"), std::string::npos) << why;
  EXPECT_TRUE(caps.empty());
}

TEST(CollisionCapsules, AMeshUsesTheCapsulesGivenForItsLinkInThatLinksFrame) {
  const std::string xml = two_link_urdf(R"(<mesh filename="package://two/fore.stl"/>)");
  RobotModel model;
  std::string why;
  ASSERT_EQ(model_from_urdf_string(xml, "base", "fore", &model, &why), Status::kOk) << why;
  LinkCapsule given;
  given.a = Eigen::Vector3d(0, 0, 0.02);
  given.b = Eigen::Vector3d(0, 0, 0.25);
  given.radius = 0.04;
  std::vector<LinkCapsule> caps;
  ASSERT_EQ(capsules_from_urdf_string(xml, model, {{"fore", {given, given}}}, &caps, &why), Status::kOk) << why;
  ASSERT_EQ(caps.size(), 3u);  // upper's cylinder, then the two given for fore's mesh
  EXPECT_EQ(caps[1].link, "fore");
  EXPECT_EQ(caps[2].b, given.b);
  EXPECT_EQ(caps[2].radius, 0.04);
  // Capsules given for a link that does not exist are a typo, not silently ignored.
  EXPECT_EQ(capsules_from_urdf_string(xml, model, {{"froe", {given}}}, &caps, &why), Status::kModelError);
  EXPECT_NE(why.find("'froe'"), std::string::npos) << why;
}

TEST(CollisionCapsules, AFoldedGripperMovesWithTheTipInItsFrame) {
  // A finger hangs off 'fore' on a prismatic joint locked at 0.03 m, its sphere 0.05 m further out.
  std::string xml = two_link_urdf(R"(<cylinder radius="0.03" length="0.2"/>)");
  xml.replace(xml.rfind("</robot>"), 8, R"(<link name="finger"><collision><origin xyz="0 0 0.05"/>
    <geometry><sphere radius="0.01"/></geometry></collision></link>
  <joint name="slide" type="prismatic"><parent link="fore"/><child link="finger"/>
    <origin xyz="0.1 0 0.2" rpy="0 1.5707963267948966 0"/><axis xyz="1 0 0"/>
    <limit lower="0" upper="0.04" velocity="0.1" effort="10"/></joint></robot>)");
  RobotModel model;
  std::string why;
  ASSERT_EQ(model_from_urdf_string(xml, "base", "fore", {{"slide", 0.03}}, &model, &why), Status::kOk) << why;
  std::vector<LinkCapsule> caps;
  ASSERT_EQ(capsules_from_urdf_string(xml, model, &caps, &why), Status::kOk) << why;
  ASSERT_EQ(caps.size(), 3u);
  EXPECT_EQ(caps[2].link, "fore");
  // finger frame in fore: translate (0.1, 0, 0.2), pitch +90 deg (x -> -z, z -> x), slide 0.03
  // along the finger's x, i.e. fore's -z; the sphere sits 0.05 along the finger's z = fore's x.
  EXPECT_NEAR((caps[2].a - Eigen::Vector3d(0.15, 0, 0.17)).norm(), 0.0, 1e-12) << caps[2].a.transpose();
  EXPECT_EQ(caps[2].radius, 0.01);
}

}  // namespace
}  // namespace kiloloop
