#pragma once
// Roll and pitch [rad] of an orientation (world <- body; ZYX Euler angles), for the tests of the
// attitude estimates.
#include <cmath>

#include <Eigen/Geometry>

namespace kiloloop {

inline double roll_of(const Eigen::Quaterniond& q) {
  const Eigen::Matrix3d R = q.toRotationMatrix();
  return std::atan2(R(2, 1), R(2, 2));
}

inline double pitch_of(const Eigen::Quaterniond& q) {
  const Eigen::Matrix3d R = q.toRotationMatrix();
  return std::asin(-R(2, 0));
}

}  // namespace kiloloop
