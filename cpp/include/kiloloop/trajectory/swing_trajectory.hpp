#pragma once
// Swing-foot trajectory from lift-off point p0 to touch-down point p1 over a swing of duration T.
// Height: 7th-order polynomial pieces S7 (zero velocity, acceleration and jerk at lift-off, apex
// and touch-down), rising by `height` above the straight line p0 -> p1 at mid-swing.
// Horizontal: the same S7 blend from p0 to p1, so the foot leaves and lands without a jerk.
//   S7(u) = 35 u^4 - 84 u^5 + 70 u^6 - 20 u^7,  u in [0, 1]
#include <Eigen/Core>

namespace kiloloop {

struct SwingSample {
  Eigen::Vector3d p;  // [m]
  Eigen::Vector3d v;  // [m/s]
  Eigen::Vector3d a;  // [m/s^2]
};

// s in [0, 1] is the swing progress (clamped); duration [s] > 0 scales velocity/acceleration.
SwingSample sample_swing(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, double height,
                         double s, double duration) noexcept;

// S7 and its first three derivatives at u (clamped to [0, 1]).
void smoothstep7(double u, double* f, double* df, double* ddf, double* dddf) noexcept;

}  // namespace kiloloop
