#include "kiloloop/control/rules.hpp"

#include <cmath>

namespace kiloloop {

Status clip_effort(Status status, Eigen::Ref<Eigen::VectorXd> tau,
                   const Eigen::Ref<const Eigen::VectorXd>& effort) noexcept {
  bool clipped = false, lost = false;
  const Eigen::Index n = tau.size() < effort.size() ? tau.size() : effort.size();
  for (Eigen::Index i = 0; i < n; ++i) {
    // fmax/fmin would turn NaN into a limit; test it first. On a non-NaN v the two comparisons
    // below give fmin(fmax(v, -e), e) (up to the sign of a zero torque under a zero limit; a NaN
    // limit leaves v, as fmax/fmin do), inline instead of two libm calls per joint and tick.
    double v = tau[i];
    if (std::isnan(v)) {
      v = 0.0;
      lost = true;
    } else {
      const double e = effort[i];
      if (v < -e) v = -e;
      if (v > e) v = e;
      if (!std::isfinite(v)) {
        v = 0.0;
        lost = true;
      }
    }
    clipped |= v != tau[i];
    tau[i] = v;
  }
  if (lost) return worst(status, Status::kSolverFailed);
  return clipped ? worst(status, Status::kSaturated) : status;
}

Status MeasurementGate::check(double t, double stamp) const noexcept {
  if (!std::isfinite(t) || !std::isfinite(stamp)) return Status::kNonFiniteMeasurement;
  if (!measurement_fresh(t, stamp, max_age_)) return Status::kStaleMeasurement;
  if (has_newest_ && stamp < newest_) return Status::kStaleMeasurement;
  return Status::kOk;
}

bool broadcast_gains(const Eigen::Ref<const Eigen::VectorXd>& gains,
                     Eigen::Ref<Eigen::VectorXd> out) noexcept {
  if (gains.size() != 1 && gains.size() != out.size()) return false;
  if (!gains.allFinite() || (gains.array() < 0.0).any()) return false;
  if (gains.size() == 1) out.setConstant(gains[0]);
  else out = gains;
  return true;
}

bool broadcast_gains(const Eigen::Ref<const Eigen::VectorXd>& gains, int n, Eigen::VectorXd* out) {
  if (n < 0) return false;
  Eigen::VectorXd v(n);
  if (!broadcast_gains(gains, v)) return false;
  *out = std::move(v);
  return true;
}

}  // namespace kiloloop
