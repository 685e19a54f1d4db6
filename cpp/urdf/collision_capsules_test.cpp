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

}  // namespace
}  // namespace kiloloop
