#include "kiloloop/control/joint_torque_controller.hpp"

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
  expand_gains(kp, model->nq(), &kp_);
  expand_gains(kd, model->nq(), &kd_);
  guard_.configure(*model, max_measurement_age);
  counters_ = StepCounters{};
  configured_ = true;
  return Status::kOk;
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
  } else if (const Status l = law(in, guard_.clamped_q_ref(), out.tau); failed(l)) {
    s = guard_.hold(dyn_, l, out.tau);
  } else {
    friction_.add(in.qd_ref, out.tau);  // the law's torque plus the friction it must overcome
    s = guard_.saturate(worst(r, l), out.tau);
  }
  counters_.record(s);
  return out.status = s;
}

}  // namespace kiloloop
