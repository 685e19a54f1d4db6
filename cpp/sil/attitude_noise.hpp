#pragma once
// Attitude-estimate noise as a stage of the native loop's measurement path (sensor_stage.hpp):
// the quaternion y[offset..offset+3] (w, x, y, z, world <- body) is followed by a small random
// rotation in the body frame, q * exp(dtheta), dtheta ~ N(0, sigma^2) per axis [rad], renormalized
// (nonideal._small_rotation, which the per-tick Python loop used to draw from numpy). Its own
// seeded stream (three normals per tick), so the other noise streams do not depend on it.
#include <string>

#include "sil/rng.hpp"
#include "sil/sensor_stage.hpp"

namespace kiloloop::sil {

class AttitudeNoise final : public SensorStage {
 public:
  AttitudeNoise(int offset, double sigma, unsigned long long seed) : offset_(offset), sigma_(sigma), rng_(seed) {}
  bool configure(int n, std::string* why) override;
  void apply(double t, double* y) noexcept override;

 private:
  int offset_;
  double sigma_;  // [rad] per axis
  Rng rng_;
};

}  // namespace kiloloop::sil
