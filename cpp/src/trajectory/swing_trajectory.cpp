#include "kiloloop/trajectory/swing_trajectory.hpp"

#include <algorithm>

namespace kiloloop {

void smoothstep7(double u, double* f, double* df, double* ddf, double* dddf) noexcept {
  u = std::clamp(u, 0.0, 1.0);
  const double u2 = u * u, u3 = u2 * u, u4 = u3 * u, u5 = u4 * u, u6 = u5 * u, u7 = u6 * u;
  if (f) *f = 35 * u4 - 84 * u5 + 70 * u6 - 20 * u7;
  if (df) *df = 140 * u3 - 420 * u4 + 420 * u5 - 140 * u6;
  if (ddf) *ddf = 420 * u2 - 1680 * u3 + 2100 * u4 - 840 * u5;
  if (dddf) *dddf = 840 * u - 5040 * u2 + 8400 * u3 - 4200 * u4;
}

SwingSample sample_swing(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, double height,
                         double s, double duration) noexcept {
  s = std::clamp(s, 0.0, 1.0);
  const double rate = 1.0 / duration;  // ds/dt
  double f, df, ddf;
  smoothstep7(s, &f, &df, &ddf, nullptr);
  SwingSample out;
  const Eigen::Vector3d delta = p1 - p0;
  out.p = p0 + f * delta;
  out.v = df * rate * delta;
  out.a = ddf * rate * rate * delta;
  // Apex bump: up on the first half, down on the second, each an S7 of u = 2s or 2 - 2s.
  double h, dh, ddh;
  const bool rising = s < 0.5;
  smoothstep7(rising ? 2.0 * s : 2.0 - 2.0 * s, &h, &dh, &ddh, nullptr);
  const double sign = rising ? 1.0 : -1.0;
  out.p.z() += height * h;
  out.v.z() += height * dh * 2.0 * sign * rate;
  out.a.z() += height * ddh * 4.0 * rate * rate;
  return out;
}

}  // namespace kiloloop
