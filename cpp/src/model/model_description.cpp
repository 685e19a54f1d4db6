#include "kiloloop/model/model_description.hpp"
#include "kiloloop/model/model_error.hpp"

#include <set>

#include <kdl/frames.hpp>
#include <kdl/rigidbodyinertia.hpp>
#include <kdl/rotationalinertia.hpp>
#include <kdl/segment.hpp>

namespace kiloloop {
namespace {

KDL::Frame frame(const PoseSpec& p) {
  return KDL::Frame(KDL::Rotation::Quaternion(p.quat[0], p.quat[1], p.quat[2], p.quat[3]),
                    KDL::Vector(p.xyz[0], p.xyz[1], p.xyz[2]));
}

KDL::Joint joint(const SegmentSpec& s) {
  if (s.kind == JointKind::kFixed) return KDL::Joint(s.joint, KDL::Joint::None);
  const KDL::Frame origin = frame(s.origin);
  const KDL::Vector axis = origin.M * KDL::Vector(s.axis[0], s.axis[1], s.axis[2]);
  return KDL::Joint(s.joint, origin.p, axis,
                    s.kind == JointKind::kRevolute ? KDL::Joint::RotAxis : KDL::Joint::TransAxis);
}

// The inertia about the CoM, rotated from the inertial frame into the link frame through a
// massless RigidBodyInertia (KDL has no rotation operator for RotationalInertia).
KDL::RigidBodyInertia inertia(const SegmentSpec& s) {
  if (!s.has_inertial) return KDL::RigidBodyInertia(0);
  const KDL::Frame origin = frame(s.inertial);
  const double* i = s.inertia;
  const KDL::RotationalInertia principal(i[0], i[1], i[2], i[3], i[4], i[5]);
  const KDL::RigidBodyInertia rotated =
      origin.M * KDL::RigidBodyInertia(0, KDL::Vector::Zero(), principal);
  return KDL::RigidBodyInertia(s.mass, origin.p, rotated.getRotationalInertia());
}

}  // namespace

Status tree_from_description(const ModelDescription& d, KDL::Tree* out, std::string* why) {
  if (out == nullptr || d.tree_root == nullptr || (d.segment_count > 0 && d.segments == nullptr))
    return model_error(why, "model description: null root or segments");
  KDL::Tree tree(d.tree_root);
  for (int k = 0; k < d.segment_count; ++k) {
    const SegmentSpec& s = d.segments[k];
    const KDL::Segment segment(s.link, joint(s), frame(s.origin), inertia(s));
    if (!tree.addSegment(segment, s.parent))
      return model_error(why, std::string("model description: link '") + s.link + "' cannot hang from '" +
                           s.parent + "' (unknown parent or duplicate name)");
  }
  *out = tree;
  return Status::kOk;
}

Status model_from_description(const ModelDescription& d, const std::string& root,
                              const std::string& tip, const std::map<std::string, double>& locked,
                              RobotModel* out, std::string* why, const std::string& source) {
  KDL::Tree tree;
  Status s = tree_from_description(d, &tree, why);
  if (failed(s)) return s;
  std::map<std::string, JointLimit> limits;
  std::set<std::string> mimic;
  for (int k = 0; k < d.segment_count; ++k) {
    limits[d.segments[k].joint] = d.segments[k].limit;
    if (d.segments[k].mimic) mimic.insert(d.segments[k].joint);
  }
  s = RobotModel::create(tree, root.empty() ? d.urdf_root : root, tip, limits, locked, out, why);
  if (failed(s)) {
    if (why) *why = "URDF " + source + ": " + *why;
    return s;
  }
  for (const std::string& name : out->joint_names()) {
    if (!mimic.count(name)) continue;
    if (!out->has_chain())
      return model_error(why, "URDF " + source + ": mimic joint '" + name +
                           "' would be controlled (no tip given: every joint is); give a tip so "
                           "that it is off the chain");
    return model_error(why, "URDF " + source + ": mimic joint '" + name + "' is in the chain '" +
                         out->root_name() + "' -> '" + out->tip_name() +
                         "'; a controlled chain cannot contain a mimic joint (off the chain it is "
                         "locked)");
  }
  out->set_root_inertia_restored(d.root_inertia_restored);
  return Status::kOk;
}

}  // namespace kiloloop
