#pragma once
// Which segment of a piecewise trajectory a time falls in, shared by the trajectories that sample
// through knot times (quintic, trapezoid).
#include <Eigen/Core>

namespace kiloloop {

// Index k of the segment [times[k], times[k+1]] holding t (times: >= 2 increasing knots); times
// before the first knot give the first segment, after the last knot the last one. Linear scan:
// trajectories have a handful of segments, and it allocates nothing.
inline Eigen::Index segment_at(const Eigen::VectorXd& times, double t) noexcept {
  const Eigen::Index last = times.size() - 2;
  Eigen::Index k = 0;
  while (k < last && t >= times[k + 1]) ++k;
  return k;
}

}  // namespace kiloloop
