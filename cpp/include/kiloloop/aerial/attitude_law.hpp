#pragma once
// Attitude control laws behind one interface, so the composed controller (and a test) can swap
// them by a config value. A law maps the measured attitude and rate, the target and the running
// error integral to a body torque; it owns no state (the integral lives in AttitudeController).
//
// Gains are per body axis and in acceleration units; the law multiplies by the inertia J, so the
// same numbers suit any vehicle: kp [1/s^2], kd [1/s], ki [1/s^3]. Both laws report the
// attitude error e_R (rad-like: the rotation angle for small errors) the integral accumulates.
#include <Eigen/Core>
#include <Eigen/Geometry>

namespace kiloloop {

struct AttitudeGains {
  Eigen::Vector3d kp{400.0, 400.0, 100.0};  // [1/s^2] roll, pitch, yaw (body axes)
  Eigen::Vector3d kd{40.0, 40.0, 20.0};     // [1/s]
  Eigen::Vector3d ki{0.0, 0.0, 0.0};        // [1/s^3] 0 turns the integral off
};

struct AttitudeTarget {
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();  // world <- desired body
  Eigen::Vector3d omega = Eigen::Vector3d::Zero();        // [rad/s] desired rate, desired frame
  Eigen::Vector3d omega_dot = Eigen::Vector3d::Zero();    // [rad/s^2] desired frame
};

class AttitudeLaw {
 public:
  virtual ~AttitudeLaw() = default;
  // q: world <- body (unit); omega: body rate [rad/s]; integral: running integral of e_R [rad s].
  // Writes e_R (3) and the body torque tau (3) [N m].
  virtual void compute(const AttitudeGains& gains, const Eigen::Matrix3d& J,
                       const Eigen::Quaterniond& q, const Eigen::Vector3d& omega,
                       const AttitudeTarget& target, const Eigen::Vector3d& integral,
                       Eigen::Vector3d* e_R, Eigen::Vector3d* tau) noexcept = 0;
  virtual void reset() noexcept {}
};

// Quaternion-error PD(+I): q_err = q_des^-1 q, e_R = 2 h vec(q_err) with h = +-1 choosing the
// shorter rotation, tau = J (-kp e_R - kd (omega - omega_des) - ki integral) + omega x J omega.
// h switches only when h w(q_err) < -hysteresis (Mayhew et al.'s hysteretic rule): near 180 deg the
// plain sign(w) rule flips back and forth on noise and the torque jumps from +max to -max.
class QuaternionPdLaw : public AttitudeLaw {
 public:
  explicit QuaternionPdLaw(double hysteresis = 0.1) : hysteresis_(hysteresis) {}
  void compute(const AttitudeGains& gains, const Eigen::Matrix3d& J, const Eigen::Quaterniond& q,
               const Eigen::Vector3d& omega, const AttitudeTarget& target,
               const Eigen::Vector3d& integral, Eigen::Vector3d* e_R,
               Eigen::Vector3d* tau) noexcept override;
  void reset() noexcept override { h_ = 1.0; }
  double sign() const { return h_; }

 private:
  double hysteresis_;
  double h_ = 1.0;
};

// Lee, Leok, McClamroch (2010), geometric tracking on SO(3):
//   e_R = 1/2 vee(R_d^T R - R^T R_d), e_W = W - R^T R_d W_d,
//   tau = J (-kR e_R - kW e_W - ki integral) + W x J W - J (hat(W) R^T R_d W_d - R^T R_d Wdot_d).
class GeometricSo3Law : public AttitudeLaw {
 public:
  void compute(const AttitudeGains& gains, const Eigen::Matrix3d& J, const Eigen::Quaterniond& q,
               const Eigen::Vector3d& omega, const AttitudeTarget& target,
               const Eigen::Vector3d& integral, Eigen::Vector3d* e_R,
               Eigen::Vector3d* tau) noexcept override;
};

}  // namespace kiloloop
