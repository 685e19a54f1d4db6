#include "kiloloop/urdf/collision_capsules.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include <Eigen/Geometry>
#include <urdf_parser/urdf_parser.h>

namespace kiloloop {
namespace {

const char* geometry_name(int type) {
  switch (type) {
    case urdf::Geometry::SPHERE: return "sphere";
    case urdf::Geometry::BOX: return "box";
    case urdf::Geometry::CYLINDER: return "cylinder";
    case urdf::Geometry::MESH: return "mesh";
    default: return "unknown";
  }
}

// Link frame -> the frame of the chain link it was folded onto, walking up the tree with each
// movable joint at its locked position (0 when not given).
Eigen::Isometry3d to_chain_link(const RobotModel& model, const std::string& link, const std::string& onto) {
  KDL::Frame T = KDL::Frame::Identity();
  for (auto it = model.tree().getSegment(link); it->first != onto; it = GetTreeElementParent(it->second)) {
    const KDL::Segment& seg = GetTreeElementSegment(it->second);
    const auto q = model.locked().find(seg.getJoint().getName());
    const double qs = (seg.getJoint().getType() == KDL::Joint::None || q == model.locked().end()) ? 0.0 : q->second;
    T = seg.pose(qs) * T;
  }
  Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) out.linear()(r, c) = T.M(r, c);
    out.translation()[r] = T.p[r];
  }
  return out;
}

// A link with no <collision> adds nothing (the caller decided it cannot hit anything). A mesh
// uses the capsules given for its link (once per link); without them it fails: skipping it would
// let the planner pass through it. Capsules are written in `frame`'s link as `onto`.
Status add_link(const urdf::Link& link, const MeshCapsules& given, const std::string& onto,
                const Eigen::Isometry3d& frame, std::vector<LinkCapsule>* out, std::string* why) {
  bool given_added = false;
  for (const urdf::CollisionSharedPtr& col : link.collision_array) {
    if (!col || !col->geometry) continue;
    const urdf::Pose& o = col->origin;
    const Eigen::Quaterniond R(o.rotation.w, o.rotation.x, o.rotation.y, o.rotation.z);
    const Eigen::Vector3d p(o.position.x, o.position.y, o.position.z);
    LinkCapsule cap;
    cap.link = onto;
    Eigen::Vector3d half_axis = Eigen::Vector3d::Zero();  // in the primitive's frame
    switch (col->geometry->type) {
      case urdf::Geometry::CYLINDER: {
        const auto& c = static_cast<const urdf::Cylinder&>(*col->geometry);
        half_axis.z() = 0.5 * c.length;
        cap.radius = c.radius;
        break;
      }
      case urdf::Geometry::SPHERE:
        cap.radius = static_cast<const urdf::Sphere&>(*col->geometry).radius;
        break;
      case urdf::Geometry::BOX: {
        const auto& b = static_cast<const urdf::Box&>(*col->geometry);
        const Eigen::Vector3d h(0.5 * b.dim.x, 0.5 * b.dim.y, 0.5 * b.dim.z);
        int axis = 0;
        h.maxCoeff(&axis);
        half_axis[axis] = h[axis];
        cap.radius = std::sqrt(h.squaredNorm() - h[axis] * h[axis]);
        break;
      }
      case urdf::Geometry::MESH: {
        const auto it = given.find(link.name);
        if (it == given.end()) {
          if (why)
            *why = "link '" + link.name + "': collision geometry 'mesh' ('" +
                   static_cast<const urdf::Mesh&>(*col->geometry).filename +
                   "') has no capsule: fit one (kiloloop.meshes.capsules_for_urdf) or give it in "
                   "[collision], or use a cylinder, sphere or box";
          return Status::kModelError;
        }
        if (given_added) continue;
        given_added = true;
        for (const LinkCapsule& g : it->second) {
          LinkCapsule c = g;
          c.link = onto;
          c.a = frame * g.a;
          c.b = frame * g.b;
          out->push_back(c);
        }
        continue;
      }
      default:
        if (why)
          *why = "link '" + link.name + "': collision geometry '" + geometry_name(col->geometry->type) +
                 "' is not supported (use a cylinder, sphere or box)";
        return Status::kModelError;
    }
    cap.a = frame * (p - R * half_axis);
    cap.b = frame * (p + R * half_axis);
    out->push_back(cap);
  }
  return Status::kOk;
}

}  // namespace

Status capsules_from_urdf_string(const std::string& xml, const RobotModel& model,
                                 std::vector<LinkCapsule>* out, std::string* why) {
  return capsules_from_urdf_string(xml, model, MeshCapsules{}, out, why);
}

Status capsules_from_urdf_string(const std::string& xml, const RobotModel& model,
                                 const MeshCapsules& mesh_capsules, std::vector<LinkCapsule>* out,
                                 std::string* why) {
  urdf::ModelInterfaceSharedPtr urdf_model = urdf::parseURDF(xml);
  if (!urdf_model) {
    if (why) *why = "URDF could not be parsed";
    return Status::kModelError;
  }
  if (!model.has_chain()) {
    if (why) *why = "capsules need a model with a serial chain";
    return Status::kModelError;
  }
  for (const auto& [name, caps] : mesh_capsules) {
    if (!urdf_model->getLink(name)) {
      if (why) *why = "capsules given for link '" + name + "', which is not in the URDF";
      return Status::kModelError;
    }
    for (const LinkCapsule& c : caps) {
      if (!c.a.allFinite() || !c.b.allFinite() || !(c.radius >= 0.0) || !std::isfinite(c.radius)) {
        if (why) *why = "capsule given for link '" + name + "': ends must be finite and radius >= 0";
        return Status::kModelError;
      }
    }
  }
  std::vector<std::string> links{model.root_name()};
  for (unsigned k = 0; k < model.chain().getNrOfSegments(); ++k)
    links.push_back(model.chain().getSegment(k).getName());
  out->clear();
  for (const std::string& name : links) {
    // The chain link itself, then every link folded onto it, in its frame.
    std::vector<std::pair<std::string, Eigen::Isometry3d>> parts{{name, Eigen::Isometry3d::Identity()}};
    for (const FoldedLink& f : model.folded())
      if (f.onto == name) parts.emplace_back(f.link, to_chain_link(model, f.link, name));
    for (const auto& [part, frame] : parts) {
      const urdf::LinkConstSharedPtr link = urdf_model->getLink(part);
      if (!link) continue;
      const Status s = add_link(*link, mesh_capsules, name, frame, out, why);
      if (failed(s)) {
        out->clear();
        return s;
      }
    }
  }
  return Status::kOk;
}

Status capsules_from_urdf_file(const std::string& path, const RobotModel& model,
                               std::vector<LinkCapsule>* out, std::string* why) {
  return capsules_from_urdf_file(path, model, MeshCapsules{}, out, why);
}

Status capsules_from_urdf_file(const std::string& path, const RobotModel& model,
                               const MeshCapsules& mesh_capsules, std::vector<LinkCapsule>* out,
                               std::string* why) {
  std::ifstream file(path);
  if (!file) {
    if (why) *why = "cannot open '" + path + "'";
    return Status::kModelError;
  }
  std::stringstream ss;
  ss << file.rdbuf();
  return capsules_from_urdf_string(ss.str(), model, mesh_capsules, out, why);
}

}  // namespace kiloloop
