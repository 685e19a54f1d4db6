#include "firmware_export.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <type_traits>
#include <vector>

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

// "gait.period" -> {"gait", "period"}, "feet[0]" -> {"feet_0"}: member names along a field path.
std::vector<std::string> members_of(const char* path) {
  std::vector<std::string> out(1);
  for (const char* c = path; *c; ++c) {
    if (*c == '.') out.emplace_back();
    else if (*c == '[') out.back() += '_';
    else if (*c != ']') out.back() += *c;
  }
  return out;
}

std::string joined(const std::vector<std::string>& parts) {
  std::string s;
  for (const auto& p : parts) s += (s.empty() ? "" : ".") + p;
  return s;
}

// One constexpr member per config field, nested like the config ("gait.period" is
// kSettings.gait.period), and one make_config() line per field.
class SettingsEmitter {
 public:
  template <class T>
  void operator()(const char* path, const T& x) {
    std::vector<std::string> member = members_of(path);
    enter(std::vector<std::string>(member.begin(), member.end() - 1));
    const std::string name = member.back(), access = "kSettings." + joined(member);
    if constexpr (std::is_same_v<T, double>) {
      scalar("double", name, path, access, literal(x));
    } else if constexpr (std::is_same_v<T, bool>) {
      scalar("bool", name, path, access, x ? "true" : "false");
    } else if constexpr (std::is_same_v<T, int>) {
      scalar("int", name, path, access, std::to_string(x));
    } else if constexpr (std::is_enum_v<T>) {
      scalar("int", name, path, access, std::to_string(static_cast<int>(x)));
    } else if constexpr (std::is_same_v<T, std::string>) {
      scalar("const char*", name, path, access, quoted(x));
    } else {  // an Eigen matrix or vector, column-major
      std::string values;
      for (Eigen::Index k = 0; k < x.size(); ++k) values += (k ? ", " : "") + literal(x.data()[k]);
      members_ += indent() + "double " + name + "[" +
                  std::to_string(std::max<Eigen::Index>(x.size(), 1)) + "] = {" + values + "};\n";
      assigns_ += "  kiloloop::set_setting(c." + std::string(path) + ", " + access + ", " +
                  std::to_string(x.rows()) + ", " + std::to_string(x.cols()) + ");\n";
    }
  }

  std::string source(const char* config_type) {
    enter({});
    return "// Every controller setting, as the SIL run configured it.\nstruct Settings {\n" +
           members_ + "};\ninline constexpr Settings kSettings{};\n\n// The runtime config.\ninline " +
           config_type + " make_config() {\n  " + config_type + " c;\n" + assigns_ +
           "  return c;\n}\n";
  }

 private:
  // Closes the nested structs that `scope` leaves and opens those it enters.
  void enter(const std::vector<std::string>& scope) {
    std::size_t common = 0;
    while (common < open_.size() && common < scope.size() && open_[common] == scope[common]) ++common;
    while (open_.size() > common) {
      const std::string name = open_.back();
      open_.pop_back();
      members_ += indent() + "} " + name + ";\n";
    }
    for (std::size_t k = common; k < scope.size(); ++k) {
      members_ += indent() + "struct {\n";
      open_.push_back(scope[k]);
    }
  }
  std::string indent() const { return std::string(2 * (open_.size() + 1), ' '); }
  void scalar(const char* type, const std::string& name, const char* path,
              const std::string& access, const std::string& value) {
    members_ += indent() + type + " " + name + " = " + value + ";\n";
    assigns_ += "  kiloloop::set_setting(c." + std::string(path) + ", " + access + ");\n";
  }

  std::string members_, assigns_;
  std::vector<std::string> open_;  // the nested structs open at the end of members_
};

template <class Config>
std::string emit(const Config& config, const char* type) {
  SettingsEmitter emitter;
  visit_fields(const_cast<Config&>(config), emitter);  // the lists only read
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
