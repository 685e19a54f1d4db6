#pragma once
// URDF <collision> primitives -> capsules on the links of a model's serial chain (init-time, in
// the URDF library). Each primitive becomes one capsule that contains it:
//   cylinder (r, l)  -> axis along its z, ends at +-l/2, radius r (the caps add r at each end);
//   sphere (r)       -> a point capsule of radius r;
//   box (x, y, z)    -> axis along the longest side, radius = half the diagonal of the other two.
// Links without <collision> contribute nothing. Any other geometry (a mesh) fails with kModelError
// and a message naming the link and the geometry: a skipped link would be invisible to the planner.
// Capsules come in chain order (root link first).
#include <string>
#include <vector>

#include "kiloloop/planning/arm_collision.hpp"

namespace kiloloop {

Status capsules_from_urdf_string(const std::string& xml, const RobotModel& model,
                                 std::vector<LinkCapsule>* out, std::string* why);
Status capsules_from_urdf_file(const std::string& path, const RobotModel& model,
                               std::vector<LinkCapsule>* out, std::string* why);

}  // namespace kiloloop
