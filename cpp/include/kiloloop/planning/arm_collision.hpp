#pragma once
// Collision model of a serial arm among box obstacles: every link is approximated by capsules
// (segment + radius, fixed in a link frame), obstacles are oriented boxes, and the test between
// them is the exact capsule-box distance (planning/capsule_box.hpp). Robot self-collision is not
// modelled. Revolute and fixed joints only (the edge check's motion bound). Queries are noexcept and allocation-free (link frames go into preallocated storage).
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "kiloloop/model/robot_model.hpp"
#include "kiloloop/planning/capsule_box.hpp"

namespace kiloloop {

struct LinkCapsule {
  std::string link;                                    // link (KDL segment) name; the root is allowed
  Eigen::Vector3d a = Eigen::Vector3d::Zero();         // [m] segment ends in the link frame
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  double radius = 0.0;                                 // [m] >= 0
};

struct ArmCollisionConfig {
  std::vector<LinkCapsule> capsules;
  std::vector<OrientedBox> boxes;
  double margin = 0.01;  // [m] a configuration is free when every capsule-box distance > margin
  // segment_free rejects an edge on which a sample's clearance is <= edge_tolerance [m]: proving
  // an edge free ever closer to the margin takes ever more samples.
  double edge_tolerance = 1e-4;
  int max_edge_samples = 10000;  // and one that needs more samples than this (a bound, rarely hit)
};

Status validate(const ArmCollisionConfig& config, const RobotModel& model, std::string* why);

class ArmCollisionChecker {
 public:
  using VecRef = Eigen::Ref<const Eigen::VectorXd>;

  static Status configure(const ArmCollisionConfig& config, RobotModelPtr model,
                          ArmCollisionChecker* out, std::string* why);

  int nq() const { return nq_; }
  const RobotModel& model() const { return *model_; }
  // Smallest capsule-box distance minus the margin [m] (+inf without boxes; NaN for a bad q).
  double clearance(const VecRef& q) noexcept;
  bool is_free(const VecRef& q) noexcept { return clearance(q) > 0.0; }
  // True only if every configuration on the straight joint-space segment q0 -> q1 is free, not
  // only its samples. First the fixed grid at steps of at most max_step [rad] per joint (both ends
  // included); then each gap between samples is proved free from its ends' clearances and a bound
  // on how fast any capsule point moves along the edge (reach() . |q1 - q0| per unit of the
  // segment parameter), halving the gaps where that does not suffice. Bounded: a sample with
  // clearance <= edge_tolerance, or more than max_edge_samples samples, rejects the edge.
  bool segment_free(const VecRef& q0, const VecRef& q1, double max_step) noexcept;
  // (nq) [m/rad] per joint, a bound on the distance from its axis to any capsule point it moves.
  const Eigen::VectorXd& reach() const { return reach_; }
  // World-frame capsule ends at q (for tests and plots); a, b: (3, n_capsules).
  Status capsules_at(const VecRef& q, Eigen::Ref<Eigen::Matrix3Xd> a, Eigen::Ref<Eigen::Matrix3Xd> b) noexcept;
  // Calls to clearance() since configure (the planners' cost figure).
  unsigned long long checks() const { return checks_; }

 private:
  bool link_frames(const VecRef& q) noexcept;
  double clearance_along(const VecRef& q0, const VecRef& q1, double s) noexcept;

  RobotModelPtr model_;
  int nq_ = 0;
  ArmCollisionConfig config_;
  std::vector<int> capsule_frame_;  // index into frames_ (0 = root, k = after segment k-1)
  std::vector<Eigen::Isometry3d, Eigen::aligned_allocator<Eigen::Isometry3d>> frames_;
  Eigen::VectorXd q_interp_;
  Eigen::VectorXd reach_;
  Eigen::VectorXd grid_clearance_;  // (max_edge_samples) segment_free's pass-1 clearances
  unsigned long long checks_ = 0;
};

}  // namespace kiloloop
