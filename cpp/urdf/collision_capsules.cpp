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

// A link with no <collision> adds nothing (the caller decided it cannot hit anything). A collision
// primitive that cannot be bounded (a mesh) fails: skipping it would let the planner pass through it.
Status add_link(const urdf::Link& link, std::vector<LinkCapsule>* out, std::string* why) {
  for (const urdf::CollisionSharedPtr& col : link.collision_array) {
    if (!col || !col->geometry) continue;
    const urdf::Pose& o = col->origin;
    const Eigen::Quaterniond R(o.rotation.w, o.rotation.x, o.rotation.y, o.rotation.z);
    const Eigen::Vector3d p(o.position.x, o.position.y, o.position.z);
    LinkCapsule cap;
    cap.link = link.name;
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
      default:
        if (why)
          *why = "link '" + link.name + "': collision geometry '" + geometry_name(col->geometry->type) +
                 "' is not supported (use a cylinder, sphere or box)";
        return Status::kModelError;
    }
    cap.a = p - R * half_axis;
    cap.b = p + R * half_axis;
    out->push_back(cap);
  }
  return Status::kOk;
}

}  // namespace

Status capsules_from_urdf_string(const std::string& xml, const RobotModel& model,
                                 std::vector<LinkCapsule>* out, std::string* why) {
  urdf::ModelInterfaceSharedPtr urdf_model = urdf::parseURDF(xml);
  if (!urdf_model) {
    if (why) *why = "URDF could not be parsed";
    return Status::kModelError;
  }
  if (!model.has_chain()) {
    if (why) *why = "capsules need a model with a serial chain";
    return Status::kModelError;
  }
  std::vector<std::string> links{model.root_name()};
  for (unsigned k = 0; k < model.chain().getNrOfSegments(); ++k)
    links.push_back(model.chain().getSegment(k).getName());
  out->clear();
  for (const std::string& name : links) {
    const urdf::LinkConstSharedPtr link = urdf_model->getLink(name);
    if (!link) continue;
    const Status s = add_link(*link, out, why);
    if (failed(s)) {
      out->clear();
      return s;
    }
  }
  return Status::kOk;
}

Status capsules_from_urdf_file(const std::string& path, const RobotModel& model,
                               std::vector<LinkCapsule>* out, std::string* why) {
  std::ifstream file(path);
  if (!file) {
    if (why) *why = "cannot open '" + path + "'";
    return Status::kModelError;
  }
  std::stringstream ss;
  ss << file.rdbuf();
  return capsules_from_urdf_string(ss.str(), model, out, why);
}

}  // namespace kiloloop
