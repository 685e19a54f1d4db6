#include "kiloloop/quadruped/attitude_filter.hpp"
#include "kiloloop/model/gravity.hpp"

#include <algorithm>
#include <cmath>

namespace kiloloop {

bool AttitudeFilter::configure(const AttitudeFilterConfig& config, double dt) {
  if (!(config.gyro_noise_density > 0) || !(config.accel_noise_density > 0) ||
      !(config.crossover >= 0) || !(config.accel_tolerance > 0) || !(config.max_gyro_bias >= 0) ||
      !(dt > 0) || !std::isfinite(config.crossover + config.gyro_noise_density +
                                  config.accel_noise_density + config.accel_tolerance + config.max_gyro_bias + dt))
    return false;
  cfg_ = config;
  if (cfg_.crossover == 0.0) cfg_.crossover = cfg_.gyro_noise_density * kGravity / cfg_.accel_noise_density;
  dt_ = dt;
  kp_ = cfg_.crossover;
  ki_ = 0.25 * kp_ * kp_;
  reset(Eigen::Quaterniond::Identity());
  return true;
}

void AttitudeFilter::reset(const Eigen::Quaterniond& q0) noexcept {
  q_ = q0.normalized();
  bias_.setZero();
  rate_.setZero();
  aligned_time_ = 0.0;
}

Eigen::Quaterniond AttitudeFilter::from_gravity(const Eigen::Vector3d& accel) noexcept {
  const double norm = accel.norm();
  if (!std::isfinite(norm) || std::abs(norm - kGravity) > 0.5 * kGravity) return Eigen::Quaterniond::Identity();
  const Eigen::Vector3d up = accel / norm;  // R^T e_z for R = Ry(pitch) Rx(roll)
  const double roll = std::atan2(up.y(), up.z());
  const double pitch = std::atan2(-up.x(), std::hypot(up.y(), up.z()));
  return Eigen::Quaterniond(Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                            Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()));
}

double AttitudeFilter::gate(const Eigen::Vector3d& accel) const noexcept {
  const double norm = accel.norm();
  return norm > 1e-3 * kGravity && std::isfinite(norm)
             ? std::clamp(1.0 - std::abs(norm - kGravity) / (cfg_.accel_tolerance * kGravity), 0.0, 1.0)
             : 0.0;
}

void AttitudeFilter::update(const Eigen::Vector3d& gyro, const Eigen::Vector3d& specific_force) noexcept {
  correct(gyro, specific_force, gate(specific_force));
}

void AttitudeFilter::update_aided(const Eigen::Vector3d& gyro, const Eigen::Vector3d& specific_force,
                                  const Eigen::Vector3d& trunk_accel, double weight) noexcept {
  const Eigen::Vector3d up = specific_force - trunk_accel;  // gravity's reaction [m/s^2]
  const double norm = up.norm();
  const double w = !(norm > 1e-3 * kGravity && std::isfinite(norm)) ? 0.0
                   : aligning() ? std::min(gate(up), std::clamp(weight, 0.0, 1.0))
                                : std::clamp(weight, 0.0, 1.0);
  correct(gyro, up, w);
}

void AttitudeFilter::correct(const Eigen::Vector3d& gyro, const Eigen::Vector3d& accel, double w) noexcept {
  Eigen::Vector3d e = Eigen::Vector3d::Zero();
  if (w > 0.0) {
    const Eigen::Vector3d up = q_.conjugate() * Eigen::Vector3d::UnitZ();
    e = accel.normalized().cross(up);
  }
  aligned_time_ = std::min(aligned_time_ + w * dt_, 1e6);
  const double kp = aligned_time_ > 0.0 ? std::min(std::max(kp_, 1.0 / aligned_time_), 1.0 / dt_) : kp_;
  bias_ -= ki_ * w * dt_ * e;
  bias_ = bias_.cwiseMax(-cfg_.max_gyro_bias).cwiseMin(cfg_.max_gyro_bias);
  rate_ = gyro - bias_;
  const Eigen::Vector3d half = 0.5 * dt_ * (rate_ + kp * w * e);
  q_ = (q_ * Eigen::Quaterniond(1.0, half.x(), half.y(), half.z())).normalized();
}

}  // namespace kiloloop
