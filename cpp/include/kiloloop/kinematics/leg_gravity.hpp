#pragma once
// Gravity torques of one leg (trunk -> foot chain) for gravity given in the trunk frame, which
// turns with the trunk. With
//   tau = tau_g(q) - J^T f
// a leg in contact makes the ground push on its foot with exactly f (its own weight carried).
//
// tau_g = dV/dq with V = -g . M(q), M the leg's first moment of mass (sum m_i c_i) in the trunk
// frame. On an abduction / pitch / knee leg (LegKinematics's layout: the knee axis parallel to
// the hip pitch axis) every point of the leg moves as  d + R_abd(q0) (e + R(p1) u + R(p12) v),
// R(.) rotations about the pitch axis, q0, p1 = q1 + a_thigh, p12 = q1 + q2 + a_shank the
// kinematics' angles (signs applied). So M is linear in the 15 products of {1, cos p1, sin p1,
// cos p12, sin p12} and {1, cos q0, sin q0}: configure fits their 15 coefficient vectors to
// ChainRne's first moment (Newton-Euler constants from the URDF, the root link's and off-chain
// masses as KDL leaves them) and checks the torques against ChainRne's gravity pass at other
// poses; a tick then takes about 90 products from the sines and cosines LegKinematics already
// has, instead of a Newton-Euler pass over the leg's segments (0.8k instructions a leg, and their
// constants' cache lines, which MuJoCo's step evicts between ticks).
#include <string>

#include <Eigen/Core>

#include "kiloloop/dynamics/chain_rne.hpp"
#include "kiloloop/kinematics/leg_kinematics.hpp"
#include "kiloloop/model/robot_model.hpp"
#include "kiloloop/status.hpp"

namespace kiloloop {

class LegGravity {
 public:
  LegGravity() = default;
  LegGravity(LegGravity&&) = default;
  LegGravity& operator=(LegGravity&&) = default;
  // kinematics: the same leg's (its signs and angle offsets define the angles the torques are
  // computed from). Fails (kModelError, why) where the chain is not 3 joints or the fitted
  // torques miss ChainRne's by more than 1e-9 of their scale.
  static Status configure(const RobotModel& model, const std::string& trunk, const std::string& foot,
                          const LegKinematics& kinematics, LegGravity* out, std::string* why);
  // From the angles' sines and cosines (LegKinematics::foot_and_jacobian's trig at this leg's
  // q); gravity_trunk [m/s^2] in the trunk frame. Allocation-free.
  Eigen::Vector3d torque(const LegKinematics::Trig& trig, const Eigen::Vector3d& gravity_trunk) const noexcept;
  // The same at q (its sines and cosines computed here).
  Eigen::Vector3d torque(const Eigen::Vector3d& q, const Eigen::Vector3d& gravity_trunk) const noexcept;

  static constexpr int kTerms = 15;  // {1, c1, s1, c12, s12} x {1, c0, s0}, outer index first

 private:
  static void terms(const LegKinematics::Trig& t, double* b) noexcept;
  LegKinematics kinematics_;
  Eigen::Matrix<double, kTerms, 3> moment_;  // M(q) = moment_^T terms(q)  [kg m]
};

}  // namespace kiloloop
