#pragma once
// JointInputGuard: the shared bad-input policy of the joint-space torque controllers.
//   bad measurement (size, NaN/Inf, stale or out of order: MeasurementGate) -> hold: gravity
//       compensation at the last valid position (zero torque if none was ever seen);
//   bad reference (size, NaN/Inf)          -> damped stop: g(q) - Kd qd at the measured state;
//   reference outside the joint limits     -> clamped, status kReferenceClamped;
//   torque beyond the effort limits        -> clipped, status kSaturated (clip_effort).
#include <string>

#include <Eigen/Core>

#include "kiloloop/control/joint_io.hpp"
#include "kiloloop/control/rules.hpp"
#include "kiloloop/dynamics/dynamics.hpp"

namespace kiloloop {

class JointInputGuard {
 public:
  void configure(const RobotModel& model, double max_measurement_age);

  // Size, finiteness, age and order of q, qd. A valid q is remembered for the hold fallback.
  Status check_measurement(const JointControlInput& in) noexcept;
  // Size and finiteness of the reference; writes q_ref clamped to the position limits.
  Status check_reference(const JointControlInput& in) noexcept;
  const Eigen::VectorXd& clamped_q_ref() const { return q_ref_; }

  // Fallbacks; both write a finite tau of size nq and return `why`.
  Status hold(Dynamics& dyn, Status why, Eigen::Ref<Eigen::VectorXd> tau) noexcept;
  Status damped_stop(Dynamics& dyn, const Eigen::VectorXd& kd, const JointControlInput& in,
                     Status why, Eigen::Ref<Eigen::VectorXd> tau) noexcept;
  // clip_effort with the model's effort limits.
  Status saturate(Status status, Eigen::Ref<Eigen::VectorXd> tau) const noexcept;
  // Forgets the last valid position and the measurement order (a new run).
  void reset() noexcept {
    has_valid_q_ = false;
    gate_.reset();
  }

 private:
  int nq_ = 0;
  MeasurementGate gate_;
  Eigen::VectorXd lower_, upper_, effort_;
  Eigen::VectorXd last_valid_q_, q_ref_;
  bool has_valid_q_ = false;
};

// Former name of broadcast_gains (control/rules.hpp), kept for existing callers.
inline bool expand_gains(const Eigen::VectorXd& gains, int nq, Eigen::VectorXd* out) {
  return broadcast_gains(gains, nq, out);
}

}  // namespace kiloloop

namespace kiloloop {

// Shared settings check of the joint torque controllers: gains (1 or nq, finite, >= 0), finite
// gravity, positive measurement age.
Status validate_joint_settings(const Eigen::VectorXd& kp, const Eigen::VectorXd& kd,
                               const Eigen::Vector3d& gravity, double max_measurement_age, int nq,
                               std::string* why);

}  // namespace kiloloop
