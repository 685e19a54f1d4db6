#pragma once
// Conversions between KDL's and Eigen's vectors and frames, defined once for every source that
// needs them (a unity build compiles several sources as one translation unit, where per-file
// copies in anonymous namespaces collide).
#include <Eigen/Geometry>
#include <kdl/frames.hpp>

namespace kiloloop {

inline Eigen::Vector3d to_eigen(const KDL::Vector& v) { return Eigen::Vector3d(v.x(), v.y(), v.z()); }

inline Eigen::Isometry3d to_eigen(const KDL::Frame& f) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) T.linear()(r, c) = f.M(r, c);
    T.translation()[r] = f.p[r];
  }
  return T;
}

inline KDL::Vector to_kdl(const Eigen::Vector3d& v) { return KDL::Vector(v.x(), v.y(), v.z()); }

}  // namespace kiloloop
