#pragma once
// Computed-torque (inverse-dynamics) joint control:
//   tau = M(q) (qdd_ref + Kd (qd_ref - qd) + Kp (q_ref - q)) + C(q,qd) qd + g(q)
// evaluated as ONE recursive Newton-Euler pass, RNE(q, qd, v) with v the bracket above, which
// equals the expression exactly without forming M, C or g. With a perfect model the error obeys
// e'' + Kd e' + Kp e = 0 per joint. Torques are clipped to the model's effort limits.
#include <string>

#include <Eigen/Core>

#include "kiloloop/control/joint_friction.hpp"
#include "kiloloop/control/joint_torque_controller.hpp"

namespace kiloloop {

struct ComputedTorqueConfig {
  Eigen::VectorXd kp = Eigen::VectorXd::Constant(1, 900.0);  // (1 or nq) [1/s^2] stiffness
  Eigen::VectorXd kd = Eigen::VectorXd::Constant(1, 60.0);   // (1 or nq) [1/s]   damping
  Eigen::Vector3d gravity = Eigen::Vector3d(0.0, 0.0, -9.81);  // [m/s^2] in the chain root frame
  double max_measurement_age = 0.005;  // [s] older measurements trigger the hold fallback
  JointFrictionConfig friction;        // compensated joint friction (0: none)
};

Status validate(const ComputedTorqueConfig& config, int nq, std::string* why);

class ComputedTorqueController : public JointTorqueController {
 public:
  static Status configure(const ComputedTorqueConfig& config, RobotModelPtr model,
                          ComputedTorqueController* out, std::string* why);

 private:
  Status law(const JointControlInput& in, const Eigen::VectorXd& q_ref,
             Eigen::Ref<Eigen::VectorXd> tau) noexcept override;

  Eigen::VectorXd v_;  // (nq) commanded acceleration
};

}  // namespace kiloloop
