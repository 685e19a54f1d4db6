// IK: ArmIk (closed form + LM where it exists, LM otherwise), the UR closed form, NumericIk settings.
#include "common.hpp"
#include "kiloloop/kinematics/arm_ik.hpp"

namespace kiloloop::py_glue {
namespace {

Eigen::Isometry3d pose_arg(const Eigen::Matrix4d& T, const char* name) {
  if (T.allFinite() && (T.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).cwiseAbs().maxCoeff() > 1e-12)
    throw py::value_error(std::string(name) + ": expected a homogeneous (4, 4) transform");
  Eigen::Isometry3d out;
  out.matrix() = T;
  return out;
}

}  // namespace

void bind_kinematics(py::module_& m) {
  py::class_<NumericIkConfig>(m, "NumericIkConfig", "Levenberg-Marquardt IK settings")
      .def(py::init<>())
      .def_readwrite("max_iterations", &NumericIkConfig::max_iterations)
      .def_readwrite("restart_after", &NumericIkConfig::restart_after)
      .def_readwrite("position_tolerance", &NumericIkConfig::position_tolerance, "[m]")
      .def_readwrite("orientation_tolerance", &NumericIkConfig::orientation_tolerance, "[rad]")
      .def_readwrite("weights", &NumericIkConfig::weights, "(6) task weights [x y z rx ry rz]")
      .def_readwrite("lambda_floor", &NumericIkConfig::lambda_floor)
      .def_readwrite("mu_initial", &NumericIkConfig::mu_initial)
      .def_readwrite("joint_limits", &NumericIkConfig::joint_limits)
      .def_readwrite("unbounded_range", &NumericIkConfig::unbounded_range);

  py::class_<ArmIkConfig>(m, "ArmIkConfig")
      .def(py::init<>())
      .def_readwrite("numeric", &ArmIkConfig::numeric)
      .def_readwrite("use_analytic", &ArmIkConfig::use_analytic)
      .def_readwrite("analytic_tolerance", &ArmIkConfig::analytic_tolerance, "[m, rad]")
      .def_readwrite("refine_iterations", &ArmIkConfig::refine_iterations);

  py::class_<IkReport>(m, "IkReport")
      .def_readonly("iterations", &IkReport::iterations)
      .def_readonly("restarts", &IkReport::restarts)
      .def_readonly("position_error", &IkReport::position_error)
      .def_readonly("orientation_error", &IkReport::orientation_error);

  py::class_<ArmIk>(m, "ArmIk", "Position IK: UR closed form + LM refinement, or LM with restarts")
      .def(py::init([](std::shared_ptr<RobotModel> model, const std::optional<ArmIkConfig>& config) {
             ArmIk ik;
             std::string why;
             if (!model) throw py::value_error("model is None");
             raise_if_failed(ArmIk::configure(config.value_or(ArmIkConfig{}), *model, &ik, &why), why);
             return ik;
           }),
           py::arg("model"), py::arg("config") = py::none())
      .def_property_readonly("nq", &ArmIk::nq)
      .def_property_readonly("has_analytic", &ArmIk::has_analytic)
      .def_property_readonly("analytic_deviation", &ArmIk::analytic_deviation, "[m, rad]")
      .def("solver", [](const ArmIk& ik) { return std::string(ik.solver()); },
           "'ur_analytic' (closed form + LM refinement) or 'numeric'")
      .def("analytic_reason", &ArmIk::analytic_reason,
           "why the closed form is not used ('' when it is)")
      .def_property_readonly("report", &ArmIk::report)
      .def("solve",
           [](ArmIk& ik, const Eigen::Matrix4d& target, const Array& seed) {
             const auto s = vector_arg(seed, ik.nq(), "seed");
             Eigen::VectorXd q(ik.nq());
             const Status st = ik.solve(pose_arg(target, "target"), s, q);
             return py::make_tuple(q, st);
           },
           py::arg("target"), py::arg("seed"), "(q, status): T_root_tip(q) = target (4, 4)");

  py::class_<UrAnalyticIk>(m, "UrAnalyticIk", "Closed-form UR inverse kinematics (up to 8 solutions)")
      .def(py::init([](std::shared_ptr<RobotModel> model) {
             UrAnalyticIk ik;
             std::string why;
             if (!model) throw py::value_error("model is None");
             raise_if_failed(UrAnalyticIk::from_model(*model, &ik, &why), why);
             return ik;
           }),
           py::arg("model"))
      .def("solve",
           [](const UrAnalyticIk& ik, const Eigen::Matrix4d& target, const Array& seed) {
             const Eigen::Matrix<double, 6, 1> s = vector_arg(seed, 6, "seed");
             UrAnalyticIk::Solutions sols;
             int count = 0;
             const Status st = ik.solve(pose_arg(target, "target"), s, sols, &count);
             Eigen::MatrixXd rows = sols.leftCols(count).transpose();
             return py::make_tuple(rows, st);
           },
           py::arg("target"), py::arg("seed"),
           "(solutions (k, 6) nearest to seed first, status)")
      .def("forward",
           [](const UrAnalyticIk& ik, const Array& q) {
             return Eigen::Matrix4d(ik.forward(Eigen::Matrix<double, 6, 1>(vector_arg(q, 6, "q"))).matrix());
           },
           py::arg("q"), "T_root_tip at joint positions q: base @ DH(theta(q)) @ tool")
      .def_property_readonly(
          "dh",
          [](const UrAnalyticIk& ik) {
            const UrDhParameters& p = ik.parameters();
            py::dict d;
            d["d1"] = p.d1, d["a2"] = p.a2, d["a3"] = p.a3, d["d4"] = p.d4, d["d5"] = p.d5, d["d6"] = p.d6;
            return d;
          },
          "identified UR DH parameters {d1, a2, a3, d4, d5, d6} [m]")
      .def_property_readonly("base", [](const UrAnalyticIk& ik) { return Eigen::Matrix4d(ik.base().matrix()); },
                             "T_root_frame0 (4, 4)")
      .def_property_readonly("tool", [](const UrAnalyticIk& ik) { return Eigen::Matrix4d(ik.tool().matrix()); },
                             "T_frame6_tip (4, 4)")
      .def_property_readonly("joint_sign", &UrAnalyticIk::joint_sign, "theta = joint_sign * q + joint_offset")
      .def_property_readonly("joint_offset", &UrAnalyticIk::joint_offset, "[rad]")
      .def_property_readonly("deviation", &UrAnalyticIk::deviation, "[m, rad]");
}

}  // namespace kiloloop::py_glue
