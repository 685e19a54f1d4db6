#include "kiloloop/control/joint_torque_controller.hpp"

#include "kiloloop/control/rules.hpp"

namespace kiloloop {

Status JointTorqueController::configure_common(const Eigen::VectorXd& kp, const Eigen::VectorXd& kd,
                                               const Eigen::Vector3d& gravity,
                                               double max_measurement_age,
                                               const JointFrictionConfig& friction,
                                               RobotModelPtr model, std::string* why) {
  if (!model) {
    if (why) *why = "model is null";
    return Status::kModelError;
  }
  Status s = validate_joint_settings(kp, kd, gravity, max_measurement_age, model->nq(), why);
  if (failed(s)) return s;
  s = friction_.configure(friction, model->nq(), why);
  if (failed(s)) return s;
  s = Dynamics::configure(model, gravity, &dyn_, why);
  if (failed(s)) return s;
  broadcast_gains(kp, model->nq(), &kp_);
  broadcast_gains(kd, model->nq(), &kd_);
  guard_.configure(*model, max_measurement_age);
  counters_ = StatusCounters{};
  configured_ = true;
  return Status::kOk;
}

Status JointTorqueController::law_with_friction(const JointControlInput& in,
                                               Eigen::Ref<Eigen::VectorXd> tau) noexcept {
  const Status l = law(in, guard_.clamped_q_ref(), tau);
  if (!failed(l)) friction_.add(in.qd_ref, tau);  // plus the friction it must overcome
  return l;
}

Status JointTorqueController::step(const JointControlInput& in, JointControlOutput& out) noexcept {
  if (!configured_) return out.status = Status::kNotConfigured;
  Status s;
  if (out.tau.size() != dyn_.nq()) {
    s = Status::kBadSize;  // nowhere safe to write: report only
  } else if (const Status m = guard_.check_measurement(in); failed(m)) {
    s = guard_.hold(dyn_, m, out.tau);
  } else if (const Status r = guard_.check_reference(in); failed(r)) {
    s = guard_.damped_stop(dyn_, kd_, in, r, out.tau);
  } else if (const Status l = law_with_friction(in, out.tau); failed(l)) {
    s = guard_.hold(dyn_, l, out.tau);
  } else if (!out.tau.allFinite()) {
    // Finite inputs whose torque overflows (huge references or velocities): no usable law.
    s = guard_.hold(dyn_, Status::kSolverFailed, out.tau);
  } else {
    s = guard_.saturate(worst(r, l), out.tau);
  }
  counters_.record(s);
  return out.status = s;
}

}  // namespace kiloloop
