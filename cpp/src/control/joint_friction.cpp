#include "kiloloop/control/joint_friction.hpp"

#include <cmath>

#include "kiloloop/safety/joint_input_guard.hpp"

namespace kiloloop {

Status validate(const JointFrictionConfig& c, int nq, std::string* why) {
  Eigen::VectorXd unused;
  const char* msg = nullptr;
  if (!expand_gains(c.viscous, nq, &unused))
    msg = "friction.viscous must have 1 or nq finite, non-negative entries";
  else if (!expand_gains(c.coulomb, nq, &unused))
    msg = "friction.coulomb must have 1 or nq finite, non-negative entries";
  else if (!(c.smoothing_speed > 0.0) || !std::isfinite(c.smoothing_speed))
    msg = "friction.smoothing_speed must be finite and > 0";
  if (msg == nullptr) return Status::kOk;
  if (why) *why = msg;
  return Status::kInvalidConfig;
}

Status JointFriction::configure(const JointFrictionConfig& c, int nq, std::string* why) {
  const Status s = validate(c, nq, why);
  if (failed(s)) return s;
  expand_gains(c.viscous, nq, &viscous_);
  expand_gains(c.coulomb, nq, &coulomb_);
  inv_speed_ = 1.0 / c.smoothing_speed;
  active_ = viscous_.any() || coulomb_.any();
  return Status::kOk;
}

void JointFriction::add(const Eigen::VectorXd& qd, Eigen::Ref<Eigen::VectorXd> tau) const noexcept {
  if (!active_) return;  // bit-identical to a controller without friction compensation
  tau.array() += viscous_.array() * qd.array() + coulomb_.array() * (qd.array() * inv_speed_).tanh();
}

}  // namespace kiloloop
