#include "kiloloop/aerial/floating_base_rne.hpp"

#include <cmath>

namespace kiloloop {

Status FloatingBaseRne::configure(RobotModelPtr model, FloatingBaseRne* out, std::string* why) {
  if (!model || !model->has_chain()) {
    if (why) *why = "FloatingBaseRne: the model has no serial chain (load it with a tip link)";
    return Status::kModelError;
  }
  FloatingBaseRne r;
  r.model_ = model;
  r.nq_ = model->nq();
  // A copy of the chain to read the constants from: KDL::Joint caches its last pose in mutable
  // members, so two configures reading one model's chain from two threads would race. Every
  // tick runs on ChainRne's constants alone.
  const KDL::Chain chain = model->chain();
  const Status s = ChainRne::configure(chain, &r.rne_, why);
  if (s != Status::kOk) return s;
  *out = std::move(r);
  return Status::kOk;
}

Status FloatingBaseRne::compute(const VecRef& q, const VecRef& qd, const VecRef& qdd,
                                const BaseMotion& base, Eigen::Ref<Eigen::VectorXd> tau,
                                Vector6d* wrench_on_arm, Eigen::Vector3d* tip_position) noexcept {
  if (!model_) return Status::kNotConfigured;
  if (tau.size() == nq_) tau.setZero();
  if (wrench_on_arm) wrench_on_arm->setZero();
  if (q.size() != nq_ || qd.size() != nq_ || qdd.size() != nq_ || tau.size() != nq_)
    return Status::kBadSize;
  if (!q.allFinite() || !qd.allFinite() || !qdd.allFinite() || !base.v.allFinite() ||
      !base.omega.allFinite() || !base.specific_force.allFinite() || !base.alpha.allFinite())
    return Status::kNonFiniteMeasurement;

  // The body's twist and spatial acceleration in its own frame (see the header): the specific
  // force already carries -g, so gravity needs no separate term (KDL's RNE puts it in a0 too).
  const Eigen::Vector3d a_lin = base.specific_force - base.omega.cross(base.v);
  Vector6d root;
  rne_.inverse_dynamics(q.data(), qd.data(), qdd.data(), base.v, base.omega, a_lin, base.alpha, tau.data(),
                        root.data());
  if (wrench_on_arm) *wrench_on_arm = root;
  if (tip_position) rne_.last_tip_position(tip_position);
  return Status::kOk;
}

Status FloatingBaseRne::first_moment(const VecRef& q, Eigen::Vector3d* moment,
                                     double* mass) const noexcept {
  moment->setZero();
  *mass = 0.0;
  if (!model_) return Status::kNotConfigured;
  if (q.size() != nq_) return Status::kBadSize;
  if (!q.allFinite()) return Status::kNonFiniteMeasurement;
  rne_.first_moment(q.data(), moment, mass);
  return Status::kOk;
}

}  // namespace kiloloop
