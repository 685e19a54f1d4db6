#pragma once
// URDF -> RobotModel (urdfdom + kdl_parser). Init-time only, in its own library
// (kiloloop::urdf) so firmware that builds its model from DH needs no XML parser.
//
// kdl_parser drops the root link's inertia (KDL trees have no root body) and only warns. A
// floating trunk would lose its mass, so when the URDF root carries an inertia the loader adds a
// massless virtual root "kiloloop_root" above it, joined by a fixed joint: the original root then
// becomes an ordinary segment and keeps its inertia. Chains still default to start at the URDF root.
#include <map>
#include <string>

#include "kiloloop/model/robot_model.hpp"

namespace kiloloop {

inline constexpr const char* kVirtualRootName = "kiloloop_root";

//
// Real descriptions: a chain root -> tip folds everything else hanging from its links (grippers,
// sensors, branches) in as rigid mass, movable joints off the chain at `locked` (joint name ->
// [rad] or [m], default 0; see model/chain_folding.hpp). Mimic joints off the chain are locked
// like any other; a mimic joint in the chain (or in a tree model without a tip) is refused,
// named. Continuous joints have infinite position limits.

// `xml` is the URDF text; `source` names it in error messages (a file path or "<string>").
Status model_from_urdf_string(const std::string& xml, const std::string& root,
                              const std::string& tip, const std::map<std::string, double>& locked,
                              RobotModel* out, std::string* why,
                              const std::string& source = "<string>");
Status model_from_urdf_string(const std::string& xml, const std::string& root,
                              const std::string& tip, RobotModel* out, std::string* why,
                              const std::string& source = "<string>");

// Reads and loads a URDF file; a missing file fails with kModelError and "cannot open '<path>'".
Status model_from_urdf_file(const std::string& path, const std::string& root,
                            const std::string& tip, const std::map<std::string, double>& locked,
                            RobotModel* out, std::string* why);
Status model_from_urdf_file(const std::string& path, const std::string& root,
                            const std::string& tip, RobotModel* out, std::string* why);

}  // namespace kiloloop
