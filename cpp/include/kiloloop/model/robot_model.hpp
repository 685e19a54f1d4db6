#pragma once
// RobotModel: the immutable description of a robot (KDL tree, the serial chain a controller uses,
// joint names and limits). Built once at init, from URDF (kiloloop/urdf/) or a DH table
// (model/dh.hpp), then shared read-only by any number of workspaces (Dynamics, controllers).
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <kdl/chain.hpp>
#include <kdl/tree.hpp>

#include "kiloloop/model/chain_folding.hpp"
#include "kiloloop/status.hpp"

namespace kiloloop {

// Limits of one joint; a missing limit is +-infinity.
struct JointLimit {
  double lower = -std::numeric_limits<double>::infinity();  // [rad] or [m]
  double upper = std::numeric_limits<double>::infinity();   // [rad] or [m]
  double velocity = std::numeric_limits<double>::infinity();  // [rad/s] or [m/s]
  double effort = std::numeric_limits<double>::infinity();    // [N m] or [N]
};

class RobotModel {
 public:
  // Builds the model from a KDL tree. `root`/`tip` select a serial chain (root defaults to the
  // tree's base link, tip to the only leaf when the tree does not branch); `root` must be an
  // ancestor of `tip`. Every subtree hanging off the chain (beyond the tip, or branching from a
  // chain link) is folded into the chain as rigid mass, its movable joints at `locked` (joint
  // name -> position [rad] or [m], absent: 0); see model/chain_folding.hpp. Limits are looked up
  // by joint name. Fails with a reason naming the link or joint at fault.
  static Status create(const KDL::Tree& tree, const std::string& root, const std::string& tip,
                       const std::map<std::string, JointLimit>& limits,
                       const std::map<std::string, double>& locked, RobotModel* out,
                       std::string* why);
  // As above with every off-chain joint at 0.
  static Status create(const KDL::Tree& tree, const std::string& root, const std::string& tip,
                       const std::map<std::string, JointLimit>& limits, RobotModel* out,
                       std::string* why);

  // A copy whose chain joints carry reflected rotor inertia (armature) [kg m^2], one finite value
  // >= 0 per joint: KDL's joint inertia, which every Dynamics solver (KDL's RNE and ChainDynParam,
  // ChainRne) adds to M's diagonal and as a * qdd to the torque; the plant's MuJoCo armature. The
  // tree is kept as loaded. Needs a chain; the chain's joints must have scale 1 and offset 0 (all
  // that the URDF and DH builders make). Fails naming the joint.
  Status with_armature(const Eigen::VectorXd& armature, RobotModel* out, std::string* why) const;
  // (nq) [kg m^2] the chain joints' armature (zeros unless with_armature set it).
  Eigen::VectorXd armature() const;

  int nq() const { return static_cast<int>(joint_names_.size()); }
  bool has_chain() const { return has_chain_; }
  const KDL::Tree& tree() const { return tree_; }
  // The serial chain root -> tip with the off-chain mass folded in; empty unless has_chain().
  const KDL::Chain& chain() const { return chain_; }
  // The links folded into the chain (empty without a chain), in tree order per chain segment.
  const std::vector<FoldedLink>& folded() const { return folded_; }
  // The off-chain joint positions the folding used (as given to create).
  const std::map<std::string, double>& locked() const { return locked_; }
  const std::string& root_name() const { return root_; }
  const std::string& tip_name() const { return tip_; }
  const std::vector<std::string>& joint_names() const { return joint_names_; }
  const Eigen::VectorXd& lower() const { return lower_; }      // (nq)
  const Eigen::VectorXd& upper() const { return upper_; }      // (nq)
  const Eigen::VectorXd& velocity_limit() const { return velocity_; }  // (nq)
  const Eigen::VectorXd& effort_limit() const { return effort_; }      // (nq)
  // Total mass of every segment in the tree [kg], root-link inertia included when restored
  // (the tree is kept as loaded; only the chain carries folded mass).
  double total_mass() const;
  // True when the URDF root link carried an inertia that kdl_parser would have dropped and the
  // loader restored it as a fixed segment (see kiloloop/urdf/urdf_loader.hpp).
  bool root_inertia_restored() const { return root_inertia_restored_; }
  void set_root_inertia_restored(bool v) { root_inertia_restored_ = v; }

 private:
  KDL::Tree tree_{"root"};
  KDL::Chain chain_;
  bool has_chain_ = false;
  bool root_inertia_restored_ = false;
  std::string root_, tip_;
  std::vector<std::string> joint_names_;
  std::vector<FoldedLink> folded_;
  std::map<std::string, double> locked_;
  Eigen::VectorXd lower_, upper_, velocity_, effort_;
};

using RobotModelPtr = std::shared_ptr<const RobotModel>;

}  // namespace kiloloop
