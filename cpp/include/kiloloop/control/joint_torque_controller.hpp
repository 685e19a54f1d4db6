#pragma once
// The frame shared by the joint-space torque controllers: configure-time sizing, the step()
// contract (size check, bad-input policy of JointInputGuard, friction compensation, saturation,
// counters). A concrete controller only supplies its control law.
#include <string>

#include <Eigen/Core>

#include "kiloloop/control/joint_friction.hpp"
#include "kiloloop/control/joint_io.hpp"
#include "kiloloop/dynamics/dynamics.hpp"
#include "kiloloop/safety/joint_input_guard.hpp"

namespace kiloloop {

class JointTorqueController {
 public:
  JointTorqueController() = default;
  JointTorqueController(JointTorqueController&&) = default;
  JointTorqueController& operator=(JointTorqueController&&) = default;
  virtual ~JointTorqueController() = default;

  // out.tau must have size nq (make_output() gives one); otherwise kBadSize and out is untouched.
  // Never allocates, throws or reads a clock; tau is always finite and within effort limits.
  Status step(const JointControlInput& in, JointControlOutput& out) noexcept;

  int nq() const { return dyn_.nq(); }
  JointControlInput make_input() const { return make_joint_input(nq()); }
  JointControlOutput make_output() const { return make_joint_output(nq()); }
  const StatusCounters& counters() const { return counters_; }
  // Back to the state right after configure: no last valid position, no measurement order,
  // counters kept (they count since configure).
  void reset() noexcept { guard_.reset(); }

 protected:
  Status configure_common(const Eigen::VectorXd& kp, const Eigen::VectorXd& kd,
                          const Eigen::Vector3d& gravity, double max_measurement_age,
                          const JointFrictionConfig& friction, RobotModelPtr model,
                          std::string* why);
  // The law itself, on a validated measurement and a validated (clamped) reference q_ref.
  virtual Status law(const JointControlInput& in, const Eigen::VectorXd& q_ref,
                     Eigen::Ref<Eigen::VectorXd> tau) noexcept = 0;

  Dynamics dyn_;
  Eigen::VectorXd kp_, kd_;

 private:
  // The law, then the compensated joint friction on its torque (JointFriction).
  Status law_with_friction(const JointControlInput& in, Eigen::Ref<Eigen::VectorXd> tau) noexcept;

  JointInputGuard guard_;
  JointFriction friction_;
  StatusCounters counters_;
  bool configured_ = false;
};

}  // namespace kiloloop
