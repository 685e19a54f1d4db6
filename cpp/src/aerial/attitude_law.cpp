#include "kiloloop/aerial/attitude_law.hpp"

namespace kiloloop {

void QuaternionPdLaw::compute(const AttitudeGains& gains, const Eigen::Matrix3d& J,
                              const Eigen::Quaterniond& q, const Eigen::Vector3d& omega,
                              const AttitudeTarget& target, const Eigen::Vector3d& integral,
                              Eigen::Vector3d* e_R, Eigen::Vector3d* tau) noexcept {
  const Eigen::Quaterniond q_err = target.q.conjugate() * q;  // desired <- body
  if (h_ * q_err.w() < -hysteresis_) h_ = -h_;
  *e_R = 2.0 * h_ * q_err.vec();
  // The desired rate, seen in the body frame.
  const Eigen::Vector3d omega_des = q_err.conjugate() * target.omega;
  const Eigen::Vector3d acc = -gains.kp.cwiseProduct(*e_R) -
                              gains.kd.cwiseProduct(omega - omega_des) -
                              gains.ki.cwiseProduct(integral);
  *tau = J * acc + omega.cross(J * omega);
}

namespace {

Eigen::Vector3d vee(const Eigen::Matrix3d& S) { return {S(2, 1), S(0, 2), S(1, 0)}; }

Eigen::Matrix3d hat(const Eigen::Vector3d& w) {
  Eigen::Matrix3d S;
  S << 0.0, -w.z(), w.y(), w.z(), 0.0, -w.x(), -w.y(), w.x(), 0.0;
  return S;
}

}  // namespace

void GeometricSo3Law::compute(const AttitudeGains& gains, const Eigen::Matrix3d& J,
                              const Eigen::Quaterniond& q, const Eigen::Vector3d& omega,
                              const AttitudeTarget& target, const Eigen::Vector3d& integral,
                              Eigen::Vector3d* e_R, Eigen::Vector3d* tau) noexcept {
  const Eigen::Matrix3d R = q.toRotationMatrix();
  const Eigen::Matrix3d Rd = target.q.toRotationMatrix();
  const Eigen::Matrix3d RtRd = R.transpose() * Rd;
  *e_R = 0.5 * vee(Rd.transpose() * R - RtRd);
  const Eigen::Vector3d w_des = RtRd * target.omega;  // desired rate in the body frame
  const Eigen::Vector3d e_W = omega - w_des;
  const Eigen::Vector3d acc = -gains.kp.cwiseProduct(*e_R) - gains.kd.cwiseProduct(e_W) -
                              gains.ki.cwiseProduct(integral);
  *tau = J * acc + omega.cross(J * omega) -
         J * (hat(omega) * w_des - RtRd * target.omega_dot);
}

}  // namespace kiloloop
