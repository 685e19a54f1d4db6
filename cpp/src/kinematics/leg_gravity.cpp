#include "kiloloop/kinematics/leg_gravity.hpp"

namespace kiloloop {

Status LegGravity::configure(const RobotModel& model, const std::string& trunk, const std::string& foot,
                             LegGravity* out, std::string* why) {
  LegGravity g;
  g.chain_ = std::make_unique<KDL::Chain>();
  if (!model.tree().getChain(trunk, foot, *g.chain_) || g.chain_->getNrOfJoints() != 3) {
    if (why) *why = "leg '" + foot + "': no 3-joint chain from '" + trunk + "'";
    return Status::kModelError;
  }
  for (int k = 0; k < 3; ++k) {
    KDL::Vector unit = KDL::Vector::Zero();
    unit(k) = 1.0;
    g.unit_[k] = std::make_unique<KDL::ChainDynParam>(*g.chain_, unit);
  }
  g.q_.resize(3);
  g.tau_.resize(3);
  *out = std::move(g);
  return Status::kOk;
}

Eigen::Vector3d LegGravity::torque(const Eigen::Vector3d& q, const Eigen::Vector3d& gravity_trunk) noexcept {
  q_.data = q;
  Eigen::Vector3d tau = Eigen::Vector3d::Zero();
  for (int k = 0; k < 3; ++k) {
    unit_[k]->JntToGravity(q_, tau_);
    tau += gravity_trunk[k] * tau_.data;
  }
  return tau;
}

}  // namespace kiloloop
