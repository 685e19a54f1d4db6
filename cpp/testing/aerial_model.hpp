#pragma once
// The aerial manipulator of models/aerial_manipulator/, loaded as the arm chain (body -> ee_link)
// the AerialController and FloatingBaseRne expect; and test multirotors written here: a body whose
// centre of mass is away from its link origin, an arm of any number of pitch joints (0: none),
// rotors on a ring (optionally tilted).
#include <cmath>
#include <memory>
#include <sstream>
#include <string>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "kiloloop/aerial/rotor_allocation.hpp"
#include "kiloloop/urdf/urdf_loader.hpp"

namespace kiloloop::testing {

inline RobotModelPtr load_aerial() {
  auto model = std::make_shared<RobotModel>();
  std::string why;
  const Status s = model_from_urdf_file(
      std::string(KILOLOOP_MODELS_DIR) + "/aerial_manipulator/aerial_manipulator.urdf", "",
      "ee_link", model.get(), &why);
  EXPECT_EQ(s, Status::kOk) << why;
  return model;
}

// A 1.2 kg body with its CoM at `com` (base_link frame) and an arm of `joints` pitch joints
// (0.1 kg links of 0.16 m, 2 N m) mounted 4 cm ahead of the origin, ending at ee_link.
inline std::string multirotor_urdf(int joints, const Eigen::Vector3d& com) {
  std::ostringstream u;
  u << "<robot name='test_multirotor'><link name='base_link'><inertial><origin xyz='" << com.x()
    << " " << com.y() << " " << com.z() << "'/><mass value='1.2'/>"
    << "<inertia ixx='0.012' ixy='0' ixz='0' iyy='0.013' iyz='0' izz='0.022'/></inertial></link>";
  std::string parent = "base_link";
  for (int j = 0; j < joints; ++j) {
    const std::string link = "arm_link" + std::to_string(j + 1);
    u << "<joint name='arm_joint" << j + 1 << "' type='revolute'><parent link='" << parent
      << "'/><child link='" << link << "'/><origin xyz='" << (j == 0 ? 0.04 : 0.0) << " 0 "
      << (j == 0 ? -0.05 : -0.16) << "'/><axis xyz='0 1 0'/>"
      << "<limit lower='-2' upper='2' velocity='6' effort='2'/></joint>"
      << "<link name='" << link << "'><inertial><origin xyz='0 0 -0.08'/><mass value='0.1'/>"
      << "<inertia ixx='2.2e-4' ixy='0' ixz='0' iyy='2.2e-4' iyz='0' izz='1e-5'/></inertial>"
      << "</link>";
    parent = link;
  }
  if (joints > 0) {
    u << "<joint name='ee_fixed' type='fixed'><parent link='" << parent
      << "'/><child link='ee_link'/><origin xyz='0 0 -0.16'/></joint><link name='ee_link'>"
      << "<inertial><mass value='0.02'/><inertia ixx='3e-6' ixy='0' ixz='0' iyy='3e-6' iyz='0' "
      << "izz='3e-6'/></inertial></link>";
  }
  u << "</robot>";
  return u.str();
}

inline RobotModelPtr load_multirotor(int joints, const Eigen::Vector3d& com) {
  auto model = std::make_shared<RobotModel>();
  std::string why;
  const Status s = model_from_urdf_string(multirotor_urdf(joints, com), "",
                                          joints > 0 ? "ee_link" : "", model.get(), &why);
  EXPECT_EQ(s, Status::kOk) << why;
  return model;
}

// n rotors on a ring of radius r, alternating spin, axes tilted alternately by +-tilt [rad]
// about the radial direction, 8 N each.
inline RotorAllocationConfig ring_rotors(int n, double r = 0.3, double tilt = 0.0) {
  RotorAllocationConfig c;
  c.positions.resize(3, n);
  c.axes.resize(3, n);
  c.spin.resize(n);
  for (int i = 0; i < n; ++i) {
    const double a = 2.0 * M_PI * (i + 0.5) / n;
    const Eigen::Vector3d radial(std::cos(a), std::sin(a), 0.0);
    c.positions.col(i) = r * radial;
    c.axes.col(i) = Eigen::AngleAxisd((i % 2 ? 1.0 : -1.0) * tilt, radial) *
                    Eigen::Vector3d::UnitZ();
    c.spin[i] = i % 2 ? 1.0 : -1.0;
  }
  return c;
}

}  // namespace kiloloop::testing
