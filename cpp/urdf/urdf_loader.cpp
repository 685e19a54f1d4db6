#include "kiloloop/urdf/urdf_loader.hpp"
#include "kiloloop/model/model_error.hpp"

#include "kiloloop/urdf/urdf_description.hpp"

#include <cmath>
#include <fstream>
#include <sstream>

#include <console_bridge/console.h>
#include <urdf_parser/urdf_parser.h>

#include "urdf_checks.hpp"

namespace kiloloop {
namespace {

// Captures urdfdom's console_bridge errors, so a parse failure can say why instead of printing.
class CapturedLog : public console_bridge::OutputHandler {
 public:
  CapturedLog() { console_bridge::useOutputHandler(this); }
  ~CapturedLog() override { console_bridge::restorePreviousOutputHandler(); }
  void log(const std::string& text, console_bridge::LogLevel level, const char*, int) override {
    if (level >= console_bridge::CONSOLE_BRIDGE_LOG_ERROR) errors_ += (errors_.empty() ? "" : "; ") + text;
  }
  const std::string& errors() const { return errors_; }

 private:
  std::string errors_;
};

// Inserts a massless virtual root above a root link that has an inertia (see the header).
bool restore_root_inertia(urdf::ModelInterface& model) {
  urdf::LinkSharedPtr root;
  model.getLink(model.getRoot()->name, root);
  if (!root->inertial) return false;
  if (root->inertial->mass <= 0.0) {
    // A massless inertial carries nothing; dropping it spares kdl_parser's root-inertia warning
    // (printed through a logger we cannot capture).
    root->inertial.reset();
    return false;
  }
  auto base = std::make_shared<urdf::Link>();
  base->name = kVirtualRootName;
  auto joint = std::make_shared<urdf::Joint>();
  joint->name = std::string(kVirtualRootName) + "_joint";
  joint->type = urdf::Joint::FIXED;
  joint->parent_link_name = base->name;
  joint->child_link_name = root->name;
  root->parent_joint = joint;
  root->setParent(base);
  base->child_links.push_back(root);
  base->child_joints.push_back(joint);
  model.links_[base->name] = base;
  model.joints_[joint->name] = joint;
  model.root_link_ = base;
  return true;
}

// URDF writes 0 for "not given" velocity/effort on continuous joints; continuous joints have no
// position range.
JointLimit limit_of(const urdf::Joint& joint) {
  JointLimit lim;
  if (joint.limits && joint.type != urdf::Joint::CONTINUOUS) {
    lim.lower = joint.limits->lower;
    lim.upper = joint.limits->upper;
  }
  if (joint.limits && joint.limits->velocity > 0) lim.velocity = joint.limits->velocity;
  if (joint.limits && joint.limits->effort > 0) lim.effort = joint.limits->effort;
  return lim;
}

JointKind kind_of(const urdf::Joint& joint) {
  switch (joint.type) {
    case urdf::Joint::REVOLUTE:
    case urdf::Joint::CONTINUOUS:
      return JointKind::kRevolute;
    case urdf::Joint::PRISMATIC:
      return JointKind::kPrismatic;
    default:
      return JointKind::kFixed;  // kdl_parser's rule for every other type
  }
}

PoseSpec pose_of(const urdf::Pose& p) {
  return PoseSpec{{p.position.x, p.position.y, p.position.z},
                  {p.rotation.x, p.rotation.y, p.rotation.z, p.rotation.w}};
}

}  // namespace

Status description_from_urdf_string(const std::string& xml, UrdfDescription* out, std::string* why,
                                    const std::string& source) {
  if (out == nullptr) return model_error(why, "description_from_urdf_string: null output");
  urdf::ModelInterfaceSharedPtr urdf_model;
  std::string parse_errors;
  {
    CapturedLog log;
    urdf_model = urdf::parseURDF(xml);
    parse_errors = log.errors();
  }
  // urdfdom logs some errors and still returns a model (a number it could not read left at 0):
  // an error is an error.
  if (!urdf_model || !parse_errors.empty())
    return model_error(why, "invalid URDF " + source + ": " +
                         (parse_errors.empty() ? std::string("parse failed") : parse_errors));

  const std::string problem = urdf_checks::first_problem(*urdf_model);
  if (!problem.empty()) return model_error(why, "invalid URDF " + source + ": " + problem);

  for (const auto& [name, joint] : urdf_model->joints_) {
    if (joint->type == urdf::Joint::FLOATING || joint->type == urdf::Joint::PLANAR)
      return model_error(why, "URDF " + source + ": joint '" + name +
                           "' is floating/planar; model a floating base without a URDF joint");
  }
  out->names_.clear();
  out->segments_.clear();
  auto keep = [out](const std::string& name) { return out->names_.emplace_back(name).c_str(); };
  const char* urdf_root = keep(urdf_model->getRoot()->name);
  const bool restored = restore_root_inertia(*urdf_model);
  const char* tree_root = keep(urdf_model->getRoot()->name);

  // Depth first, children in urdfdom's order: the order kdl_parser adds segments in.
  std::vector<urdf::LinkConstSharedPtr> stack(urdf_model->getRoot()->child_links.rbegin(),
                                              urdf_model->getRoot()->child_links.rend());
  while (!stack.empty()) {
    const urdf::LinkConstSharedPtr link = stack.back();
    stack.pop_back();
    const urdf::Joint& joint = *link->parent_joint;
    SegmentSpec s{};
    s.link = keep(link->name);
    s.joint = keep(joint.name);
    s.parent = keep(joint.parent_link_name);
    s.kind = kind_of(joint);
    s.origin = pose_of(joint.parent_to_joint_origin_transform);
    s.axis[0] = joint.axis.x;
    s.axis[1] = joint.axis.y;
    s.axis[2] = joint.axis.z;
    s.has_inertial = static_cast<bool>(link->inertial);
    if (link->inertial) {
      const urdf::Inertial& i = *link->inertial;
      s.mass = i.mass;
      s.inertial = pose_of(i.origin);
      const double inertia[6] = {i.ixx, i.iyy, i.izz, i.ixy, i.ixz, i.iyz};
      for (int k = 0; k < 6; ++k) s.inertia[k] = inertia[k];
    } else {
      s.inertial = PoseSpec{{0.0, 0.0, 0.0}, {0.0, 0.0, 0.0, 1.0}};
    }
    s.limit = limit_of(joint);
    s.mimic = static_cast<bool>(joint.mimic);
    out->segments_.push_back(s);
    stack.insert(stack.end(), link->child_links.rbegin(), link->child_links.rend());
  }
  out->description_ = ModelDescription{tree_root, urdf_root, restored, out->segments_.data(),
                                       static_cast<int>(out->segments_.size())};
  return Status::kOk;
}

Status model_from_urdf_string(const std::string& xml, const std::string& root,
                              const std::string& tip, RobotModel* out, std::string* why,
                              const std::string& source) {
  return model_from_urdf_string(xml, root, tip, {}, out, why, source);
}

Status model_from_urdf_string(const std::string& xml, const std::string& root,
                              const std::string& tip, const std::map<std::string, double>& locked,
                              RobotModel* out, std::string* why, const std::string& source) {
  UrdfDescription urdf;
  const Status s = description_from_urdf_string(xml, &urdf, why, source);
  if (failed(s)) return s;
  return model_from_description(urdf.description(), root, tip, locked, out, why, source);
}

Status model_from_urdf_file(const std::string& path, const std::string& root,
                            const std::string& tip, RobotModel* out, std::string* why) {
  return model_from_urdf_file(path, root, tip, {}, out, why);
}

Status model_from_urdf_file(const std::string& path, const std::string& root,
                            const std::string& tip, const std::map<std::string, double>& locked,
                            RobotModel* out, std::string* why) {
  std::ifstream file(path);
  if (!file) return model_error(why, "cannot open URDF file '" + path + "'");
  std::stringstream text;
  text << file.rdbuf();
  return model_from_urdf_string(text.str(), root, tip, locked, out, why, "'" + path + "'");
}

}  // namespace kiloloop
