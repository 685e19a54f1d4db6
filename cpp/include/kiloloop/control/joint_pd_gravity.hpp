#pragma once
// Joint PD with gravity compensation:
//   tau = Kp (q_ref - q) + Kd (qd_ref - qd) + g(q)
// The classic regulator (asymptotically stable for constant q_ref with any positive gains); it
// ignores inertia and Coriolis terms, so it lags on fast trajectories where computed torque
// does not. Torques are clipped to the model's effort limits.
#include <string>

#include <Eigen/Core>

#include "kiloloop/control/joint_friction.hpp"
#include "kiloloop/control/joint_torque_controller.hpp"

namespace kiloloop {

struct JointPdGravityConfig {
  Eigen::VectorXd kp = Eigen::VectorXd::Constant(1, 500.0);  // (1 or nq) [N m/rad]
  Eigen::VectorXd kd = Eigen::VectorXd::Constant(1, 50.0);   // (1 or nq) [N m s/rad]
  Eigen::Vector3d gravity = Eigen::Vector3d(0.0, 0.0, -9.81);  // [m/s^2] in the chain root frame
  double max_measurement_age = 0.005;  // [s] older measurements trigger the hold fallback
  JointFrictionConfig friction;        // compensated joint friction (0: none)
};

Status validate(const JointPdGravityConfig& config, int nq, std::string* why);

class JointPdGravityController : public JointTorqueController {
 public:
  static Status configure(const JointPdGravityConfig& config, RobotModelPtr model,
                          JointPdGravityController* out, std::string* why);

 private:
  Status law(const JointControlInput& in, const Eigen::VectorXd& q_ref,
             Eigen::Ref<Eigen::VectorXd> tau) noexcept override;
};

}  // namespace kiloloop
