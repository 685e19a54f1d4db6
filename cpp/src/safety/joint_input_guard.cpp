#include "kiloloop/safety/joint_input_guard.hpp"

#include <cmath>

namespace kiloloop {

void JointInputGuard::configure(const RobotModel& model, double max_measurement_age) {
  nq_ = model.nq();
  gate_ = MeasurementGate(max_measurement_age);
  lower_ = model.lower();
  upper_ = model.upper();
  effort_ = model.effort_limit();
  last_valid_q_ = Eigen::VectorXd::Zero(nq_);
  q_ref_ = Eigen::VectorXd::Zero(nq_);
  has_valid_q_ = false;
}

Status JointInputGuard::check_measurement(const JointControlInput& in) noexcept {
  if (in.q.size() != nq_ || in.qd.size() != nq_) return Status::kBadSize;
  if (!in.q.allFinite() || !in.qd.allFinite()) return Status::kNonFiniteMeasurement;
  if (const Status age = gate_.check(in.t, in.stamp); failed(age)) return age;
  gate_.accept(in.stamp);
  last_valid_q_ = in.q;
  has_valid_q_ = true;
  return Status::kOk;
}

Status JointInputGuard::check_reference(const JointControlInput& in) noexcept {
  if (in.q_ref.size() != nq_ || in.qd_ref.size() != nq_ || in.qdd_ref.size() != nq_)
    return Status::kBadSize;
  if (!in.q_ref.allFinite() || !in.qd_ref.allFinite() || !in.qdd_ref.allFinite())
    return Status::kNonFiniteReference;
  q_ref_ = in.q_ref.cwiseMax(lower_).cwiseMin(upper_);
  return q_ref_ == in.q_ref ? Status::kOk : Status::kReferenceClamped;
}

Status JointInputGuard::hold(Dynamics& dyn, Status why, Eigen::Ref<Eigen::VectorXd> tau) noexcept {
  if (!has_valid_q_ || failed(dyn.gravity(last_valid_q_, tau))) tau.setZero();
  saturate(why, tau);
  return why;
}

Status JointInputGuard::damped_stop(Dynamics& dyn, const Eigen::VectorXd& kd,
                                    const JointControlInput& in, Status why,
                                    Eigen::Ref<Eigen::VectorXd> tau) noexcept {
  if (failed(dyn.gravity(in.q, tau))) tau.setZero();
  tau.noalias() -= kd.cwiseProduct(in.qd);
  saturate(why, tau);
  return why;
}

Status JointInputGuard::saturate(Status status, Eigen::Ref<Eigen::VectorXd> tau) const noexcept {
  return clip_effort(status, tau, effort_);
}

}  // namespace kiloloop

namespace kiloloop {

Status validate_joint_settings(const Eigen::VectorXd& kp, const Eigen::VectorXd& kd,
                               const Eigen::Vector3d& gravity, double max_measurement_age, int nq,
                               std::string* why) {
  Eigen::VectorXd unused;
  const char* msg = nullptr;
  if (!expand_gains(kp, nq, &unused)) msg = "kp must have 1 or nq finite, non-negative entries";
  else if (!expand_gains(kd, nq, &unused)) msg = "kd must have 1 or nq finite, non-negative entries";
  else if (!gravity.allFinite()) msg = "gravity must be finite";
  else if (!(max_measurement_age > 0.0)) msg = "max_measurement_age must be > 0";
  if (msg == nullptr) return Status::kOk;
  if (why) *why = msg;
  return Status::kInvalidConfig;
}

}  // namespace kiloloop
