#pragma once
// The rules every controller's step applies the same way, written once:
//
//   effort clipping   clip_effort: tau_i is clamped to [-effort_i, effort_i]; an entry that is
//                     not finite after clamping (NaN, or inf beyond an infinite limit) becomes 0,
//                     the one torque that is always safe, and the step fails (kSolverFailed) -
//                     a control law that produced it must not pass for "saturated".
//   measurement age   measurement_fresh: t and stamp finite and |t - stamp| <= max_age. A stamp
//                     from the future is as untrustworthy as an old one (clock skew or a corrupt
//                     stamp), so the test is symmetric. MeasurementGate adds the order rule: a
//                     sample older than one already acted on is stale too (time going
//                     backwards, a replayed or reordered packet); equal stamps are fine (a sensor
//                     slower than the loop).
//   gain broadcasting broadcast_gains: a gain given as one value applies to every joint, else
//                     one value per joint; finite and >= 0. Configure time only.
//
// Generic over the robot: any length of vector, fixed-size (Vector12d) or dynamic, through
// Eigen::Ref. Everything but broadcast_gains is noexcept and allocation-free.
#include <Eigen/Core>

#include "kiloloop/status.hpp"

namespace kiloloop {

// Clamps tau to +-effort (same length; an infinite limit leaves that joint unclamped). Returns
// `status` if nothing changed, worst(status, kSaturated) if an entry was clamped, and
// worst(status, kSolverFailed) if an entry was not finite (it is set to 0).
Status clip_effort(Status status, Eigen::Ref<Eigen::VectorXd> tau,
                   const Eigen::Ref<const Eigen::VectorXd>& effort) noexcept;

// True when t and stamp are finite and the sample is at most max_age [s] old or ahead.
inline bool measurement_fresh(double t, double stamp, double max_age) noexcept {
  const double age = t - stamp;  // NaN or inf when either is not finite, or the gap overflows
  return age <= max_age && age >= -max_age;
}

// measurement_fresh plus the order rule, for a controller that keeps state between ticks.
// check() classifies the tick; accept() records a measurement the step went on to use.
class MeasurementGate {
 public:
  explicit MeasurementGate(double max_age = 0.005) noexcept : max_age_(max_age) {}
  // kNonFiniteMeasurement (t or stamp NaN/inf), kStaleMeasurement (too old, from the future, or
  // older than the newest accepted stamp), else kOk.
  Status check(double t, double stamp) const noexcept;
  void accept(double stamp) noexcept {
    newest_ = stamp;
    has_newest_ = true;
  }
  void reset() noexcept { has_newest_ = false; }  // forget the order (a new run, a new clock)
  double max_age() const noexcept { return max_age_; }

 private:
  double max_age_;
  double newest_ = 0.0;  // [s] newest accepted stamp
  bool has_newest_ = false;
};

// One gain (broadcast) or out.size() gains, finite and >= 0, into out. False (out untouched) on
// a wrong size or a negative or non-finite gain.
bool broadcast_gains(const Eigen::Ref<const Eigen::VectorXd>& gains,
                     Eigen::Ref<Eigen::VectorXd> out) noexcept;
// The same into a vector sized n (allocates: configure time).
bool broadcast_gains(const Eigen::Ref<const Eigen::VectorXd>& gains, int n, Eigen::VectorXd* out);

}  // namespace kiloloop
