#include "kiloloop/aerial/rotor_allocation.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/LU>

namespace kiloloop {

Status validate(const RotorAllocationConfig& c, std::string* why) {
  auto fail = [why](const char* msg) {
    if (why) *why = std::string("RotorAllocationConfig: ") + msg;
    return Status::kInvalidConfig;
  };
  if (!c.positions.allFinite()) return fail("positions must be finite");
  for (int i = 0; i < 4; ++i)
    if (std::abs(c.spin[i]) != 1.0) return fail("spin must be +1 or -1 per rotor");
  if (!(std::isfinite(c.drag_coefficient) && c.drag_coefficient > 0))
    return fail("drag_coefficient must be > 0 (yaw needs it)");
  if (!(std::isfinite(c.thrust_min) && c.thrust_min >= 0)) return fail("thrust_min must be >= 0");
  if (!(std::isfinite(c.thrust_max) && c.thrust_max > c.thrust_min))
    return fail("thrust_max must exceed thrust_min");
  if (!(std::isfinite(c.time_constant) && c.time_constant >= 0))
    return fail("time_constant must be >= 0");
  if (!(std::isfinite(c.dt) && c.dt > 0)) return fail("dt must be > 0");
  return Status::kOk;
}

Status RotorAllocation::configure(const RotorAllocationConfig& config, RotorAllocation* out,
                                  std::string* why) {
  const Status s = validate(config, why);
  if (failed(s)) return s;
  RotorAllocation r;
  r.cfg_ = config;
  for (int i = 0; i < 4; ++i) {
    r.A_(0, i) = 1.0;
    r.A_(1, i) = config.positions(1, i);
    r.A_(2, i) = -config.positions(0, i);
    r.A_(3, i) = config.spin[i] * config.drag_coefficient;
  }
  Eigen::FullPivLU<Eigen::Matrix4d> lu(r.A_);
  if (!lu.isInvertible()) {
    if (why) *why = "RotorAllocationConfig: rotor layout cannot produce every wrench (A singular)";
    return Status::kInvalidConfig;
  }
  r.A_inv_ = lu.inverse();
  // Collective thrust must raise every rotor (true for any layout around the CoM); the
  // saturation handling shifts thrust along this column.
  if ((r.A_inv_.col(0).array() <= 0.0).any()) {
    if (why) *why = "RotorAllocationConfig: the rotors do not surround the body origin";
    return Status::kInvalidConfig;
  }
  r.configured_ = true;
  *out = r;
  return Status::kOk;
}

Status RotorAllocation::allocate(const Eigen::Vector4d& wrench, Eigen::Vector4d* thrust,
                                 Eigen::Vector4d* achieved) noexcept {
  const double lo = cfg_.thrust_min, hi = cfg_.thrust_max;
  if (!configured_) {
    thrust->setZero();
    if (achieved) achieved->setZero();
    return Status::kNotConfigured;
  }
  if (!wrench.allFinite()) {
    thrust->setConstant(lo);
    if (achieved) *achieved = A_ * *thrust;
    return Status::kNonFiniteReference;
  }
  Status status = Status::kOk;
  Eigen::Vector4d f = A_inv_ * wrench;
  const bool fits = (f.array() >= lo).all() && (f.array() <= hi).all();
  if (!fits) {
    status = Status::kSaturated;
    const Eigen::Vector4d u = A_inv_.col(0);  // thrust share per newton of collective
    Eigen::Vector4d f_rp = A_inv_.col(1) * wrench[1] + A_inv_.col(2) * wrench[2];
    // Roll/pitch alone wider than the thrust range: scale them down (the last resort).
    const double spread = f_rp.maxCoeff() - f_rp.minCoeff();
    if (spread > hi - lo) f_rp *= (hi - lo) / spread;
    // Collective thrust: the value nearest the command that keeps every rotor in range.
    double t_lo = -std::numeric_limits<double>::infinity();
    double t_hi = std::numeric_limits<double>::infinity();
    for (int i = 0; i < 4; ++i) {
      t_lo = std::max(t_lo, (lo - f_rp[i]) / u[i]);
      t_hi = std::min(t_hi, (hi - f_rp[i]) / u[i]);
    }
    const double collective =
        t_lo <= t_hi ? std::clamp(wrench[0], t_lo, t_hi) : 0.5 * (t_lo + t_hi);
    const Eigen::Vector4d base = f_rp + u * collective;
    // Yaw last: the largest share k in [0, 1] of its thrust pattern that stays in range.
    const Eigen::Vector4d f_yaw = A_inv_.col(3) * wrench[3];
    double k = 1.0;
    for (int i = 0; i < 4; ++i) {
      if (f_yaw[i] > 0) k = std::min(k, (hi - base[i]) / f_yaw[i]);
      if (f_yaw[i] < 0) k = std::min(k, (lo - base[i]) / f_yaw[i]);
    }
    k = std::clamp(k, 0.0, 1.0);
    f = base + k * f_yaw;
  }
  // Rounding only: after the steps above every thrust is in range up to a few ulps.
  f = f.cwiseMax(lo).cwiseMin(hi);
  if (achieved) *achieved = A_ * f;
  Eigen::Vector4d command = f;
  if (cfg_.lag_compensation && have_prev_) {
    command = (f + (cfg_.time_constant / cfg_.dt) * (f - prev_)).cwiseMax(lo).cwiseMin(hi);
  }
  prev_ = f;
  have_prev_ = true;
  *thrust = command;
  return status;
}

}  // namespace kiloloop
