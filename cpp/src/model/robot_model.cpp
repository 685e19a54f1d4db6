#include "kiloloop/model/robot_model.hpp"

#include <algorithm>
#include <cmath>
#include <string>

namespace kiloloop {
namespace {

// The only leaf below `from` when no segment branches; empty when the tree branches.
std::string unique_leaf(const KDL::Tree& tree, const std::string& from) {
  auto it = tree.getSegment(from);
  while (true) {
    const auto& children = GetTreeElementChildren(it->second);
    if (children.empty()) return it->first;
    if (children.size() > 1) return {};
    it = children.front();
  }
}

// "'name' is not in the model (links: a, b, ...)": a few names help spot a typo.
std::string not_in_model(const KDL::Tree& tree, const std::string& what, const std::string& name) {
  constexpr int kShown = 8;
  std::string msg = what + " link '" + name + "' is not in the model (links: ";
  int n = 0;
  for (const auto& [link, el] : tree.getSegments()) {
    if (n == kShown) {
      msg += ", ... " + std::to_string(tree.getSegments().size() - kShown) + " more";
      break;
    }
    msg += (n++ ? ", " : "") + link;
  }
  return msg + ")";
}

}  // namespace

Status RobotModel::create(const KDL::Tree& tree, const std::string& root, const std::string& tip,
                          const std::map<std::string, JointLimit>& limits, RobotModel* out,
                          std::string* why) {
  return create(tree, root, tip, limits, {}, out, why);
}

Status RobotModel::create(const KDL::Tree& tree, const std::string& root, const std::string& tip,
                          const std::map<std::string, JointLimit>& limits,
                          const std::map<std::string, double>& locked, RobotModel* out,
                          std::string* why) {
  auto fail = [&](const std::string& msg) {
    if (why) *why = msg;
    return Status::kModelError;
  };
  if (out == nullptr) return fail("RobotModel::create: null output");
  RobotModel m;
  m.tree_ = tree;
  m.root_ = root.empty() ? tree.getRootSegment()->first : root;
  if (tree.getSegment(m.root_) == tree.getSegments().end())
    return fail(not_in_model(tree, "root", m.root_));
  m.tip_ = tip.empty() ? unique_leaf(tree, m.root_) : tip;
  if (!tip.empty() && tree.getSegment(tip) == tree.getSegments().end())
    return fail(not_in_model(tree, "tip", tip));

  std::vector<std::string> names;
  if (!m.tip_.empty()) {
    std::vector<std::string> path;
    Status s = chain_path(tree, m.root_, m.tip_, &path, why);
    if (failed(s)) return s;
    if (!tree.getChain(m.root_, m.tip_, m.chain_))
      return fail("no chain from '" + m.root_ + "' to '" + m.tip_ + "'");
    s = fold_off_chain_mass(tree, path, locked, &m.chain_, &m.folded_, why);
    if (failed(s)) return s;
    m.locked_ = locked;
    m.has_chain_ = true;
    for (const auto& seg : m.chain_.segments)
      if (seg.getJoint().getType() != KDL::Joint::None) names.push_back(seg.getJoint().getName());
  } else {
    if (!locked.empty())
      return fail("locked joint '" + locked.begin()->first +
                  "': locking applies to joints off a chain; give a tip link");
    // Branching tree without a tip: joints in KDL's q_nr order, so vectors index like KDL's.
    names.resize(tree.getNrOfJoints());
    for (const auto& [name, el] : tree.getSegments()) {
      const auto& seg = GetTreeElementSegment(el);
      if (seg.getJoint().getType() != KDL::Joint::None)
        names[GetTreeElementQNr(el)] = seg.getJoint().getName();
    }
  }
  const int n = static_cast<int>(names.size());
  m.joint_names_ = names;
  m.lower_.resize(n);
  m.upper_.resize(n);
  m.velocity_.resize(n);
  m.effort_.resize(n);
  for (int i = 0; i < n; ++i) {
    const auto it = limits.find(names[i]);
    const JointLimit lim = it == limits.end() ? JointLimit{} : it->second;
    if (!(lim.lower <= lim.upper)) return fail("joint '" + names[i] + "': lower limit > upper");
    if (!(lim.velocity > 0) || !(lim.effort > 0))
      return fail("joint '" + names[i] + "': velocity and effort limits must be > 0");
    m.lower_[i] = lim.lower;
    m.upper_[i] = lim.upper;
    m.velocity_[i] = lim.velocity;
    m.effort_[i] = lim.effort;
  }
  *out = std::move(m);
  return Status::kOk;
}

double RobotModel::total_mass() const {
  double mass = 0.0;
  for (const auto& [name, el] : tree_.getSegments())
    mass += GetTreeElementSegment(el).getInertia().getMass();
  return mass;
}

Status RobotModel::with_armature(const Eigen::VectorXd& armature, RobotModel* out,
                                 std::string* why) const {
  auto fail = [&](const std::string& msg) {
    if (why) *why = msg;
    return Status::kModelError;
  };
  if (out == nullptr) return fail("RobotModel::with_armature: null output");
  if (!has_chain_) return fail("armature: the model has no chain (give a tip link)");
  if (armature.size() != nq())
    return fail("armature: expected " + std::to_string(nq()) + " values (one per chain joint), got " +
                std::to_string(armature.size()));
  for (int i = 0; i < nq(); ++i)
    if (!std::isfinite(armature[i]) || armature[i] < 0.0)
      return fail("armature of joint '" + joint_names_[i] + "' must be finite and >= 0");
  RobotModel m = *this;
  KDL::Chain chain;
  int i = 0;
  for (const KDL::Segment& seg : chain_.segments) {
    const KDL::Joint& j = seg.getJoint();
    if (j.getType() == KDL::Joint::None) {
      chain.addSegment(seg);
      continue;
    }
    const bool axis = j.getType() == KDL::Joint::RotAxis || j.getType() == KDL::Joint::TransAxis;
    const KDL::Joint with =
        axis ? KDL::Joint(j.getName(), j.JointOrigin(), j.JointAxis(), j.getType(), 1.0, 0.0,
                          armature[i], j.getDamping(), j.getStiffness())
             : KDL::Joint(j.getName(), j.getType(), 1.0, 0.0, armature[i], j.getDamping(),
                          j.getStiffness());
    chain.addSegment(KDL::Segment(seg.getName(), with, seg.getFrameToTip(), seg.getInertia()));
    ++i;
  }
  m.chain_ = chain;
  *out = std::move(m);
  return Status::kOk;
}

Eigen::VectorXd RobotModel::armature() const {
  Eigen::VectorXd a = Eigen::VectorXd::Zero(nq());
  if (!has_chain_) return a;
  int i = 0;
  for (const KDL::Segment& seg : chain_.segments)
    if (seg.getJoint().getType() != KDL::Joint::None) a[i++] = seg.getJoint().getInertia();
  return a;
}

}  // namespace kiloloop
