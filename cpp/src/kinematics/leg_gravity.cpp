#include "kiloloop/kinematics/leg_gravity.hpp"

namespace kiloloop {

Status LegGravity::configure(const RobotModel& model, const std::string& trunk, const std::string& foot,
                             LegGravity* out, std::string* why) {
  KDL::Chain chain;
  if (!model.tree().getChain(trunk, foot, chain) || chain.getNrOfJoints() != 3) {
    if (why) *why = "leg '" + foot + "': no 3-joint chain from '" + trunk + "'";
    return Status::kModelError;
  }
  LegGravity g;
  const Status s = ChainRne::configure(chain, &g.rne_, why);
  if (s != Status::kOk) return s;
  *out = std::move(g);
  return Status::kOk;
}

Eigen::Vector3d LegGravity::torque(const Eigen::Vector3d& q, const Eigen::Vector3d& gravity_trunk,
                                   const Eigen::Vector3d* cos_q, const Eigen::Vector3d* sin_q) noexcept {
  Eigen::Vector3d tau;
  rne_.gravity_torque(q.data(), gravity_trunk, tau.data(), cos_q ? cos_q->data() : nullptr,
                      sin_q ? sin_q->data() : nullptr);
  return tau;
}

}  // namespace kiloloop
