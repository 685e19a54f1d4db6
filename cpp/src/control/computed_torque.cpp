#include "kiloloop/control/computed_torque.hpp"

namespace kiloloop {

Status validate(const ComputedTorqueConfig& c, int nq, std::string* why) {
  const Status s = validate_joint_settings(c.kp, c.kd, c.gravity, c.max_measurement_age, nq, why);
  return failed(s) ? s : validate(c.friction, nq, why);
}

Status ComputedTorqueController::configure(const ComputedTorqueConfig& config, RobotModelPtr model,
                                           ComputedTorqueController* out, std::string* why) {
  ComputedTorqueController c;
  const Status s = c.configure_common(config.kp, config.kd, config.gravity,
                                      config.max_measurement_age, config.friction, std::move(model), why);
  if (failed(s)) return s;
  c.v_ = Eigen::VectorXd::Zero(c.nq());
  *out = std::move(c);
  return s;
}

Status ComputedTorqueController::law(const JointControlInput& in, const Eigen::VectorXd& q_ref,
                                     Eigen::Ref<Eigen::VectorXd> tau) noexcept {
  // Commanded acceleration, then tau = M v + C qd + g in a single RNE pass.
  v_ = in.qdd_ref + kd_.cwiseProduct(in.qd_ref - in.qd) + kp_.cwiseProduct(q_ref - in.q);
  return dyn_.inverse_dynamics(in.q, in.qd, v_, tau);
}

}  // namespace kiloloop
