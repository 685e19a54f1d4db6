#include "sil/imu_model.hpp"

#include <cmath>

namespace kiloloop::sil {

namespace {
bool valid(const InertialNoise& s) {
  for (double v : {s.noise_density, s.bias_random_walk, s.turn_on_bias})
    if (!std::isfinite(v) || v < 0.0) return false;
  return true;
}
}  // namespace

bool ImuModel::configure(const ImuModelConfig& config, std::string* why) {
  if (!valid(config.gyro) || !valid(config.accel)) {
    *why = "imu noise parameters: expected finite values >= 0";
    return false;
  }
  if (!std::isfinite(config.dt) || !(config.dt > 0.0)) {
    *why = "imu dt: expected a finite period > 0";
    return false;
  }
  cfg_ = config;
  rng_.reseed(config.seed);
  for (int i = 0; i < kSize; ++i) {
    const InertialNoise& s = i < 3 ? config.gyro : config.accel;
    white_[i] = s.noise_density / std::sqrt(config.dt);
    walk_[i] = s.bias_random_walk * std::sqrt(config.dt);
    bias_[i] = s.turn_on_bias * rng_.normal();
  }
  return true;
}

void ImuModel::apply(const double* x, double* y) noexcept {
  for (int i = 0; i < kSize; ++i) {
    const double white = rng_.normal(), step = rng_.normal();
    y[i] = x[i] + bias_[i] + white_[i] * white;
    bias_[i] += walk_[i] * step;
  }
}

bool EncoderVelocity::configure(int n, double resolution, double dt, std::string* why) {
  if (n < 0 || !std::isfinite(resolution) || resolution < 0.0 || !std::isfinite(dt) || !(dt > 0.0)) {
    *why = "encoder velocity: expected n >= 0, a finite resolution >= 0 and dt > 0";
    return false;
  }
  n_ = n;
  resolution_ = resolution;
  dt_ = dt;
  previous_.assign(n, 0.0);
  primed_ = false;
  return true;
}

void EncoderVelocity::apply(const double* q, double* qd) noexcept {
  for (int i = 0; i < n_; ++i) {
    // nearbyint rounds half to even in the default rounding mode (as numpy.round).
    const double reading = resolution_ > 0.0 ? resolution_ * std::nearbyint(q[i] / resolution_) : q[i];
    qd[i] = primed_ ? (reading - previous_[i]) / dt_ : 0.0;
    previous_[i] = reading;
  }
  primed_ = true;
}

}  // namespace kiloloop::sil
