#pragma once
// Validity of pose references, shared by every controller that takes one: a rotation that is not
// orthonormal with det +1 (or a 4x4 whose bottom row is not 0 0 0 1) has no meaningful log, and
// AngleAxis of it would turn into a wrong, but finite, error. Both are noexcept and allocation-free.
#include <cmath>

#include <Eigen/Core>
#include <Eigen/LU>

namespace kiloloop {

inline constexpr double kRotationTolerance = 1e-6;  // max |R^T R - I| entry

// Finite, R^T R = I within kRotationTolerance, det R > 0.
inline bool is_rotation(const Eigen::Matrix3d& R) noexcept {
  return R.allFinite() &&
         (R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() < kRotationTolerance &&
         R.determinant() > 0.0;
}

// Finite homogeneous transform with a rotation block and bottom row 0 0 0 1 (same tolerance).
inline bool is_rigid_transform(const Eigen::Matrix4d& T) noexcept {
  return T.allFinite() &&
         (T.row(3) - Eigen::RowVector4d(0.0, 0.0, 0.0, 1.0)).cwiseAbs().maxCoeff() < kRotationTolerance &&
         is_rotation(T.topLeftCorner<3, 3>());
}

}  // namespace kiloloop
