#include "kiloloop/urdf/urdf_loader.hpp"

#include <cmath>
#include <fstream>
#include <set>
#include <sstream>

#include <console_bridge/console.h>
#include <kdl_parser/kdl_parser.hpp>
#include <urdf_parser/urdf_parser.h>

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

Status fail(std::string* why, const std::string& msg) {
  if (why) *why = msg;
  return Status::kModelError;
}

}  // namespace

Status model_from_urdf_string(const std::string& xml, const std::string& root,
                              const std::string& tip, RobotModel* out, std::string* why,
                              const std::string& source) {
  return model_from_urdf_string(xml, root, tip, {}, out, why, source);
}

Status model_from_urdf_string(const std::string& xml, const std::string& root,
                              const std::string& tip, const std::map<std::string, double>& locked,
                              RobotModel* out, std::string* why, const std::string& source) {
  urdf::ModelInterfaceSharedPtr urdf_model;
  std::string parse_errors;
  {
    CapturedLog log;
    urdf_model = urdf::parseURDF(xml);
    parse_errors = log.errors();
  }
  if (!urdf_model)
    return fail(why, "invalid URDF " + source + ": " +
                         (parse_errors.empty() ? std::string("parse failed") : parse_errors));

  std::map<std::string, JointLimit> limits;
  std::set<std::string> mimic;
  for (const auto& [name, joint] : urdf_model->joints_) {
    if (joint->type == urdf::Joint::FLOATING || joint->type == urdf::Joint::PLANAR)
      return fail(why, "URDF " + source + ": joint '" + name +
                           "' is floating/planar; model a floating base without a URDF joint");
    // A mimic joint is an ordinary joint to kdl_parser; only a controlled one is a problem.
    if (joint->mimic) mimic.insert(name);
    JointLimit lim;
    if (joint->limits && joint->type != urdf::Joint::CONTINUOUS) {
      lim.lower = joint->limits->lower;
      lim.upper = joint->limits->upper;
    }
    // URDF writes 0 for "not given" velocity/effort on continuous joints.
    if (joint->limits && joint->limits->velocity > 0) lim.velocity = joint->limits->velocity;
    if (joint->limits && joint->limits->effort > 0) lim.effort = joint->limits->effort;
    limits[name] = lim;
  }

  const std::string urdf_root = urdf_model->getRoot()->name;
  const bool restored = restore_root_inertia(*urdf_model);
  KDL::Tree tree;
  {
    CapturedLog log;  // kdl_parser's warnings are not ours to print
    if (!kdl_parser::treeFromUrdfModel(*urdf_model, tree))
      return fail(why, "URDF " + source + ": kdl_parser could not build a KDL tree");
  }
  const Status s =
      RobotModel::create(tree, root.empty() ? urdf_root : root, tip, limits, locked, out, why);
  if (failed(s)) {
    if (why) *why = "URDF " + source + ": " + *why;
    return s;
  }
  for (const std::string& joint : out->joint_names()) {
    if (!mimic.count(joint)) continue;
    if (!out->has_chain())
      return fail(why, "URDF " + source + ": mimic joint '" + joint +
                           "' would be controlled (no tip given: every joint is); give a tip so "
                           "that it is off the chain");
    return fail(why, "URDF " + source + ": mimic joint '" + joint + "' is in the chain '" +
                         out->root_name() + "' -> '" + out->tip_name() +
                         "'; a controlled chain cannot contain a mimic joint (off the chain it is locked)");
  }
  out->set_root_inertia_restored(restored);
  return s;
}

Status model_from_urdf_file(const std::string& path, const std::string& root,
                            const std::string& tip, RobotModel* out, std::string* why) {
  return model_from_urdf_file(path, root, tip, {}, out, why);
}

Status model_from_urdf_file(const std::string& path, const std::string& root,
                            const std::string& tip, const std::map<std::string, double>& locked,
                            RobotModel* out, std::string* why) {
  std::ifstream file(path);
  if (!file) return fail(why, "cannot open URDF file '" + path + "'");
  std::stringstream text;
  text << file.rdbuf();
  return model_from_urdf_string(text.str(), root, tip, locked, out, why, "'" + path + "'");
}

}  // namespace kiloloop
