#include "kiloloop/model/dh.hpp"

#include <Eigen/Eigenvalues>
#include <kdl/frames.hpp>
#include <kdl/rigidbodyinertia.hpp>
#include <kdl/rotationalinertia.hpp>

namespace kiloloop {
namespace {

KDL::RigidBodyInertia to_kdl_inertia(const DhLink& l) {
  const Eigen::Matrix3d& I = l.inertia;
  // KDL takes the rotational inertia about the reference point; ours is about the CoM.
  const KDL::RotationalInertia Ic(I(0, 0), I(1, 1), I(2, 2), I(0, 1), I(0, 2), I(1, 2));
  return KDL::RigidBodyInertia(l.mass, KDL::Vector(l.com.x(), l.com.y(), l.com.z()), Ic);
}

bool valid_inertia(const DhLink& l, std::string* why, int i) {
  const Eigen::Matrix3d& I = l.inertia;
  if (!(l.mass >= 0.0) || !I.allFinite() || !l.com.allFinite() ||
      (I - I.transpose()).cwiseAbs().maxCoeff() > 1e-12 * (1.0 + I.cwiseAbs().maxCoeff())) {
    if (why) *why = "DH link " + std::to_string(i) + ": mass, com or inertia invalid or asymmetric";
    return false;
  }
  if (Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(I).eigenvalues().minCoeff() < -1e-12) {
    if (why) *why = "DH link " + std::to_string(i) + ": inertia is not positive semi-definite";
    return false;
  }
  return true;
}

}  // namespace

Status model_from_dh(const std::vector<DhLink>& links, DhConvention convention, RobotModel* out,
                     std::string* why) {
  if (links.empty()) {
    if (why) *why = "DH table is empty";
    return Status::kModelError;
  }
  KDL::Tree tree("base");
  std::map<std::string, JointLimit> limits;
  std::string parent = "base";
  const int n = static_cast<int>(links.size());
  for (int i = 0; i < n; ++i) {
    const DhLink& l = links[i];
    if (!valid_inertia(l, why, i)) return Status::kModelError;
    const std::string joint = l.name.empty() ? "joint" + std::to_string(i + 1) : l.name;
    const std::string link = "link" + std::to_string(i + 1);
    const KDL::Joint::JointType type = l.prismatic ? KDL::Joint::TransZ : KDL::Joint::RotZ;
    // KDL puts the joint at the start of a segment, so the joint's own offset and everything
    // after it up to the next joint goes into f_tip; the link's inertia is then re-expressed
    // from frame i into the segment's tip frame.
    KDL::Frame pre, post;  // frame i-1 -> joint frame, and joint frame (at q=0) -> frame i
    if (convention == DhConvention::kStandard) {
      pre = KDL::Frame::Identity();
      post = KDL::Frame(KDL::Rotation::RotZ(l.theta), KDL::Vector(0, 0, l.d)) *
             KDL::Frame(KDL::Rotation::RotX(l.alpha), KDL::Vector(l.a, 0, 0));
    } else {
      pre = KDL::Frame(KDL::Rotation::RotX(l.alpha)) * KDL::Frame(KDL::Vector(l.a, 0, 0));
      post = KDL::Frame(KDL::Rotation::RotZ(l.theta), KDL::Vector(0, 0, l.d));
    }
    if (!(pre == KDL::Frame::Identity())) {
      const std::string fixed = link + "_pre";
      tree.addSegment(KDL::Segment(fixed, KDL::Joint(joint + "_pre", KDL::Joint::None), pre),
                      parent);
      parent = fixed;
    }
    // Segment tip == frame i here, so the inertia goes in as given.
    tree.addSegment(KDL::Segment(link, KDL::Joint(joint, type), post, to_kdl_inertia(l)), parent);
    parent = link;
    limits[joint] = l.limit;
  }
  // A named tool frame equal to the last link frame, so FK has a stable tip name.
  tree.addSegment(KDL::Segment("tool", KDL::Joint("tool_fixed", KDL::Joint::None)), parent);
  return RobotModel::create(tree, "base", "tool", limits, out, why);
}

}  // namespace kiloloop
