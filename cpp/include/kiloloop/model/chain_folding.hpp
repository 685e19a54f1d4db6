#pragma once
// Chain folding: the mass a serial chain carries but does not actuate. A controller drives the
// joints root -> tip; everything else attached to those links (a gripper beyond the tip, a
// camera mast on link 2, the fingers of a hand) moves with them as rigid bodies. Each subtree
// hanging off a chain link is collapsed into one composite inertia (its movable joints locked at
// given positions, default 0) and added to that link's segment, so the chain's dynamics equal
// those of the full tree with every non-chain joint locked (Pinocchio's buildReducedModel).
// Mass above the chain root or hanging from the root link is carried by the fixed base and is
// not folded. Init-time only (allocates).
#include <map>
#include <string>
#include <vector>

#include <kdl/chain.hpp>
#include <kdl/tree.hpp>

#include "kiloloop/status.hpp"

namespace kiloloop {

// One link whose mass was folded into a chain segment.
struct FoldedLink {
  std::string link;   // the link (KDL segment) folded away
  std::string onto;   // the chain segment that now carries its mass
  double mass = 0.0;  // [kg] this link's own mass
};

// The tree segments from `root` (exclusive) to `tip` (inclusive), or a reason naming the links
// when `root` is not an ancestor of `tip` (tip->root given, or two different branches).
Status chain_path(const KDL::Tree& tree, const std::string& root, const std::string& tip,
                  std::vector<std::string>* path, std::string* why);

// Adds to each segment of `chain` (the tree path root -> tip, as KDL::Tree::getChain builds it)
// the composite inertia of every subtree hanging from it off the path, expressed in that
// segment's frame, with movable joints at `locked` (joint name -> [rad] or [m]; absent: 0).
// `folded` lists every folded link. Fails when a locked name is not a joint of the tree or is a
// chain joint, or a locked value is not finite.
Status fold_off_chain_mass(const KDL::Tree& tree, const std::vector<std::string>& path,
                           const std::map<std::string, double>& locked, KDL::Chain* chain,
                           std::vector<FoldedLink>* folded, std::string* why);

}  // namespace kiloloop
