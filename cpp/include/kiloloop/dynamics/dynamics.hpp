#pragma once
// Dynamics: the mutable workspace over a RobotModel's serial chain. Everything a control law
// needs (FK, Jacobian, RNE inverse dynamics, M, C(q,qd)qd, g) through KDL's solvers, with all
// KDL arrays sized at configure: every call below is noexcept and allocation-free.
//
// Frames: poses and Jacobians are of the chain tip in the chain root frame; Jacobian rows are
// [linear; angular] with the reference point at the tip (KDL's convention).
#include <memory>
#include <string>

#include <Eigen/Core>
#include <kdl/chaindynparam.hpp>
#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/chainidsolver_recursive_newton_euler.hpp>
#include <kdl/chainjnttojacsolver.hpp>

#include "kiloloop/dynamics/chain_rne.hpp"
#include "kiloloop/model/robot_model.hpp"
#include "kiloloop/status.hpp"

namespace kiloloop {

class Dynamics {
 public:
  using VecRef = Eigen::Ref<const Eigen::VectorXd>;

  Dynamics() = default;
  // Fails with kModelError when the model has no serial chain (pass a tip when loading it).
  static Status configure(RobotModelPtr model, const Eigen::Vector3d& gravity, Dynamics* out,
                          std::string* why);

  int nq() const { return nq_; }
  const RobotModel& model() const { return *model_; }
  const RobotModelPtr& model_ptr() const { return model_; }
  const Eigen::Vector3d& gravity_vector() const { return gravity_; }

  // tau = M(q) qdd + C(q,qd) qd + g(q), one recursive Newton-Euler pass (ChainRne; KDL's
  // ChainIdSolver_RNE where ChainRne refuses the chain). [N m] (nq)
  Status inverse_dynamics(const VecRef& q, const VecRef& qd, const VecRef& qdd,
                          Eigen::Ref<Eigen::VectorXd> tau) noexcept;
  Status mass_matrix(const VecRef& q, Eigen::Ref<Eigen::MatrixXd> M) noexcept;           // (nq,nq)
  Status coriolis(const VecRef& q, const VecRef& qd, Eigen::Ref<Eigen::VectorXd> c) noexcept;  // C qd
  Status gravity(const VecRef& q, Eigen::Ref<Eigen::VectorXd> g) noexcept;               // (nq)
  Status forward_kinematics(const VecRef& q, Eigen::Ref<Eigen::Matrix4d> T) noexcept;    // T_root_tip
  Status jacobian(const VecRef& q, Eigen::Ref<Eigen::MatrixXd> J) noexcept;              // (6,nq)

 private:
  // Copies q (and optionally qd, qdd) into the KDL arrays after checking size and finiteness.
  Status load(const VecRef& q) noexcept;
  Status load(const VecRef& q, const VecRef& qd) noexcept;

  RobotModelPtr model_;
  // This workspace's own copy of the chain, which the KDL solvers reference (a stable heap
  // address across moves): KDL::Joint caches its last pose in mutable members, so workspaces
  // sharing one model's chain across threads would race (found by the native batch runner).
  std::unique_ptr<KDL::Chain> chain_;
  int nq_ = 0;
  Eigen::Vector3d gravity_ = Eigen::Vector3d(0.0, 0.0, -9.81);
  std::unique_ptr<KDL::ChainFkSolverPos_recursive> fk_;
  std::unique_ptr<KDL::ChainJntToJacSolver> jac_;
  std::unique_ptr<KDL::ChainIdSolver_RNE> rne_;
  ChainRne own_rne_;          // the inverse-dynamics pass, about half of rne_'s cost (chain_rne.hpp)
  bool use_own_rne_ = false;  // false: a joint with a scale/offset ChainRne does not model
  std::unique_ptr<KDL::ChainDynParam> dyn_;
  KDL::JntArray q_, qd_, qdd_, tau_;
  KDL::Wrenches no_external_wrench_;
  KDL::JntSpaceInertiaMatrix M_;
  KDL::Jacobian J_;
};

}  // namespace kiloloop
