#include "kiloloop/quadruped/axis_covariance.hpp"

#include <cmath>

namespace kiloloop {

void AxisCovariance::predict(double dt, double accel_noise) noexcept {
  // F P: the position row gains dt times the velocity row.
  const double fp_pp = pp_ + dt * vp_, fp_pv = pv_ + dt * vv_;
  // (F P) F^T + Q; Q's entries as the 6x6 code formed them (left to right).
  const double qa = accel_noise * accel_noise;
  const double q_p = 0.25 * dt * dt * dt * dt * qa, q_v = dt * dt * qa;
  pp_ = (fp_pp + fp_pv * dt) + q_p;
  pv_ = fp_pv;
  vp_ = vp_ + vv_ * dt;
  vv_ = vv_ + q_v;
}

AxisGain AxisCovariance::correct(double position_var, double velocity_var) noexcept {
  // S = P + R.
  const double s11 = pp_ + position_var, s12 = pv_, s21 = vp_, s22 = vv_ + velocity_var;
  // S^-1 as PartialPivLU: the pivot is the larger of |s11|, |s21| (the first on a tie); an
  // exactly zero pivot is left undivided.
  const bool swap = std::abs(s21) > std::abs(s11);
  const double u11 = swap ? s21 : s11, u12 = swap ? s22 : s12;
  const double below = swap ? s11 : s21, below2 = swap ? s12 : s22;
  const double l = u11 != 0.0 ? below / u11 : below;
  const double u22 = below2 - l * u12;
  const double inv11 = 1.0 / u11, inv22 = 1.0 / u22;
  // Columns of the permuted identity, then L y = b (unit lower), then U x = y (upper, bottom up).
  auto solve = [&](double b1, double b2, double* x1, double* x2) {
    const double y2 = b2 - b1 * l;
    *x2 = y2 * inv22;
    *x1 = (b1 - *x2 * u12) * inv11;
  };
  double i11, i21, i12, i22;  // S^-1
  solve(swap ? 0.0 : 1.0, swap ? 1.0 : 0.0, &i11, &i21);
  solve(swap ? 1.0 : 0.0, swap ? 0.0 : 1.0, &i12, &i22);
  AxisGain k;
  k.pp = pp_ * i11 + pv_ * i21;
  k.pv = pp_ * i12 + pv_ * i22;
  k.vp = vp_ * i11 + vv_ * i21;
  k.vv = vp_ * i12 + vv_ * i22;
  // P = (I - K) P.
  const double a11 = 1.0 - k.pp, a12 = -k.pv, a21 = -k.vp, a22 = 1.0 - k.vv;
  const double n11 = a11 * pp_ + a12 * vp_, n12 = a11 * pv_ + a12 * vv_;
  const double n21 = a21 * pp_ + a22 * vp_, n22 = a21 * pv_ + a22 * vv_;
  // 0.5 (P + P^T) in place, column by column: the lower entry first, the upper one from it.
  pp_ = 0.5 * (n11 + n11);
  vp_ = 0.5 * (n21 + n12);
  pv_ = 0.5 * (n12 + vp_);
  vv_ = 0.5 * (n22 + n22);
  return k;
}

Eigen::Matrix<double, 6, 6> AxisCovariance::full() const noexcept {
  Eigen::Matrix<double, 6, 6> P = Eigen::Matrix<double, 6, 6>::Zero();
  for (int a = 0; a < 3; ++a) {
    P(a, a) = pp_;
    P(a, a + 3) = pv_;
    P(a + 3, a) = vp_;
    P(a + 3, a + 3) = vv_;
  }
  return P;
}

}  // namespace kiloloop
