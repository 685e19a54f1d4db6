#include "kiloloop/dynamics/dynamics.hpp"

#include <kdl/frames.hpp>

namespace kiloloop {

Status Dynamics::configure(RobotModelPtr model, const Eigen::Vector3d& gravity, Dynamics* out,
                           std::string* why) {
  if (!model || !model->has_chain()) {
    if (why) *why = "Dynamics needs a serial chain: load the model with a tip link";
    return Status::kModelError;
  }
  if (!gravity.allFinite()) {
    if (why) *why = "gravity must be finite";
    return Status::kInvalidConfig;
  }
  Dynamics d;
  d.model_ = std::move(model);
  d.nq_ = d.model_->nq();
  d.gravity_ = gravity;
  d.chain_ = std::make_unique<KDL::Chain>(d.model_->chain());
  const KDL::Chain& chain = *d.chain_;
  const KDL::Vector g(gravity.x(), gravity.y(), gravity.z());
  d.fk_ = std::make_unique<KDL::ChainFkSolverPos_recursive>(chain);
  d.jac_ = std::make_unique<KDL::ChainJntToJacSolver>(chain);
  d.rne_ = std::make_unique<KDL::ChainIdSolver_RNE>(chain, g);
  d.dyn_ = std::make_unique<KDL::ChainDynParam>(chain, g);
  d.use_own_rne_ = ChainRne::configure(chain, &d.own_rne_, nullptr) == Status::kOk;
  d.q_.resize(d.nq_);
  d.qd_.resize(d.nq_);
  d.qdd_.resize(d.nq_);
  d.tau_.resize(d.nq_);
  d.no_external_wrench_.assign(chain.getNrOfSegments(), KDL::Wrench::Zero());
  d.M_.resize(d.nq_);
  d.J_.resize(d.nq_);
  *out = std::move(d);
  return Status::kOk;
}

Status Dynamics::load(const VecRef& q) noexcept {
  if (!rne_) return Status::kNotConfigured;
  if (q.size() != nq_) return Status::kBadSize;
  if (!q.allFinite()) return Status::kNonFiniteMeasurement;
  q_.data = q;
  return Status::kOk;
}

Status Dynamics::load(const VecRef& q, const VecRef& qd) noexcept {
  const Status s = load(q);
  if (s != Status::kOk) return s;
  if (qd.size() != nq_) return Status::kBadSize;
  if (!qd.allFinite()) return Status::kNonFiniteMeasurement;
  qd_.data = qd;
  return Status::kOk;
}

Status Dynamics::inverse_dynamics(const VecRef& q, const VecRef& qd, const VecRef& qdd,
                                  Eigen::Ref<Eigen::VectorXd> tau) noexcept {
  // load()'s checks in load()'s order, without its copies into the KDL arrays: our own pass
  // reads the caller's contiguous vectors (a computed-torque step calls this every tick).
  if (!rne_) return Status::kNotConfigured;
  if (q.size() != nq_) return Status::kBadSize;
  if (!q.allFinite()) return Status::kNonFiniteMeasurement;
  if (qd.size() != nq_) return Status::kBadSize;
  if (!qd.allFinite()) return Status::kNonFiniteMeasurement;
  if (qdd.size() != nq_ || tau.size() != nq_) return Status::kBadSize;
  if (!qdd.allFinite()) return Status::kNonFiniteReference;
  if (use_own_rne_) {
    own_rne_.inverse_dynamics(q.data(), qd.data(), qdd.data(), gravity_, tau_.data.data());
  } else {
    q_.data = q;
    qd_.data = qd;
    qdd_.data = qdd;
    if (rne_->CartToJnt(q_, qd_, qdd_, no_external_wrench_, tau_) < 0) return Status::kSolverFailed;
  }
  tau = tau_.data;
  return Status::kOk;
}

Status Dynamics::mass_matrix(const VecRef& q, Eigen::Ref<Eigen::MatrixXd> M) noexcept {
  const Status s = load(q);
  if (s != Status::kOk) return s;
  if (M.rows() != nq_ || M.cols() != nq_) return Status::kBadSize;
  if (dyn_->JntToMass(q_, M_) < 0) return Status::kSolverFailed;
  M = M_.data;
  return Status::kOk;
}

Status Dynamics::coriolis(const VecRef& q, const VecRef& qd, Eigen::Ref<Eigen::VectorXd> c) noexcept {
  const Status s = load(q, qd);
  if (s != Status::kOk) return s;
  if (c.size() != nq_) return Status::kBadSize;
  if (dyn_->JntToCoriolis(q_, qd_, tau_) < 0) return Status::kSolverFailed;
  c = tau_.data;
  return Status::kOk;
}

Status Dynamics::gravity(const VecRef& q, Eigen::Ref<Eigen::VectorXd> g) noexcept {
  const Status s = load(q);
  if (s != Status::kOk) return s;
  if (g.size() != nq_) return Status::kBadSize;
  if (dyn_->JntToGravity(q_, tau_) < 0) return Status::kSolverFailed;
  g = tau_.data;
  return Status::kOk;
}

Status Dynamics::forward_kinematics(const VecRef& q, Eigen::Ref<Eigen::Matrix4d> T) noexcept {
  const Status s = load(q);
  if (s != Status::kOk) return s;
  KDL::Frame f;
  if (fk_->JntToCart(q_, f) < 0) return Status::kSolverFailed;
  T.setIdentity();
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) T(r, c) = f.M(r, c);
    T(r, 3) = f.p(r);
  }
  return Status::kOk;
}

Status Dynamics::jacobian(const VecRef& q, Eigen::Ref<Eigen::MatrixXd> J) noexcept {
  const Status s = load(q);
  if (s != Status::kOk) return s;
  if (J.rows() != 6 || J.cols() != nq_) return Status::kBadSize;
  if (jac_->JntToJac(q_, J_) < 0) return Status::kSolverFailed;
  J = J_.data;
  return Status::kOk;
}

}  // namespace kiloloop
