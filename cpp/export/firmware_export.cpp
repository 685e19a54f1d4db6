#include "firmware_export.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <type_traits>

namespace kiloloop {
namespace {

// Exact spelling of a double in C++ source.
std::string literal(double x) {
  if (std::isnan(x)) return "std::numeric_limits<double>::quiet_NaN()";
  if (std::isinf(x)) return x > 0 ? "std::numeric_limits<double>::infinity()"
                                  : "-std::numeric_limits<double>::infinity()";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%a", x);
  return buf;
}

std::string quoted(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

std::string pose(const PoseSpec& p) {
  return "{{" + literal(p.xyz[0]) + ", " + literal(p.xyz[1]) + ", " + literal(p.xyz[2]) + "}, {" +
         literal(p.quat[0]) + ", " + literal(p.quat[1]) + ", " + literal(p.quat[2]) + ", " +
         literal(p.quat[3]) + "}}";
}

const char* kind_name(JointKind k) {
  switch (k) {
    case JointKind::kRevolute: return "kiloloop::JointKind::kRevolute";
    case JointKind::kPrismatic: return "kiloloop::JointKind::kPrismatic";
    default: return "kiloloop::JointKind::kFixed";
  }
}

// "gait.period" -> "gait_period", "feet[0]" -> "feet_0_": a member name for a field path.
std::string identifier(const char* path) {
  std::string id;
  for (const char* c = path; *c; ++c) id += std::isalnum(static_cast<unsigned char>(*c)) ? *c : '_';
  return id;
}

// One constexpr member and one make_config() line per config field.
class SettingsEmitter {
 public:
  template <class T>
  void operator()(const char* path, const T& x) {
    const std::string id = identifier(path);
    if constexpr (std::is_same_v<T, double>) {
      scalar("double", id, path, literal(x));
    } else if constexpr (std::is_same_v<T, bool>) {
      scalar("bool", id, path, x ? "true" : "false");
    } else if constexpr (std::is_same_v<T, int>) {
      scalar("int", id, path, std::to_string(x));
    } else if constexpr (std::is_enum_v<T>) {
      scalar("int", id, path, std::to_string(static_cast<int>(x)));
    } else if constexpr (std::is_same_v<T, std::string>) {
      scalar("const char*", id, path, quoted(x));
    } else {  // an Eigen matrix or vector, column-major
      std::string values;
      for (Eigen::Index k = 0; k < x.size(); ++k) values += (k ? ", " : "") + literal(x.data()[k]);
      members_ += "  double " + id + "[" + std::to_string(std::max<Eigen::Index>(x.size(), 1)) +
                  "] = {" + values + "};\n";
      assigns_ += "  kiloloop::set_setting(c." + std::string(path) + ", kSettings." + id + ", " +
                  std::to_string(x.rows()) + ", " + std::to_string(x.cols()) + ");\n";
    }
  }

  std::string source(const char* config_type) const {
    return "// Every controller setting, as the SIL run configured it.\nstruct Settings {\n" +
           members_ + "};\ninline constexpr Settings kSettings{};\n\n// The runtime config.\ninline " +
           config_type + " make_config() {\n  " + config_type + " c;\n" + assigns_ +
           "  return c;\n}\n";
  }

 private:
  void scalar(const char* type, const std::string& id, const char* path, const std::string& value) {
    members_ += "  " + std::string(type) + " " + id + " = " + value + ";\n";
    assigns_ += "  kiloloop::set_setting(c." + std::string(path) + ", kSettings." + id + ");\n";
  }

  std::string members_, assigns_;
};

template <class Config>
std::string emit(const Config& config, const char* type) {
  SettingsEmitter emitter;
  visit_fields(const_cast<Config&>(config), emitter);
  return emitter.source(type);
}

}  // namespace

std::string description_source(const ModelDescription& d) {
  std::string s = "// The kinematic/inertial tree: one segment per URDF joint, depth first.\n"
                  "inline constexpr kiloloop::SegmentSpec kSegments[] = {\n";
  for (int k = 0; k < d.segment_count; ++k) {
    const SegmentSpec& g = d.segments[k];
    s += "    {" + quoted(g.link) + ", " + quoted(g.joint) + ", " + quoted(g.parent) + ", " +
         kind_name(g.kind) + ",\n     " + pose(g.origin) + ",\n     {" + literal(g.axis[0]) + ", " +
         literal(g.axis[1]) + ", " + literal(g.axis[2]) + "}, " +
         (g.has_inertial ? "true" : "false") + ", " + literal(g.mass) + ",\n     " +
         pose(g.inertial) + ",\n     {";
    for (int i = 0; i < 6; ++i) s += (i ? ", " : "") + literal(g.inertia[i]);
    s += "},\n     {" + literal(g.limit.lower) + ", " + literal(g.limit.upper) + ", " +
         literal(g.limit.velocity) + ", " + literal(g.limit.effort) + "}, " +
         (g.mimic ? "true" : "false") + "},\n";
  }
  s += "};\ninline constexpr kiloloop::ModelDescription kDescription{" + quoted(d.tree_root) + ", " +
       quoted(d.urdf_root) + ", " + (d.root_inertia_restored ? "true" : "false") +
       ", kSegments, " + std::to_string(d.segment_count) + "};\n";
  return s;
}

std::string settings_source(const ComputedTorqueConfig& c) {
  return emit(c, "kiloloop::ComputedTorqueConfig");
}
std::string settings_source(const QuadrupedConfig& c) { return emit(c, "kiloloop::QuadrupedConfig"); }
std::string settings_source(const AerialConfig& c) { return emit(c, "kiloloop::AerialConfig"); }

}  // namespace kiloloop
