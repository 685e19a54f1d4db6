#pragma once
// Conversions between KDL's and Eigen's vectors and frames, defined once for every source that
// needs them (a unity build compiles several sources as one translation unit, where per-file
// copies in anonymous namespaces collide).
#include <Eigen/Geometry>
#include <kdl/frames.hpp>

namespace kiloloop {

inline Eigen::Vector3d to_eigen(const KDL::Vector& v) { return Eigen::Vector3d(v.x(), v.y(), v.z()); }

inline Eigen::Matrix3d to_eigen(const KDL::Rotation& R) {
  Eigen::Matrix3d m;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) m(r, c) = R(r, c);
  return m;
}

inline Eigen::Isometry3d to_eigen(const KDL::Frame& f) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = to_eigen(f.M);
  T.translation() = to_eigen(f.p);
  return T;
}

inline KDL::Vector to_kdl(const Eigen::Vector3d& v) { return KDL::Vector(v.x(), v.y(), v.z()); }

}  // namespace kiloloop
