#pragma once
// The sanity bound on measured states and references, written once: a finite value beyond
// kSaneMagnitude ([m], [m/s], [rad], [rad/s], [m/s^2] alike) can only be a fault (a corrupt
// packet, an overflowed upstream filter) and would overflow the products of a control law or an
// estimator to Inf. Such an input is treated as a bad measurement (status < 0), as NaN is.
#include <cmath>

#include <Eigen/Core>

namespace kiloloop {

inline constexpr double kSaneMagnitude = 1e6;
// [s] a controller clock or stamp beyond this (30 years) is a fault too (t = 1e308 overflowed
// the gait phase and the wrench in fuzzing).
inline constexpr double kSaneTime = 1e9;

inline bool within_sane_range(double x) noexcept { return std::isfinite(x) && std::abs(x) <= kSaneMagnitude; }

template <typename Derived>
bool within_sane_range(const Eigen::MatrixBase<Derived>& v) noexcept {
  return v.allFinite() && (v.size() == 0 || v.cwiseAbs().maxCoeff() <= kSaneMagnitude);
}

}  // namespace kiloloop
