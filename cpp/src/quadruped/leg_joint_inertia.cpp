#include "kiloloop/quadruped/leg_joint_inertia.hpp"

#include <kdl/frames.hpp>
#include <kdl/rigidbodyinertia.hpp>

namespace kiloloop {

bool LegJointInertia::configure(const KDL::Chain& chain) {
  if (chain.getNrOfJoints() != 3 || chain.getNrOfSegments() > static_cast<unsigned>(kMaxSegments))
    return false;
  chain_ = chain;
  segments_ = static_cast<int>(chain.getNrOfSegments());
  return true;
}

// KDL's JntToMass, with fixed-size scratch: a root -> leaf sweep for each segment's pose and
// motion axis, then leaf -> root accumulating the composite inertias.
Eigen::Matrix3d LegJointInertia::at(const Eigen::Vector3d& q) const noexcept {
  std::array<KDL::Frame, kMaxSegments> X;
  std::array<KDL::Twist, kMaxSegments> S;
  std::array<KDL::RigidBodyInertia, kMaxSegments> Ic;
  Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
  int k = 0;
  for (int i = 0; i < segments_; ++i) {
    const KDL::Segment& seg = chain_.getSegment(i);
    Ic[i] = seg.getInertia();
    double qi = 0.0;
    if (seg.getJoint().getType() != KDL::Joint::Fixed) qi = q[k++];
    X[i] = seg.pose(qi);
    S[i] = X[i].M.Inverse(seg.twist(qi, 1.0));
  }
  k = 2;
  for (int i = segments_ - 1; i >= 0; --i) {
    if (i > 0) Ic[i - 1] = Ic[i - 1] + X[i] * Ic[i];
    const KDL::Segment& seg = chain_.getSegment(i);
    if (seg.getJoint().getType() == KDL::Joint::Fixed) continue;
    KDL::Wrench F = Ic[i] * S[i];
    H(k, k) = KDL::dot(S[i], F) + seg.getJoint().getInertia();
    int j = k;
    for (int l = i; l > 0;) {
      F = X[l] * F;
      --l;
      if (chain_.getSegment(l).getJoint().getType() != KDL::Joint::Fixed) {
        --j;
        H(k, j) = H(j, k) = KDL::dot(F, S[l]);
      }
    }
    --k;
  }
  return H;
}

}  // namespace kiloloop
