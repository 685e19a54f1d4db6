#pragma once
// URDF <collision> primitives -> capsules on the links of a model's serial chain (init-time, in
// the URDF library). Each primitive becomes one capsule that contains it:
//   cylinder (r, l)  -> axis along its z, ends at +-l/2, radius r (the caps add r at each end);
//   sphere (r)       -> a point capsule of radius r;
//   box (x, y, z)    -> axis along the longest side, radius = half the diagonal of the other two.
// Links without <collision> contribute nothing. A mesh cannot be bounded here (no mesh reader in
// the C++ library): its capsules are given by the caller, per link in that link's frame (fitted
// to the mesh by kiloloop.meshes.capsules_for_urdf, or written in a robot file's [collision]),
// and replace the link's mesh collisions. A mesh without given capsules fails with kModelError
// and a message naming the link: a skipped link would be invisible to the planner.
// Links folded into the chain (a gripper beyond the tip, see model/chain_folding.hpp) move with
// their chain link: their capsules are moved into that link's frame (at the locked joint
// positions) and carry its name. Capsules come in chain order (root link first), each chain
// link's own before those folded onto it.
#include <map>
#include <string>
#include <vector>

#include "kiloloop/planning/arm_collision.hpp"

namespace kiloloop {

// Capsules in place of mesh collision geometry: link name -> capsules in that link's frame.
using MeshCapsules = std::map<std::string, std::vector<LinkCapsule>>;

Status capsules_from_urdf_string(const std::string& xml, const RobotModel& model,
                                 const MeshCapsules& mesh_capsules, std::vector<LinkCapsule>* out,
                                 std::string* why);
Status capsules_from_urdf_string(const std::string& xml, const RobotModel& model,
                                 std::vector<LinkCapsule>* out, std::string* why);
Status capsules_from_urdf_file(const std::string& path, const RobotModel& model,
                               const MeshCapsules& mesh_capsules, std::vector<LinkCapsule>* out,
                               std::string* why);
Status capsules_from_urdf_file(const std::string& path, const RobotModel& model,
                               std::vector<LinkCapsule>* out, std::string* why);

}  // namespace kiloloop
