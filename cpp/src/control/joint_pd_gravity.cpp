#include "kiloloop/control/joint_pd_gravity.hpp"

namespace kiloloop {

Status validate(const JointPdGravityConfig& c, int nq, std::string* why) {
  const Status s = validate_joint_settings(c.kp, c.kd, c.gravity, c.max_measurement_age, nq, why);
  return failed(s) ? s : validate(c.friction, nq, why);
}

Status JointPdGravityController::configure(const JointPdGravityConfig& config, RobotModelPtr model,
                                           JointPdGravityController* out, std::string* why) {
  JointPdGravityController c;
  const Status s = c.configure_common(config.kp, config.kd, config.gravity,
                                      config.max_measurement_age, config.friction, std::move(model), why);
  if (failed(s)) return s;
  *out = std::move(c);
  return s;
}

Status JointPdGravityController::law(const JointControlInput& in, const Eigen::VectorXd& q_ref,
                                     Eigen::Ref<Eigen::VectorXd> tau) noexcept {
  const Status s = dyn_.gravity(in.q, tau);
  if (failed(s)) return s;
  tau += kp_.cwiseProduct(q_ref - in.q) + kd_.cwiseProduct(in.qd_ref - in.qd);
  return s;
}

}  // namespace kiloloop
