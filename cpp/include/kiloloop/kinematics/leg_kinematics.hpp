#pragma once
// Closed-form kinematics of a 3-DoF leg: hip abduction (about trunk x), hip pitch and knee
// (both about the abduction frame's y), the classic quadruped leg (MIT Cheetah, Unitree, Solo,
// ANYmal). Geometry is read from the RobotModel's KDL tree at configure, so nothing about the
// robot is hard-coded. In the abduction frame (rotated by q0 about x) the leg is planar:
//   foot = p_abd + Rx(q0) * [ x(q1, q2),  l_abd,  h_abd + z(q1, q2) ]
//   x = -l_thigh sin(q1 + a_thigh) - l_shank sin(q1 + q2 + a_shank)
//   z = -l_thigh cos(q1 + a_thigh) - l_shank cos(q1 + q2 + a_shank)
// l_abd sums every offset along the pitch axis (hip, thigh and shank offsets: they do not move
// with q1, q2); a_thigh, a_shank are the thigh's and shank's angles from straight down at q = 0
// (a knee or foot not straight below the hip). Joint axes along -x / -y flip the joint's sign.
// All vectors in the trunk frame [m]; FK, Jacobian and IK are noexcept and allocation-free.
#include <string>

#include <Eigen/Core>

#include "kiloloop/model/robot_model.hpp"
#include "kiloloop/status.hpp"

namespace kiloloop {

// Which way the knee bends. Backward: the knee sits behind the hip-foot line (Unitree); forward:
// in front of it (ANYmal's rear legs, Solo's front legs). kAuto reads it from the knee's joint
// limits (the bend the limits allow; backward when they allow both).
enum class KneeDirection { kAuto = 0, kBackward = 1, kForward = 2 };

struct LegGeometry {
  Eigen::Vector3d abd_origin = Eigen::Vector3d::Zero();  // [m] abduction axis point at the pitch joint's x, trunk frame
  double l_abd = 0.0;     // [m] signed lateral offset abduction axis -> leg plane (+ left)
  double h_abd = 0.0;     // [m] offset abduction axis -> pitch axis along the abduction frame's z
  double l_thigh = 0.0;   // [m] hip pitch axis -> knee axis, in the leg plane
  double l_shank = 0.0;   // [m] knee axis -> foot point (the foot sphere's centre), in the leg plane
  double a_thigh = 0.0;   // [rad] thigh angle from straight down at q = 0 (+ = foot towards -x)
  double a_shank = 0.0;   // [rad] shank angle from straight down at q = 0
  Eigen::Vector3d sign = Eigen::Vector3d::Ones();  // +1 / -1: joint axis along +x,+y / -x,-y
  KneeDirection knee = KneeDirection::kBackward;   // resolved (never kAuto after configure)
  Eigen::Vector3d lower = Eigen::Vector3d::Constant(-1e9);  // [rad] joint limits
  Eigen::Vector3d upper = Eigen::Vector3d::Constant(1e9);
  double length() const { return l_thigh + l_shank; }  // [m] fully stretched hip -> foot
};

// Which bends the knee's joint limits allow (bend angle beta = q2 (internal sign) + a_shank -
// a_thigh: beta < 0 backward, beta > 0 forward).
struct KneeBends {
  bool backward = false;
  bool forward = false;
};
KneeBends allowed_bends(const LegGeometry& g);

// Reads the geometry of the chain trunk -> foot; fails with the reason when the chain is not
// abduction(+-x) - pitch(+-y) - knee(+-y), or when the closed form does not reproduce KDL's
// forward kinematics. `knee` picks the bend (kAuto: from the knee limits). The foot point is
// `foot_offset` [m] in the foot link's frame (the contact sphere's centre: ANYmal's sits 23 mm
// up the shank from the link origin); it moves rigidly with the shank, so the closed form holds
// with l_shank, a_shank and l_abd measured to it. It must be finite and shorter than the shank
// (knee axis -> foot link origin).
Status leg_geometry_from_model(const RobotModel& model, const std::string& trunk,
                               const std::string& foot, LegGeometry* out, std::string* why,
                               KneeDirection knee = KneeDirection::kAuto,
                               const Eigen::Vector3d& foot_offset = Eigen::Vector3d::Zero());

class LegKinematics {
 public:
  LegKinematics() = default;
  explicit LegKinematics(const LegGeometry& g) : g_(g) {}
  const LegGeometry& geometry() const { return g_; }

  Eigen::Vector3d foot_position(const Eigen::Vector3d& q) const noexcept;  // trunk frame
  Eigen::Matrix3d jacobian(const Eigen::Vector3d& q) const noexcept;       // d foot / d q
  // What foot_and_jacobian's set of sines and cosines also gives.
  struct Trig {
    // The hip pitch and knee axes' direction in the trunk frame: (0, cos, sin) of sign[0] q[0]
    // (the abduction turns them about x).
    Eigen::Vector3d pitch_axis;
    // The set itself: cos and sin of the abduction angle sign[0] q[0] (c0, s0), of the thigh's
    // p1 = sign[1] q[1] + a_thigh (c1, s1) and of the shank's p12 = p1 + sign[2] q[2] + a_shank -
    // a_thigh (c12, s12). LegGravity's torques are read off them.
    double c0 = 1.0, s0 = 0.0, c1 = 1.0, s1 = 0.0, c12 = 1.0, s12 = 0.0;
  };
  // Both at once, equal to the two calls bit for bit: one set of the joint angles' sines and
  // cosines (the controller needs both for every leg every tick; three sin/cos pairs a set);
  // trig (optional): what else the set gives.
  void foot_and_jacobian(const Eigen::Vector3d& q, Eigen::Vector3d* foot, Eigen::Matrix3d* jacobian,
                         Trig* trig = nullptr) const noexcept;

  // The solution with the geometry's knee direction. Returns kUnreachable and leaves q untouched
  // when the point is out of reach or the solution breaks a joint limit.
  Status inverse(const Eigen::Vector3d& foot, Eigen::Vector3d& q) const noexcept;

 private:
  struct Angles {  // of the abduction (0), the thigh (1) and thigh + shank (12) in the leg plane
    double q0, p1;  // [rad] the abduction's and the thigh's angles (sign[0] q[0], sign[1] q[1] + a_thigh)
    double s0, c0, s1, c1, s12, c12;
    double z;  // [m] the foot below the abduction axis in the leg plane
  };
  // inline (defined in leg_kinematics.cpp, their only user): GCC at -O2 kept the calls
  // otherwise, about 23 a tick in the quadruped controller (foot_and_jacobian, jacobian).
  inline Angles angles(const Eigen::Vector3d& q) const noexcept;
  inline Eigen::Vector3d foot_from(const Angles& a) const noexcept;
  inline Eigen::Matrix3d jacobian_from(const Angles& a) const noexcept;

  LegGeometry g_;
};

}  // namespace kiloloop
