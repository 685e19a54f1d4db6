#include "kiloloop/quadruped/attitude_filter.hpp"
#include "kiloloop/model/gravity.hpp"

#include <algorithm>
#include <cmath>

namespace kiloloop {

bool AttitudeFilter::configure(const AttitudeFilterConfig& config, double dt) {
  if (!(config.gyro_noise_density > 0) || !(config.accel_noise_density > 0) ||
      !(config.crossover >= 0) || !(config.accel_tolerance > 0) || !(config.max_gyro_bias >= 0) ||
      !(config.gyro_bias_random_walk >= 0) || !(config.gyro_turn_on_bias >= 0) ||
      !(dt > 0) || !std::isfinite(config.crossover + config.gyro_noise_density +
                                  config.accel_noise_density + config.accel_tolerance + config.max_gyro_bias +
                                  config.gyro_bias_random_walk + config.gyro_turn_on_bias + dt))
    return false;
  cfg_ = config;
  if (cfg_.crossover == 0.0) cfg_.crossover = cfg_.gyro_noise_density * kGravity / cfg_.accel_noise_density;
  dt_ = dt;
  kp_ = cfg_.crossover;
  // The tilt measurement's noise density follows from the crossover c = N_g / sqrt(r): r = (N_a /
  // g)^2 when derived; a crossover set by hand sets r with it.
  q_gyro_ = cfg_.gyro_noise_density * cfg_.gyro_noise_density;
  r_ = q_gyro_ / (kp_ * kp_);
  q_bias_ = cfg_.gyro_bias_random_walk * cfg_.gyro_bias_random_walk;
  reset(Eigen::Quaterniond::Identity());
  return true;
}

void AttitudeFilter::reset(const Eigen::Quaterniond& q0) noexcept {
  q_ = q0.normalized();
  bias_.setZero();
  rate_.setZero();
  aligned_time_ = 0.0;
  // Tilt: set by the start-up alignment's gain (correct()); the bias: the turn-on bias.
  p_tt_ = r_ / dt_;
  p_tb_ = 0.0;
  p_bb_ = cfg_.gyro_turn_on_bias * cfg_.gyro_turn_on_bias;
  k_tilt_ = k_bias_ = 0.0;
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
  const bool start_up = aligning();  // before this reading
  Eigen::Vector3d e = Eigen::Vector3d::Zero();
  if (w > 0.0) {
    const Eigen::Vector3d up = q_.conjugate() * Eigen::Vector3d::UnitZ();
    e = accel.normalized().cross(up);
  }
  aligned_time_ = std::min(aligned_time_ + w * dt_, 1e6);
  k_tilt_ = k_bias_ = 0.0;
  if (start_up) {
    // Initial alignment: the tilt gain of an uninformative prior, 1 / T (capped at one reading),
    // and the tilt variance it stands for (k = P_tt / r). The bias is held: the start-up's readings
    // (a drop, feet sinking into soft ground, a shove) are no steady gravity to learn it from
    // (measured: learnt there by the Kalman gains, the tilt-stop's shove at 0.5 s was taken as
    // bias, the stop 11 ticks late; with the Kalman's tilt gain there, our model on compliant
    // ground read its pitch 14 deg off within 40 ms and fell).
    const double kp = aligned_time_ > 0.0 ? std::min(std::max(kp_, 1.0 / aligned_time_), 1.0 / dt_) : kp_;
    k_tilt_ = kp * w * dt_;
    p_tt_ = r_ * kp;
  } else if (w > 0.0) {
    // Kalman update of [tilt; bias] with one reading's variance r / dt [rad^2], applied with the
    // weight w as the probability that the reading is gravity (probabilistic data association:
    // x += w K nu, P -= w K S K^T), so that w scales the gains as it scales Mahony's k_p w.
    const double s = p_tt_ + r_ / dt_;
    const double p_tt = p_tt_, p_tb = p_tb_;
    k_tilt_ = w * p_tt / s;
    // The bias gain at most the critically damped one of this tilt gain (k_i <= k_p^2 / 4 in
    // s^2 + k_p s + k_i): right after the alignment the Kalman's k_i (up to 23 rad/s^2 at 1 s
    // against k_p 6.7) overshoots the bias by half (measured: -8.8e-3 rad/s at 1-2 s for a
    // -5.84e-3 bias) and passes the legs' corrections into it.
    const double kp = k_tilt_ / dt_;
    k_bias_ = std::max(w * p_tb / s, -0.25 * kp * kp * dt_);
    p_tt_ -= w * p_tt * p_tt / s;
    p_tb_ -= w * p_tt * p_tb / s;
    p_bb_ -= w * p_tb * p_tb / s;
  }
  bias_ += k_bias_ * e;
  bias_ = bias_.cwiseMax(-cfg_.max_gyro_bias).cwiseMin(cfg_.max_gyro_bias);
  rate_ = gyro - bias_;
  const Eigen::Vector3d half = 0.5 * (dt_ * rate_ + k_tilt_ * e);
  q_ = (q_ * Eigen::Quaterniond(1.0, half.x(), half.y(), half.z())).normalized();
  if (start_up) return;
  // Propagate over dt: tilt' = -bias (error state) + gyro noise, bias' = random walk (exact
  // discretisation of F = [1 -dt; 0 1] with Q from q_gyro_, q_bias_).
  const double dt = dt_;
  p_tt_ += dt * (-2.0 * p_tb_ + dt * p_bb_) + q_gyro_ * dt + q_bias_ * dt * dt * dt / 3.0;
  p_tb_ += -dt * p_bb_ - 0.5 * q_bias_ * dt * dt;
  p_bb_ += q_bias_ * dt;
}

}  // namespace kiloloop
