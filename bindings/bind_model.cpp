#include <fstream>

#include "common.hpp"
#include "kiloloop/model/dh.hpp"
#include "kiloloop/urdf/urdf_loader.hpp"

namespace kiloloop::py_glue {
namespace {

// A path or the URDF text itself: text starts with '<' once leading whitespace is skipped.
std::shared_ptr<RobotModel> from_urdf(const std::string& path_or_xml,
                                      const std::optional<std::string>& root,
                                      const std::optional<std::string>& tip,
                                      const std::optional<std::map<std::string, double>>& locked_arg) {
  auto model = std::make_shared<RobotModel>();
  std::string why;
  const std::map<std::string, double> locked = locked_arg.value_or(std::map<std::string, double>{});
  const auto first = path_or_xml.find_first_not_of(" \t\r\n");
  Status s;
  if (first != std::string::npos && path_or_xml[first] == '<') {
    s = model_from_urdf_string(path_or_xml, root.value_or(""), tip.value_or(""), locked, model.get(),
                               &why);
  } else {
    if (!std::ifstream(path_or_xml)) {
      PyErr_SetString(PyExc_FileNotFoundError, ("URDF file not found: '" + path_or_xml + "'").c_str());
      throw py::error_already_set();
    }
    s = model_from_urdf_file(path_or_xml, root.value_or(""), tip.value_or(""), locked, model.get(),
                             &why);
  }
  raise_if_failed(s, why);
  return model;
}

}  // namespace

void bind_model(py::module_& m) {
  py::class_<JointLimit>(m, "JointLimit")
      .def(py::init<>())
      .def_readwrite("lower", &JointLimit::lower)
      .def_readwrite("upper", &JointLimit::upper)
      .def_readwrite("velocity", &JointLimit::velocity)
      .def_readwrite("effort", &JointLimit::effort);

  py::class_<DhLink>(m, "DhLink", "One row of a DH table with its link's mass properties (frame i)")
      .def(py::init<>())
      .def_readwrite("a", &DhLink::a)
      .def_readwrite("alpha", &DhLink::alpha)
      .def_readwrite("d", &DhLink::d)
      .def_readwrite("theta", &DhLink::theta)
      .def_readwrite("prismatic", &DhLink::prismatic)
      .def_readwrite("mass", &DhLink::mass)
      .def_readwrite("com", &DhLink::com)
      .def_readwrite("inertia", &DhLink::inertia)
      .def_readwrite("limit", &DhLink::limit)
      .def_readwrite("name", &DhLink::name);

  py::class_<RobotModel, std::shared_ptr<RobotModel>>(m, "RobotModel",
                                                       "Immutable robot description (KDL tree/chain, names, limits)")
      .def_static("from_urdf", &from_urdf, py::arg("path_or_xml"), py::arg("root") = py::none(),
                  py::arg("tip") = py::none(), py::arg("locked") = py::none(),
                  "Load a URDF file or XML string; with tip (and optionally root) select a serial chain.\n"
                  "Everything off the chain is folded into it as rigid mass; `locked` maps off-chain\n"
                  "joint names to the positions [rad or m] they are frozen at (default 0).")
      .def_static(
          "from_dh",
          [](const std::vector<DhLink>& links, const std::string& convention) {
            if (convention != "standard" && convention != "modified")
              throw py::value_error("convention: expected 'standard' or 'modified'");
            auto model = std::make_shared<RobotModel>();
            std::string why;
            raise_if_failed(model_from_dh(links, convention == "standard" ? DhConvention::kStandard
                                                                          : DhConvention::kModified,
                                          model.get(), &why),
                            why);
            return model;
          },
          py::arg("links"), py::arg("convention") = "standard")
      .def_property_readonly("nq", &RobotModel::nq)
      .def_property_readonly("joint_names", &RobotModel::joint_names)
      .def_property_readonly("lower", &RobotModel::lower)
      .def_property_readonly("upper", &RobotModel::upper)
      .def_property_readonly("velocity_limit", &RobotModel::velocity_limit)
      .def_property_readonly("effort_limit", &RobotModel::effort_limit)
      .def_property_readonly("armature", &RobotModel::armature,
                             "(nq) [kg m^2] reflected rotor inertia of the chain joints")
      .def(
          "with_armature",
          [](const RobotModel& self, const Eigen::VectorXd& armature) {
            auto model = std::make_shared<RobotModel>();
            std::string why;
            raise_if_failed(self.with_armature(armature, model.get(), &why), why);
            return model;
          },
          py::arg("armature"),
          "A copy whose chain joints carry armature [kg m^2] (one per joint): every Dynamics\n"
          "solver adds it to M's diagonal and a * qdd to the torque (MuJoCo's joint armature).")
      .def_property_readonly("has_chain", &RobotModel::has_chain)
      .def_property_readonly("root_name", &RobotModel::root_name)
      .def_property_readonly("tip_name", &RobotModel::tip_name)
      .def_property_readonly("total_mass", &RobotModel::total_mass)
      .def_property_readonly("root_inertia_restored", &RobotModel::root_inertia_restored)
      .def_property_readonly(
          "folded_links",
          [](const RobotModel& r) {
            std::vector<std::tuple<std::string, std::string, double>> out;
            for (const FoldedLink& f : r.folded()) out.emplace_back(f.link, f.onto, f.mass);
            return out;
          },
          "[(link, onto_chain_segment, mass [kg])]: links folded into the chain as rigid mass")
      .def_property_readonly("locked", &RobotModel::locked,
                             "{joint: position}: off-chain joint positions used for folding")
      .def("__repr__", [](const RobotModel& r) {
        return "<RobotModel nq=" + std::to_string(r.nq()) + " root='" + r.root_name() + "' tip='" +
               r.tip_name() + "'>";
      });
}

}  // namespace kiloloop::py_glue
