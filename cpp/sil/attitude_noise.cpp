#include "sil/attitude_noise.hpp"

#include <cmath>

namespace kiloloop::sil {

bool AttitudeNoise::configure(int n, std::string* why) {
  if (offset_ < 0 || offset_ + 4 > n || !std::isfinite(sigma_) || sigma_ < 0.0) {
    *why = "attitude noise: expected a quaternion inside y (offset + 4 <= " + std::to_string(n) +
           ") and a finite sigma >= 0";
    return false;
  }
  return true;
}

void AttitudeNoise::apply(double /*t*/, double* y) noexcept {
  double d[3];
  for (double& x : d) x = sigma_ * rng_.normal();
  // The same operations, in the same order, as nonideal._small_rotation (numpy).
  const double angle = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  if (angle < 1e-12) return;
  double* q = y + offset_;
  const double a[3] = {d[0] / angle, d[1] / angle, d[2] / angle};
  const double w2 = std::cos(angle / 2), s = std::sin(angle / 2);
  const double v2[3] = {s * a[0], s * a[1], s * a[2]};
  const double w1 = q[0], v1[3] = {q[1], q[2], q[3]};
  const double cross[3] = {v1[1] * v2[2] - v1[2] * v2[1], v1[2] * v2[0] - v1[0] * v2[2],
                           v1[0] * v2[1] - v1[1] * v2[0]};
  double out[4] = {w1 * w2 - (v1[0] * v2[0] + v1[1] * v2[1] + v1[2] * v2[2]), 0.0, 0.0, 0.0};
  for (int i = 0; i < 3; ++i) out[1 + i] = w1 * v2[i] + w2 * v1[i] + cross[i];
  const double norm = std::sqrt(out[0] * out[0] + out[1] * out[1] + out[2] * out[2] + out[3] * out[3]);
  for (int i = 0; i < 4; ++i) q[i] = out[i] / norm;
}

}  // namespace kiloloop::sil
