#pragma once
// AttitudeController: one of two interchangeable laws (attitude_law.hpp) plus the error integral
// with anti-windup. The integral's share ki * integral of the commanded angular acceleration is
// clamped to +-integral_limit per axis, and the integral is frozen on a
// tick whose torque the rotors could not deliver (the caller passes `saturated`), so it neither
// winds up while the rotors are at their limits nor kicks when they come back.
#include <string>

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "kiloloop/aerial/attitude_law.hpp"
#include "kiloloop/status.hpp"

namespace kiloloop {

enum class AttitudeLawType : int { kQuaternionPd = 0, kGeometricSo3 = 1 };

struct AttitudeControlConfig {
  AttitudeLawType law = AttitudeLawType::kQuaternionPd;  // quaternion PD or geometric SO(3)
  AttitudeGains gains;  // kp, kd, ki per body axis
  // [rad/s^2] largest angular acceleration the integral may command, per axis (30 rad/s^2 at
  // J = 0.015 kg m^2 is 0.45 N m: a 40 % thrust loss on one rotor of this vehicle).
  Eigen::Vector3d integral_limit{30.0, 30.0, 10.0};
  double hysteresis = 0.1;  // quaternion law: |w| margin before the shortest-path sign flips
  double dt = 0.001;        // [s]
};

Status validate(const AttitudeControlConfig& config, std::string* why);

class AttitudeController {
 public:
  static Status configure(const AttitudeControlConfig& config, const Eigen::Matrix3d& inertia,
                          AttitudeController* out, std::string* why);

  // q: world <- body, omega: body rate [rad/s]; writes the body torque tau (3) [N m].
  // `saturated`: the previous torque was not delivered in full (freezes the integral).
  Status step(const Eigen::Quaterniond& q, const Eigen::Vector3d& omega,
              const AttitudeTarget& target, bool saturated, Eigen::Vector3d* tau) noexcept;
  void reset() noexcept;

  const Eigen::Vector3d& error() const { return e_R_; }        // [rad] last e_R
  const Eigen::Vector3d& integral() const { return integral_; }  // [rad s]
  const Eigen::Matrix3d& inertia() const { return J_; }          // [kg m^2]
  // J's factorization, made once at configure: alpha = J^-1 (tau - w x J w) each tick needs only
  // the solve (the same LDLT J.ldlt() would build, so the same numbers).
  const Eigen::LDLT<Eigen::Matrix3d>& inertia_ldlt() const { return J_ldlt_; }
  AttitudeLawType law() const { return cfg_.law; }

 private:
  AttitudeLaw* active() noexcept;

  AttitudeControlConfig cfg_;
  Eigen::Matrix3d J_ = Eigen::Matrix3d::Identity();
  Eigen::LDLT<Eigen::Matrix3d> J_ldlt_{Eigen::Matrix3d::Identity()};
  QuaternionPdLaw quaternion_pd_;
  GeometricSo3Law geometric_;
  Eigen::Vector3d e_R_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d integral_ = Eigen::Vector3d::Zero();
  bool configured_ = false;
};

}  // namespace kiloloop
