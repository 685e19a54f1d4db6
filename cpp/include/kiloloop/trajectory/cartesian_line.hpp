#pragma once
// Cartesian straight line with slerp orientation (Corke's `ctraj`): the position moves along the
// segment start -> end and the orientation rotates about one fixed axis (the shortest rotation
// R_start^T R_end), both with the same quintic time scaling s(t) = 10 u^3 - 15 u^4 + 6 u^5,
// u = (t - t0) / duration, so the motion starts and ends at rest with zero acceleration.
//   p(t) = p0 + s (p1 - p0),   R(t) = R0 Exp(s w),   w = Log(R0^T R1)  (|w| <= pi)
//   v = s' (p1 - p0),          omega = s' R0 w        (root frame; the axis R0 w is fixed)
// Sampling is noexcept and allocation-free; before t0 it holds the start, after the end the end.
#include <string>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "kiloloop/kinematics/chain_kinematics.hpp"
#include "kiloloop/status.hpp"

namespace kiloloop {

class CartesianLine {
 public:
  CartesianLine() = default;
  // start, end: T_root_tip [m]; t0 [s]; duration > 0 [s].
  static Status configure(const Eigen::Isometry3d& start, const Eigen::Isometry3d& end, double t0,
                          double duration, CartesianLine* out, std::string* why);

  double start_time() const { return t0_; }
  double end_time() const { return t0_ + duration_; }
  double length() const { return (p1_ - p0_).norm(); }  // [m]
  double angle() const { return w_.norm(); }             // [rad]

  // Pose, twist [v; omega] [m/s; rad/s] and its derivative [m/s^2; rad/s^2] at t [s], all in
  // the root frame. A non-finite t returns kNonFiniteReference with the start at rest.
  Status sample(double t, Eigen::Isometry3d& pose, Vector6d& twist, Vector6d& accel) const noexcept;

 private:
  Eigen::Vector3d p0_ = Eigen::Vector3d::Zero(), p1_ = Eigen::Vector3d::Zero();
  Eigen::Matrix3d R0_ = Eigen::Matrix3d::Identity();
  Eigen::Vector3d w_ = Eigen::Vector3d::Zero();  // rotation vector in the start frame [rad]
  double t0_ = 0.0, duration_ = 1.0;
};

}  // namespace kiloloop
