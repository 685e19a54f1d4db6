#pragma once
// RobotModel from a Denavit-Hartenberg table: the firmware path that needs no XML parser.
// Standard DH (Spong/Siciliano):   T_{i-1,i} = Rz(theta_i) Tz(d_i) Tx(a_i) Rx(alpha_i)
// Modified DH (Craig 1989):        T_{i-1,i} = Rx(alpha_{i-1}) Tx(a_{i-1}) Rz(theta_i) Tz(d_i)
// theta_i = q_i + theta_offset_i for revolute joints; d_i = q_i + d_offset for prismatic ones.
#include <string>
#include <vector>

#include <Eigen/Core>

#include "kiloloop/model/robot_model.hpp"

namespace kiloloop {

enum class DhConvention { kStandard, kModified };

struct DhLink {
  // Geometry. In the modified convention a and alpha are a_{i-1}, alpha_{i-1} (Craig's table).
  double a = 0.0;             // [m]
  double alpha = 0.0;         // [rad]
  double d = 0.0;             // [m]  (offset for a prismatic joint)
  double theta = 0.0;         // [rad] (offset for a revolute joint)
  bool prismatic = false;
  // Dynamics, expressed in link frame i (the DH frame attached to this link).
  double mass = 0.0;                                  // [kg]
  Eigen::Vector3d com = Eigen::Vector3d::Zero();      // [m] centre of mass in frame i
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();  // [kg m^2] about the CoM, axes of frame i
  JointLimit limit;
  std::string name;  // joint name; "joint<i+1>" when empty
};

// Builds a serial chain "base" -> "tool". Fails on a non-symmetric or negative inertia.
Status model_from_dh(const std::vector<DhLink>& links, DhConvention convention, RobotModel* out,
                     std::string* why);

}  // namespace kiloloop
