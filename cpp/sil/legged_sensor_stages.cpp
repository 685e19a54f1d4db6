#include "sil/legged_sensor_stages.hpp"

#include <cmath>

namespace kiloloop::sil {

bool ImuStage::setup(const ImuModelConfig& config, int offset, std::string* why) {
  if (offset < 0) {
    *why = "imu stage: offset must be >= 0";
    return false;
  }
  offset_ = offset;
  return imu_.configure(config, why);
}

bool ImuStage::configure(int n, std::string* why) {
  if (offset_ + ImuModel::kSize > n) {
    *why = "imu stage: y has " + std::to_string(n) + " entries, the IMU slice ends at " +
           std::to_string(offset_ + ImuModel::kSize);
    return false;
  }
  return true;
}

void ImuStage::apply(double /*t*/, double* y) noexcept { imu_.apply(y + offset_, y + offset_); }

bool JointEncoderStage::setup(int n, int q_offset, int qd_offset, double q_resolution,
                              double velocity_resolution, double dt, std::string* why) {
  if (q_offset < 0 || qd_offset < 0 || !std::isfinite(q_resolution) || q_resolution < 0.0) {
    *why = "joint encoder stage: expected offsets >= 0 and a finite q_resolution >= 0";
    return false;
  }
  n_ = n;
  q_offset_ = q_offset;
  qd_offset_ = qd_offset;
  q_resolution_ = q_resolution;
  return velocity_.configure(n, velocity_resolution, dt, why);
}

bool JointEncoderStage::configure(int n, std::string* why) {
  if (q_offset_ + n_ > n || qd_offset_ + n_ > n) {
    *why = "joint encoder stage: the q or qd slice lies beyond y (" + std::to_string(n) + " entries)";
    return false;
  }
  velocity_.reset();
  return true;
}

void JointEncoderStage::apply(double /*t*/, double* y) noexcept {
  double* q = y + q_offset_;
  velocity_.apply(q, y + qd_offset_);
  if (q_resolution_ > 0.0)
    for (int i = 0; i < n_; ++i) q[i] = q_resolution_ * std::nearbyint(q[i] / q_resolution_);
}

}  // namespace kiloloop::sil
