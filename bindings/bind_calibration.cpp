// Kinematic calibration (offline): parameters, identification, residuals.
#include "common.hpp"
#include "kiloloop/calibration/kinematic_calibration.hpp"

namespace kiloloop::py_glue {

void bind_calibration(py::module_& m) {
  py::class_<KinematicParameters>(m, "KinematicParameters",
                                  "Modified DH + beta (parallel axes), base and tool point")
      .def_static(
          "from_ur_model",
          [](std::shared_ptr<RobotModel> model, const Eigen::Vector3d& tool_point) {
            if (!model) throw py::value_error("model is None");
            KinematicParameters k;
            std::string why;
            raise_if_failed(KinematicParameters::from_ur_model(*model, tool_point, &k, &why), why);
            return k;
          },
          py::arg("model"), py::arg("tool_point") = Eigen::Vector3d::Zero(),
          "Nominal parameters of a UR-shaped model (DH and base read off the model), tool point in tool0")
      .def_property_readonly("nq", &KinematicParameters::nq)
      .def_property_readonly("has_beta", [](const KinematicParameters& k) { return k.has_beta; })
      .def_property(
          "vector", &KinematicParameters::pack,
          [](KinematicParameters& k, const Eigen::VectorXd& x) {
            if (!k.unpack(x))
              throw py::value_error("vector: expected shape (" + std::to_string(k.size()) + ",)");
          },
          "[base_position(3), base_rotation(3), alpha(n), a(n), beta(n), theta(n), d(n), tool(3)]")
      .def("position",
           [](const KinematicParameters& k, const Array& q) {
             return Eigen::Vector3d(k.position(vector_arg(q, k.nq(), "q")));
           },
           py::arg("q"), "measured point [m] at q");

  py::class_<CalibrationConfig>(m, "CalibrationConfig")
      .def(py::init<>())
      .def_readwrite("max_iterations", &CalibrationConfig::max_iterations)
      .def_readwrite("step_tolerance", &CalibrationConfig::step_tolerance)
      .def_readwrite("rank_tolerance", &CalibrationConfig::rank_tolerance)
      .def_readwrite("finite_difference", &CalibrationConfig::finite_difference)
      .def_readwrite("identify_beta", &CalibrationConfig::identify_beta)
      .def_readwrite("length_range", &CalibrationConfig::length_range)
      .def_readwrite("angle_range", &CalibrationConfig::angle_range);

  py::class_<CalibrationResult>(m, "CalibrationResult")
      .def_readonly("parameters", &CalibrationResult::parameters)
      .def_readonly("iterations", &CalibrationResult::iterations)
      .def_readonly("num_parameters", &CalibrationResult::num_parameters)
      .def_readonly("rank", &CalibrationResult::rank)
      .def_readonly("condition_number", &CalibrationResult::condition_number)
      .def_readonly("observability_index", &CalibrationResult::observability_index)
      .def_readonly("rms_residual", &CalibrationResult::rms_residual)
      .def_readonly("rms_residual_nominal", &CalibrationResult::rms_residual_nominal);

  m.def(
      "calibrate_kinematics",
      [](const KinematicParameters& nominal, const Eigen::MatrixXd& q, const Eigen::MatrixXd& p,
         const std::optional<CalibrationConfig>& config) {
        // Python passes one sample per row: q (m, n), p (m, 3).
        if (q.cols() != nominal.nq()) throw py::value_error("q: expected shape (m, nq)");
        if (p.cols() != 3 || p.rows() != q.rows()) throw py::value_error("p: expected shape (m, 3)");
        CalibrationResult res;
        std::string why;
        raise_if_failed(calibrate_kinematics(nominal, q.transpose(), p.transpose(),
                                             config.value_or(CalibrationConfig{}), &res, &why),
                        why);
        return res;
      },
      py::arg("nominal"), py::arg("q"), py::arg("p"), py::arg("config") = py::none(),
      "Least-squares identification from measured positions p (m, 3) at q (m, nq)");
  m.def(
      "position_residuals",
      [](const KinematicParameters& k, const Eigen::MatrixXd& q, const Eigen::MatrixXd& p) {
        if (q.cols() != k.nq() || p.cols() != 3 || p.rows() != q.rows())
          throw py::value_error("q: expected (m, nq) and p: (m, 3)");
        double rms, max;
        position_residuals(k, q.transpose(), p.transpose(), &rms, &max);
        return py::make_tuple(rms, max);
      },
      py::arg("params"), py::arg("q"), py::arg("p"), "(rms, max) of |p - position(q)| [m]");
}

}  // namespace kiloloop::py_glue
