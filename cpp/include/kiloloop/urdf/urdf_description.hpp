#pragma once
// URDF -> ModelDescription (model/model_description.hpp): the plain numbers of a URDF, owning
// their names. The loader (urdf_loader.hpp) builds every RobotModel from one of these through
// model_from_description; `kiloloop export` writes one out as constexpr data.
#include <deque>
#include <string>
#include <vector>

#include "kiloloop/model/model_description.hpp"
#include "kiloloop/status.hpp"

namespace kiloloop {

class UrdfDescription {
 public:
  UrdfDescription() = default;
  UrdfDescription(const UrdfDescription&) = delete;  // the specs point into names_
  UrdfDescription& operator=(const UrdfDescription&) = delete;
  const ModelDescription& description() const { return description_; }

 private:
  friend Status description_from_urdf_string(const std::string&, UrdfDescription*, std::string*,
                                             const std::string&);
  std::deque<std::string> names_;  // a deque: c_str() pointers stay valid as it grows
  std::vector<SegmentSpec> segments_;
  ModelDescription description_{};
};

// Parses URDF text into a description: the root link's inertia restored under a virtual root
// (urdf_loader.hpp), limits as RobotModel takes them, floating/planar joints refused, segments in
// the order kdl_parser would add them. `source` names the text in error messages.
Status description_from_urdf_string(const std::string& xml, UrdfDescription* out, std::string* why,
                                    const std::string& source = "<string>");

}  // namespace kiloloop
