#pragma once
// Closed-form kinematics of a 3-DoF leg: hip abduction (about trunk x), hip pitch and knee
// (both about y), the classic quadruped leg (MIT Cheetah, Unitree). Geometry is read from the
// RobotModel's KDL tree at configure, so nothing about the robot is hard-coded:
//   foot = p_abd + Rx(q0) * ( [0, l_abd, 0] + Ry(q1) * ( [0, 0, -l_thigh] + Ry(q2) [0, 0, -l_shank] ) )
// All vectors in the trunk frame [m]; FK, Jacobian and IK are noexcept and allocation-free.
#include <string>

#include <Eigen/Core>

#include "kiloloop/model/robot_model.hpp"
#include "kiloloop/status.hpp"

namespace kiloloop {

struct LegGeometry {
  Eigen::Vector3d abd_origin = Eigen::Vector3d::Zero();  // [m] hip abduction axis point, trunk frame
  double l_abd = 0.0;     // [m] signed lateral offset abduction axis -> leg plane (+ left)
  double l_thigh = 0.0;   // [m] hip pitch axis -> knee axis
  double l_shank = 0.0;   // [m] knee axis -> foot point
  Eigen::Vector3d lower = Eigen::Vector3d::Constant(-1e9);  // [rad] joint limits
  Eigen::Vector3d upper = Eigen::Vector3d::Constant(1e9);
};

// Reads the geometry of the chain trunk -> foot; fails with the reason when the chain is not
// abduction(x) - pitch(y) - knee(y) with the knee and the foot straight below at q = 0.
Status leg_geometry_from_model(const RobotModel& model, const std::string& trunk,
                               const std::string& foot, LegGeometry* out, std::string* why);

class LegKinematics {
 public:
  LegKinematics() = default;
  explicit LegKinematics(const LegGeometry& g) : g_(g) {}
  const LegGeometry& geometry() const { return g_; }

  Eigen::Vector3d foot_position(const Eigen::Vector3d& q) const noexcept;  // trunk frame
  Eigen::Matrix3d jacobian(const Eigen::Vector3d& q) const noexcept;       // d foot / d q

  // Knee-backward solution (knee angle <= 0, as in the standing pose). Returns kUnreachable and
  // leaves q untouched when the point is out of reach or the solution breaks a joint limit.
  Status inverse(const Eigen::Vector3d& foot, Eigen::Vector3d& q) const noexcept;

 private:
  LegGeometry g_;
};

}  // namespace kiloloop
