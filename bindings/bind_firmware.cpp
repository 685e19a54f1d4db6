// kiloloop._core.firmware: what `kiloloop export` and `kiloloop b2b` need from C++ (the source
// text of a model description and of a config; the log's byte records). Thin: each call is one
// function of cpp/export/ or kiloloop/firmware/record.hpp.
#include <fstream>
#include <sstream>

#include "common.hpp"
#include "../cpp/export/firmware_export.hpp"
#include "kiloloop/firmware/record.hpp"
#include "kiloloop/urdf/urdf_description.hpp"

namespace kiloloop::py_glue {

namespace {

template <class IO>
void bind_record(py::module_& m) {
  m.def("record", [](const IO& io) {
    std::string bytes(record_bytes(io), '\0');
    write_record(io, reinterpret_cast<unsigned char*>(bytes.data()));
    return py::bytes(bytes);
  }, py::arg("io"), "the log record of a controller input or output (firmware/record.hpp)");
}

}  // namespace

void bind_firmware(py::module_& root) {
  py::module_ m = root.def_submodule("firmware", "firmware export and back-to-back log records");
  m.def("description_source", [](const std::string& urdf_path) {
    std::ifstream file(urdf_path);
    if (!file) throw py::value_error("cannot open URDF file '" + urdf_path + "'");
    std::stringstream text;
    text << file.rdbuf();
    UrdfDescription urdf;
    std::string why;
    raise_if_failed(description_from_urdf_string(text.str(), &urdf, &why, "'" + urdf_path + "'"), why);
    return description_source(urdf.description());
  }, py::arg("urdf_path"), "C++ source of the URDF's model description (constexpr, hex floats)");
  m.def("settings_source", py::overload_cast<const ComputedTorqueConfig&>(&settings_source));
  m.def("settings_source", py::overload_cast<const QuadrupedConfig&>(&settings_source));
  m.def("settings_source", py::overload_cast<const AerialConfig&>(&settings_source),
        "C++ source of a config as a constexpr Settings aggregate and make_config()");
  bind_record<JointControlInput>(m);
  bind_record<JointControlOutput>(m);
  bind_record<QuadrupedInput>(m);
  bind_record<QuadrupedOutput>(m);
  bind_record<AerialInput>(m);
  bind_record<AerialOutput>(m);
  m.attr("LOG_MAGIC") = py::bytes(kLogMagic, sizeof kLogMagic);
  m.attr("FAMILY") = py::dict(py::arg("arm") = static_cast<int>(Family::kArm),
                              py::arg("quadruped") = static_cast<int>(Family::kQuadruped),
                              py::arg("aerial") = static_cast<int>(Family::kAerial));
}

}  // namespace kiloloop::py_glue
