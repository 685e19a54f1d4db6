#include "kiloloop/model/chain_folding.hpp"
#include "kiloloop/model/model_error.hpp"

#include <cmath>
#include <set>

namespace kiloloop {
namespace {

using TreeIt = KDL::SegmentMap::const_iterator;

bool is_ancestor(const KDL::Tree& tree, const std::string& ancestor, const std::string& of) {
  TreeIt it = tree.getSegment(of);
  const TreeIt end = tree.getSegments().end();
  while (it != end) {
    if (it->first == ancestor) return true;
    if (it == tree.getRootSegment()) return false;
    it = GetTreeElementParent(it->second);
  }
  return false;
}

// The subtree's composite inertia below and including `seg`, in `seg`'s own (link) frame, with
// each movable joint at its locked position; appends the links to `folded`.
KDL::RigidBodyInertia subtree_inertia(TreeIt seg, const std::map<std::string, double>& locked,
                                      const std::string& onto, std::vector<FoldedLink>* folded) {
  const KDL::Segment& s = GetTreeElementSegment(seg->second);
  folded->push_back({seg->first, onto, s.getInertia().getMass()});
  KDL::RigidBodyInertia I = s.getInertia();
  for (const TreeIt& child : GetTreeElementChildren(seg->second)) {
    const KDL::Segment& c = GetTreeElementSegment(child->second);
    const auto q = locked.find(c.getJoint().getName());
    const double qc = (c.getJoint().getType() == KDL::Joint::None || q == locked.end()) ? 0.0 : q->second;
    // Child link frame in this link's frame at the locked position.
    I = I + c.pose(qc) * subtree_inertia(child, locked, onto, folded);
  }
  return I;
}

}  // namespace

Status chain_path(const KDL::Tree& tree, const std::string& root, const std::string& tip,
                  std::vector<std::string>* path, std::string* why) {
  const TreeIt end = tree.getSegments().end();
  if (tree.getSegment(root) == end) return model_error(why, "root link '" + root + "' is not in the model");
  if (tree.getSegment(tip) == end) return model_error(why, "tip link '" + tip + "' is not in the model");
  if (!is_ancestor(tree, root, tip)) {
    if (is_ancestor(tree, tip, root))
      return model_error(why, "chain given tip->root: tip link '" + tip + "' is an ancestor of root link '" +
                           root + "'; swap root and tip");
    return model_error(why, "root link '" + root + "' is not an ancestor of tip link '" + tip +
                         "' (they are on different branches of the tree)");
  }
  std::vector<std::string> reversed;
  for (TreeIt it = tree.getSegment(tip); it->first != root; it = GetTreeElementParent(it->second))
    reversed.push_back(it->first);
  path->assign(reversed.rbegin(), reversed.rend());
  return Status::kOk;
}

Status fold_off_chain_mass(const KDL::Tree& tree, const std::vector<std::string>& path,
                           const std::map<std::string, double>& locked, KDL::Chain* chain,
                           std::vector<FoldedLink>* folded, std::string* why) {
  if (chain->getNrOfSegments() != path.size())
    return model_error(why, "fold_off_chain_mass: the chain does not match the path");
  std::set<std::string> tree_joints, chain_joints;
  for (const auto& [name, el] : tree.getSegments()) tree_joints.insert(GetTreeElementSegment(el).getJoint().getName());
  for (const auto& seg : chain->segments)
    if (seg.getJoint().getType() != KDL::Joint::None) chain_joints.insert(seg.getJoint().getName());
  for (const auto& [name, value] : locked) {
    if (!tree_joints.count(name)) return model_error(why, "locked joint '" + name + "' is not a joint of the model");
    if (chain_joints.count(name))
      return model_error(why, "locked joint '" + name + "' is in the chain; only joints off the chain are locked");
    if (!std::isfinite(value)) return model_error(why, "locked joint '" + name + "': position must be finite");
  }
  folded->clear();
  for (size_t k = 0; k < path.size(); ++k) {
    const TreeIt seg = tree.getSegment(path[k]);
    KDL::RigidBodyInertia extra = KDL::RigidBodyInertia::Zero();
    for (const TreeIt& child : GetTreeElementChildren(seg->second)) {
      if (k + 1 < path.size() && child->first == path[k + 1]) continue;  // the chain goes on
      const KDL::Segment& c = GetTreeElementSegment(child->second);
      const auto q = locked.find(c.getJoint().getName());
      const double qc = (c.getJoint().getType() == KDL::Joint::None || q == locked.end()) ? 0.0 : q->second;
      extra = extra + c.pose(qc) * subtree_inertia(child, locked, path[k], folded);
    }
    // KDL::Chain::getChain copies tree segments, so segment k is path[k]'s, in its link frame.
    KDL::Segment& target = chain->segments[k];
    target.setInertia(target.getInertia() + extra);
  }
  return Status::kOk;
}

}  // namespace kiloloop
