#include "kiloloop/aerial/floating_base_rne.hpp"
#include "kiloloop/model/kdl_eigen.hpp"

#include <cmath>

namespace kiloloop {

Status FloatingBaseRne::configure(RobotModelPtr model, FloatingBaseRne* out, std::string* why) {
  if (!model || !model->has_chain()) {
    if (why) *why = "FloatingBaseRne: the model has no serial chain (load it with a tip link)";
    return Status::kModelError;
  }
  FloatingBaseRne r;
  r.model_ = model;
  r.chain_ = std::make_shared<const KDL::Chain>(model->chain());
  r.nq_ = model->nq();
  const unsigned ns = model->chain().getNrOfSegments();
  r.X_.assign(ns, KDL::Frame::Identity());
  r.S_.assign(ns, KDL::Twist::Zero());
  r.v_.assign(ns, KDL::Twist::Zero());
  r.a_.assign(ns, KDL::Twist::Zero());
  r.f_.assign(ns, KDL::Wrench::Zero());
  *out = std::move(r);
  return Status::kOk;
}

Status FloatingBaseRne::compute(const VecRef& q, const VecRef& qd, const VecRef& qdd,
                                const BaseMotion& base, Eigen::Ref<Eigen::VectorXd> tau,
                                Vector6d* wrench_on_arm) noexcept {
  if (!model_) return Status::kNotConfigured;
  if (tau.size() == nq_) tau.setZero();
  if (wrench_on_arm) wrench_on_arm->setZero();
  if (q.size() != nq_ || qd.size() != nq_ || qdd.size() != nq_ || tau.size() != nq_)
    return Status::kBadSize;
  if (!q.allFinite() || !qd.allFinite() || !qdd.allFinite() || !base.v.allFinite() ||
      !base.omega.allFinite() || !base.specific_force.allFinite() || !base.alpha.allFinite())
    return Status::kNonFiniteMeasurement;

  const KDL::Chain& chain = *chain_;
  const unsigned ns = chain.getNrOfSegments();
  // The body's twist and spatial acceleration in its own frame (see the header): the specific
  // force already carries -g, so gravity needs no separate term (KDL's RNE puts it in a0 too).
  const KDL::Twist v_base(to_kdl(base.v), to_kdl(base.omega));
  const Eigen::Vector3d a_lin = base.specific_force - base.omega.cross(base.v);
  const KDL::Twist a_base(to_kdl(a_lin), to_kdl(base.alpha));

  // Inward pass (root to tip): KDL's, with the base's motion in place of a resting base.
  int j = 0;
  for (unsigned i = 0; i < ns; ++i) {
    const KDL::Segment& seg = chain.getSegment(i);
    double qi = 0.0, qdi = 0.0, qddi = 0.0;
    if (seg.getJoint().getType() != KDL::Joint::Fixed) {
      qi = q[j];
      qdi = qd[j];
      qddi = qdd[j];
      ++j;
    }
    X_[i] = seg.pose(qi);  // frame i in frame i-1
    const KDL::Twist vj = X_[i].M.Inverse(seg.twist(qi, qdi));
    S_[i] = X_[i].M.Inverse(seg.twist(qi, 1.0));
    const KDL::Twist& v_parent = i == 0 ? v_base : v_[i - 1];
    const KDL::Twist& a_parent = i == 0 ? a_base : a_[i - 1];
    v_[i] = X_[i].Inverse(v_parent) + vj;
    a_[i] = X_[i].Inverse(a_parent) + S_[i] * qddi + v_[i] * vj;
    const KDL::RigidBodyInertia& I = seg.getInertia();
    f_[i] = I * a_[i] + v_[i] * (I * v_[i]);
  }
  // Outward pass (tip to root): joint torques, and each segment's force handed to its parent.
  j = nq_ - 1;
  KDL::Wrench root = KDL::Wrench::Zero();
  for (int i = static_cast<int>(ns) - 1; i >= 0; --i) {
    const KDL::Segment& seg = chain.getSegment(i);
    if (seg.getJoint().getType() != KDL::Joint::Fixed) {
      tau[j] = KDL::dot(S_[i], f_[i]) + seg.getJoint().getInertia() * qdd[j];
      --j;
    }
    const KDL::Wrench in_parent = X_[i] * f_[i];
    if (i > 0) {
      f_[i - 1] = f_[i - 1] + in_parent;
    } else {
      root = in_parent;
    }
  }
  if (wrench_on_arm) {
    *wrench_on_arm << root.force.x(), root.force.y(), root.force.z(), root.torque.x(),
        root.torque.y(), root.torque.z();
  }
  return Status::kOk;
}

Status FloatingBaseRne::first_moment(const VecRef& q, Eigen::Vector3d* moment,
                                     double* mass) const noexcept {
  moment->setZero();
  *mass = 0.0;
  if (!model_) return Status::kNotConfigured;
  if (q.size() != nq_) return Status::kBadSize;
  if (!q.allFinite()) return Status::kNonFiniteMeasurement;
  const KDL::Chain& chain = *chain_;
  KDL::Frame T = KDL::Frame::Identity();
  int j = 0;
  for (unsigned i = 0; i < chain.getNrOfSegments(); ++i) {
    const KDL::Segment& seg = chain.getSegment(i);
    const bool moving = seg.getJoint().getType() != KDL::Joint::Fixed;
    T = T * seg.pose(moving ? q[j++] : 0.0);
    const double m = seg.getInertia().getMass();
    const KDL::Vector c = T * seg.getInertia().getCOG();
    *moment += m * Eigen::Vector3d(c.x(), c.y(), c.z());
    *mass += m;
  }
  return Status::kOk;
}

}  // namespace kiloloop
