#include "urdf_checks.hpp"

#include <cmath>
#include <map>
#include <set>
#include <vector>

#include <Eigen/Eigenvalues>

namespace kiloloop::urdf_checks {
namespace {

bool finite(double x) { return std::isfinite(x); }
bool finite(const urdf::Vector3& v) { return finite(v.x) && finite(v.y) && finite(v.z); }
bool finite(const urdf::Pose& p) {
  return finite(p.position) && finite(p.rotation.x) && finite(p.rotation.y) &&
         finite(p.rotation.z) && finite(p.rotation.w);
}

// The graph: one parent joint per link, no joint from a link to itself, every link reached from
// the root (a loop has a link with two parents, or a cycle the root does not reach).
std::string tree_problem(const urdf::ModelInterface& model) {
  std::map<std::string, std::string> parent_joint;  // child link -> the joint above it
  std::map<std::string, std::vector<std::string>> children;  // link -> child links
  for (const auto& [name, joint] : model.joints_) {
    if (joint->parent_link_name == joint->child_link_name)
      return "joint '" + name + "' connects link '" + joint->child_link_name + "' to itself";
    const auto [it, fresh] = parent_joint.emplace(joint->child_link_name, name);
    if (!fresh)
      return "link '" + joint->child_link_name + "' has two parent joints ('" + it->second +
             "' and '" + name + "'): a kinematic loop; URDF describes trees only";
    children[joint->parent_link_name].push_back(joint->child_link_name);
  }
  if (!model.getRoot()) return "no root link";
  std::set<std::string> reached{model.getRoot()->name};
  std::vector<std::string> open{model.getRoot()->name};
  while (!open.empty()) {
    const std::string link = open.back();
    open.pop_back();
    for (const std::string& child : children[link])
      if (reached.insert(child).second) open.push_back(child);
  }
  for (const auto& [name, link] : model.links_)
    if (!reached.count(name))
      return "link '" + name + "' is not connected to the root link '" + model.getRoot()->name +
             "' (a kinematic loop, or a separate tree)";
  return "";
}

// Finite, mass >= 0, and an inertia tensor that is positive semi-definite (a tiny negative
// eigenvalue from rounding in exported files is tolerated: 1e-9 of the largest moment).
std::string inertial_problem(const std::string& name, const urdf::Inertial& in) {
  const std::string where = "link '" + name + "': ";
  if (!finite(in.mass) || !finite(in.origin) || !finite(in.ixx) || !finite(in.iyy) ||
      !finite(in.izz) || !finite(in.ixy) || !finite(in.ixz) || !finite(in.iyz))
    return where + "<inertial> has a number that is not finite (NaN or Inf)";
  if (in.mass < 0) return where + "negative mass " + std::to_string(in.mass) + " kg";
  Eigen::Matrix3d I;
  I << in.ixx, in.ixy, in.ixz, in.ixy, in.iyy, in.iyz, in.ixz, in.iyz, in.izz;
  const Eigen::Vector3d eig = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(I, Eigen::EigenvaluesOnly).eigenvalues();
  const double scale = I.cwiseAbs().maxCoeff();
  if (eig.minCoeff() < -1e-9 * scale)
    return where + "inertia tensor is not positive semi-definite (smallest principal moment " +
           std::to_string(eig.minCoeff()) + " kg m^2)";
  return "";
}

std::string joint_problem(const std::string& name, const urdf::Joint& j) {
  const std::string where = "joint '" + name + "': ";
  if (j.type == urdf::Joint::UNKNOWN) return where + "unknown joint type";
  if (!finite(j.parent_to_joint_origin_transform))
    return where + "origin has a number that is not finite (NaN or Inf)";
  const bool moves = j.type == urdf::Joint::REVOLUTE || j.type == urdf::Joint::CONTINUOUS ||
                     j.type == urdf::Joint::PRISMATIC;
  if (moves) {
    if (!finite(j.axis)) return where + "axis has a number that is not finite (NaN or Inf)";
    if (j.axis.x == 0 && j.axis.y == 0 && j.axis.z == 0) return where + "axis is zero";
  }
  if (j.limits) {
    const auto& l = *j.limits;
    if (!finite(l.lower) || !finite(l.upper) || !finite(l.effort) || !finite(l.velocity))
      return where + "<limit> has a number that is not finite (NaN or Inf)";
    if (l.effort < 0 || l.velocity < 0) return where + "effort and velocity limits must be >= 0";
    if (j.type != urdf::Joint::CONTINUOUS && l.lower > l.upper)
      return where + "lower limit above the upper one";
  }
  if (j.dynamics && (!finite(j.dynamics->damping) || !finite(j.dynamics->friction) ||
                     j.dynamics->damping < 0 || j.dynamics->friction < 0))
    return where + "<dynamics> damping and friction must be finite and >= 0";
  return "";
}

}  // namespace

std::string first_problem(const urdf::ModelInterface& model) {
  std::string p = tree_problem(model);
  if (!p.empty()) return p;
  double total_mass = 0.0;
  for (const auto& [name, link] : model.links_) {
    if (!link->inertial) continue;
    p = inertial_problem(name, *link->inertial);
    if (!p.empty()) return p;
    total_mass += link->inertial->mass;
  }
  for (const auto& [name, joint] : model.joints_) {
    p = joint_problem(name, *joint);
    if (!p.empty()) return p;
  }
  if (!(total_mass > 0))
    return "the robot has no mass (every <inertial> missing or of mass 0): nothing for a "
           "controller to move";
  return "";
}

}  // namespace kiloloop::urdf_checks
