#pragma once
// Recursive Newton-Euler for a serial chain whose base moves: the arm under a multirotor.
//
// KDL's ChainIdSolver_RNE assumes a fixed base; it only injects gravity as a fictitious base
// acceleration. Here the base (the chain root frame = the body frame) has a twist and a spatial
// acceleration, both propagated down the chain; the passes are KDL's recursion, computed by
// ChainRne (dynamics/chain_rne.hpp: constants precomputed, about half of KDL's cost).
// Outputs: the joint torques that realise qdd while the base moves as given, and the wrench the
// base must apply to the arm at the chain root, which is minus the arm's reaction on the body.
//
// Conventions (Featherstone body coordinates, as in KDL's RNE): twists (linear; angular) of the
// frame origin in the frame's own axes. The base's spatial acceleration is built from the
// classical one: a_spatial_lin = R^T (a_origin - g) - omega x v, a_spatial_ang = alpha.
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <kdl/chain.hpp>
#include <kdl/frames.hpp>

#include "kiloloop/dynamics/chain_rne.hpp"
#include "kiloloop/model/robot_model.hpp"
#include "kiloloop/status.hpp"

namespace kiloloop {

using Vector6d = Eigen::Matrix<double, 6, 1>;

// Motion of the chain root (the body), everything in the body frame at the body origin.
struct BaseMotion {
  Eigen::Vector3d v = Eigen::Vector3d::Zero();      // [m/s] velocity of the body origin
  Eigen::Vector3d omega = Eigen::Vector3d::Zero();  // [rad/s] angular velocity
  // [m/s^2] classical acceleration of the body origin minus gravity, body axes: what an ideal
  // accelerometer at the origin reads (+9.81 up at rest).
  Eigen::Vector3d specific_force = Eigen::Vector3d(0.0, 0.0, 9.81);
  Eigen::Vector3d alpha = Eigen::Vector3d::Zero();  // [rad/s^2] angular acceleration
};

class FloatingBaseRne {
 public:
  using VecRef = Eigen::Ref<const Eigen::VectorXd>;

  // Needs the model's serial chain (root = the body link, tip = the end effector).
  static Status configure(RobotModelPtr model, FloatingBaseRne* out, std::string* why);

  int nq() const { return nq_; }

  // tau (nq) [N m]: joint torques; wrench_on_arm (6) [N; N m]: force and torque the body applies
  // to the arm, body frame, about the body origin (the arm's reaction on the body is its negative).
  // kBadSize / kNonFiniteMeasurement leave both outputs zero.
  // tip_position (may be null): the end effector at q [m], body frame, from the same pass's poses
  // (left as it was on a bad input).
  Status compute(const VecRef& q, const VecRef& qd, const VecRef& qdd, const BaseMotion& base,
                 Eigen::Ref<Eigen::VectorXd> tau, Vector6d* wrench_on_arm,
                 Eigen::Vector3d* tip_position = nullptr) noexcept;

  // The arm's first moment of mass sum(m_i c_i) (3) [kg m] at q, in the root (body) frame, and
  // its mass [kg]: where the arm puts the vehicle's centre of mass.
  Status first_moment(const VecRef& q, Eigen::Vector3d* moment, double* mass) const noexcept;

 private:
  RobotModelPtr model_;
  int nq_ = 0;
  ChainRne rne_;  // the moving-base Newton-Euler pass over the chain's constants
};

}  // namespace kiloloop
