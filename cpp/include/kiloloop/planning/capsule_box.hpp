#pragma once
// Exact distance between a segment (a capsule's axis) and an oriented box.
// In the box frame the squared distance from the segment point p(t) = P + t D to the box is
//   f(t) = sum_i max(0, |P_i + t D_i| - h_i)^2,
// piecewise quadratic and convex in t, with breakpoints where a coordinate crosses a face plane
// (at most 6). On each piece f is one closed-form quadratic, minimized in closed form: the result
// is exact up to rounding (no sampling, no iteration). Capsule-box distance = that minus the radius.
#include <Eigen/Core>

namespace kiloloop {

struct OrientedBox {
  Eigen::Vector3d center = Eigen::Vector3d::Zero();          // [m] in the world (chain root) frame
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();    // box axes in the world frame
  Eigen::Vector3d half_extents = Eigen::Vector3d::Zero();    // [m] >= 0
};

// Euclidean distance [m] from the segment [a, b] to the box (0 when they intersect).
double segment_box_distance(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                            const OrientedBox& box) noexcept;
// Distance [m] from a point to the box (0 inside).
double point_box_distance(const Eigen::Vector3d& p, const OrientedBox& box) noexcept;
// Capsule (segment [a, b], radius r) to box: segment distance - r; <= 0 means they touch.
inline double capsule_box_distance(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double r,
                                   const OrientedBox& box) noexcept {
  return segment_box_distance(a, b, box) - r;
}

}  // namespace kiloloop
