#pragma once
// ModelDescription: a robot's kinematic/inertial tree as plain numbers (what a URDF says, after
// urdfdom parsed it), and ONE builder that turns it into a RobotModel. The URDF loader
// (kiloloop/urdf/) fills a description from XML; a firmware export (`kiloloop export`) writes the
// same numbers as constexpr arrays (hex floats) and calls the same builder, so both models are
// bit-identical by construction: no XML at run time and no second code path that could round
// differently.
//
// Every type here is a literal aggregate (const char* names, plain arrays), so an exported header
// holds a description as `inline constexpr`.
#include <map>
#include <string>

#include "kiloloop/model/robot_model.hpp"
#include "kiloloop/status.hpp"

namespace kiloloop {

enum class JointKind : int { kFixed = 0, kRevolute = 1, kPrismatic = 2 };

// A pose as urdfdom stores it: position [m] and a unit quaternion x, y, z, w (urdfdom converts
// the URDF's rpy to this quaternion; the builder uses these exact doubles).
struct PoseSpec {
  double xyz[3];
  double quat[4];  // x, y, z, w
};

// One URDF joint and the link below it (a KDL segment).
struct SegmentSpec {
  const char* link;         // child link name (the segment's name)
  const char* joint;        // joint name
  const char* parent;       // parent link name
  JointKind kind;
  PoseSpec origin;          // parent link -> joint frame
  double axis[3];           // joint axis in the joint frame (unit)
  bool has_inertial;        // false: a massless link
  double mass;              // [kg]
  PoseSpec inertial;        // link frame -> inertial frame (CoM [m] and principal-frame rotation)
  double inertia[6];        // [kg m^2] ixx, iyy, izz, ixy, ixz, iyz in the inertial frame
  JointLimit limit;         // as RobotModel takes it (+-inf where the URDF gives none)
  bool mimic;               // a mimic joint (refused in a controlled chain)
};

struct ModelDescription {
  const char* tree_root;        // the KDL tree's root link (a virtual root when one was added)
  const char* urdf_root;        // the URDF's root link (the default chain root)
  bool root_inertia_restored;   // see kiloloop/urdf/urdf_loader.hpp
  const SegmentSpec* segments;  // depth first, children in urdfdom's order
  int segment_count;
};

// The KDL tree of a description (kdl_parser's construction, same arithmetic, same order).
Status tree_from_description(const ModelDescription& description, KDL::Tree* out, std::string* why);

// The RobotModel of a description: the tree, then RobotModel::create with the chain root -> tip
// (empty root: the URDF root; empty tip: as RobotModel::create), off-chain joints at `locked`.
// A mimic joint among the controlled joints is refused, named. Errors name `source`.
Status model_from_description(const ModelDescription& description, const std::string& root,
                              const std::string& tip, const std::map<std::string, double>& locked,
                              RobotModel* out, std::string* why,
                              const std::string& source = "<description>");

}  // namespace kiloloop
