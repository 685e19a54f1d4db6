#pragma once
// Joint friction a joint torque controller compensates (feed-forward): viscous b * qd plus
// Coulomb fc * tanh(qd / v_s), evaluated on the *reference* velocity: it is known ahead and clean,
// where the measured one is noisy and would make the Coulomb term chatter at rest. The values come
// from the robot's URDF (<dynamics damping friction>) through its robot file; 0 turns it off.
#include <string>

#include <Eigen/Core>

#include "kiloloop/status.hpp"

namespace kiloloop {

struct JointFrictionConfig {
  Eigen::VectorXd viscous = Eigen::VectorXd::Zero(1);  // (1 or nq) [N m s/rad] damping b
  Eigen::VectorXd coulomb = Eigen::VectorXd::Zero(1);  // (1 or nq) [N m] dry friction fc
  double smoothing_speed = 0.01;  // [rad/s] v_s: the Coulomb term reaches 76 % of fc at v_s
};

Status validate(const JointFrictionConfig& config, int nq, std::string* why);

class JointFriction {
 public:
  // Sizes the per-joint values (allocates); fails like validate().
  Status configure(const JointFrictionConfig& config, int nq, std::string* why);
  // tau += b .* qd + fc .* tanh(qd / v_s). Allocation-free; qd must have size nq.
  void add(const Eigen::VectorXd& qd, Eigen::Ref<Eigen::VectorXd> tau) const noexcept;
  bool active() const { return active_; }

 private:
  Eigen::VectorXd viscous_, coulomb_;
  double inv_speed_ = 100.0;  // [s/rad]
  bool active_ = false;
};

}  // namespace kiloloop
