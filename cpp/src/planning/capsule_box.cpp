#include "kiloloop/planning/capsule_box.hpp"

#include <cmath>

namespace kiloloop {

double point_box_distance(const Eigen::Vector3d& p, const OrientedBox& box) noexcept {
  const Eigen::Vector3d local = box.rotation.transpose() * (p - box.center);
  return (local.cwiseAbs() - box.half_extents).cwiseMax(0.0).norm();
}

double segment_box_distance(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                            const OrientedBox& box) noexcept {
  const Eigen::Vector3d P = box.rotation.transpose() * (a - box.center);
  const Eigen::Vector3d D = box.rotation.transpose() * (b - a);
  const Eigen::Vector3d& h = box.half_extents;
  // Breakpoints in (0, 1): where P_i + t D_i = +-h_i. With the ends, at most 8, sorted in place.
  double t[8];
  int n = 0;
  t[n++] = 0.0;
  t[n++] = 1.0;
  for (int i = 0; i < 3; ++i) {
    if (D[i] == 0.0) continue;
    for (double face : {h[i], -h[i]}) {
      const double ti = (face - P[i]) / D[i];
      if (ti > 0.0 && ti < 1.0) t[n++] = ti;
    }
  }
  for (int i = 1; i < n; ++i)  // insertion sort of <= 8 values
    for (int j = i; j > 0 && t[j] < t[j - 1]; --j) std::swap(t[j], t[j - 1]);

  double best = INFINITY;
  for (int k = 0; k + 1 < n; ++k) {
    const double t0 = t[k], t1 = t[k + 1];
    // Which side of each slab the piece lies on, decided at its midpoint.
    const double tm = 0.5 * (t0 + t1);
    double A = 0.0, B = 0.0, C = 0.0;  // f(t) = A t^2 + B t + C on [t0, t1]
    for (int i = 0; i < 3; ++i) {
      const double x = P[i] + tm * D[i];
      double offset;
      if (x > h[i]) offset = P[i] - h[i];
      else if (x < -h[i]) offset = P[i] + h[i];
      else continue;
      A += D[i] * D[i];
      B += 2.0 * D[i] * offset;
      C += offset * offset;
    }
    double ts = t0;
    if (A > 0.0) ts = std::fmin(std::fmax(-B / (2.0 * A), t0), t1);
    else if (B > 0.0) ts = t0;
    else ts = t1;
    best = std::fmin(best, std::fmax(A * ts * ts + B * ts + C, 0.0));
  }
  return std::sqrt(best);
}

}  // namespace kiloloop
