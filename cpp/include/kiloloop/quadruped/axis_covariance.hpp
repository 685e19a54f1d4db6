#pragma once
// The covariance of StateEstimator's velocity filter, x = [p; v] (world), held per axis.
// The filter's F = [I dt I; 0 I], its process noise, its measurement (H = I: the legs' [p; v])
// and that measurement's noise act on x, y and z alike and never couple two axes, so the 6x6
// covariance is [[a I, b I], [c I, d I]]: one 2x2 block [a b; c d] carries all of it.
//
// Why not the 6x6: its products and its inverse (Eigen's PartialPivLU) were a fifth of the
// quadruped controller's instructions per tick (callgrind: 8.2k of 70.7k), nearly all of it on
// entries that are exact zeros. Every operation here reproduces, bit for bit, what those 6x6
// operations computed: each 6x6 entry is a sum whose terms from the other axes are exact zeros
// (adding them changes nothing), and an entry with two non-zero terms rounds their sum once,
// whichever order they came in. The inverse follows PartialPivLU's steps on the axis's two rows
// (pivot, rank-1 update, unit-lower then upper substitution with the reciprocal diagonal), and
// the symmetrization 0.5 (P + P^T), which Eigen evaluated in place, column by column, takes the
// lower entry already averaged into the upper one, as it did (axis_covariance_test.cpp checks
// all of it against the 6x6 code).
#include <Eigen/Core>

namespace kiloloop {

// The per-axis Kalman gain K = P S^-1: dx_p = pp e_p + pv e_v, dx_v = vp e_p + vv e_v per axis.
struct AxisGain {
  double pp = 0.0, pv = 0.0, vp = 0.0, vv = 0.0;
};

class AxisCovariance {
 public:
  AxisCovariance() = default;
  // [p_var, pv; vp, v_var] on every axis (tests; the filter starts from reset()).
  explicit AxisCovariance(const Eigen::Matrix2d& block) noexcept
      : pp_(block(0, 0)), pv_(block(0, 1)), vp_(block(1, 0)), vv_(block(1, 1)) {}
  // P = variance I (6x6).
  void reset(double variance) noexcept {
    pp_ = vv_ = variance;
    pv_ = vp_ = 0.0;
  }
  // P = F P F^T + Q, F = [I dt I; 0 I], Q = diag(dt^4 / 4, dt^2) accel_noise^2 per axis.
  void predict(double dt, double accel_noise) noexcept;
  // Correction with the legs' [p; v] measurement of noise variances position_var [m^2] and
  // velocity_var [m^2/s^2] per axis: returns K = P (P + R)^-1 and leaves P = (I - K) P,
  // symmetrized.
  AxisGain correct(double position_var, double velocity_var) noexcept;
  double velocity_variance() const noexcept { return vv_; }  // [m^2/s^2] P(v, v) of each axis
  Eigen::Matrix2d block() const noexcept { return (Eigen::Matrix2d() << pp_, pv_, vp_, vv_).finished(); }
  Eigen::Matrix<double, 6, 6> full() const noexcept;  // the 6x6 P (diagnostics, tests)

 private:
  double pp_ = 1.0, pv_ = 0.0, vp_ = 0.0, vv_ = 1.0;  // P = I until reset
};

}  // namespace kiloloop
