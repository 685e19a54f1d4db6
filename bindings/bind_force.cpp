// Cartesian impedance and hybrid force/position controllers (glue only).
#include "common.hpp"
#include "kiloloop/control/cartesian_impedance.hpp"
#include "kiloloop/control/hybrid_force_position.hpp"

namespace kiloloop::py_glue {
namespace {

template <class Controller, class Config>
py::class_<Controller> bind_cartesian_controller(py::module_& m, const char* name, const char* doc) {
  py::class_<Controller> cls(m, name, doc);
  cls.def(py::init([](std::shared_ptr<RobotModel> model, const std::optional<Config>& config) {
            Controller c;
            std::string why;
            raise_if_failed(Controller::configure(config.value_or(Config{}), model, &c, &why), why);
            return c;
          }),
          py::arg("model"), py::arg("config") = py::none())
      .def("step", &Controller::step, py::arg("input"), py::arg("output"),
           "One tick: writes output.tau, returns the Status (also in output.status)")
      .def_property_readonly("nq", &Controller::nq)
      .def("make_input", &Controller::make_input)
      .def("make_output", &Controller::make_output)
      .def_property_readonly("tip_pose", &Controller::tip_pose)
      .def("reset", &Controller::reset,
           "forget the last valid state and the measurement order; clear the law's own state")
      .def_property_readonly("counters", &Controller::counters);
  return cls;
}

}  // namespace

void bind_force(py::module_& m) {
  py::class_<CartesianControlInput> in(m, "CartesianControlInput");
  in.def(py::init<>())
      .def_readwrite("t", &CartesianControlInput::t, "[s] controller time of this tick")
      .def_readwrite("stamp", &CartesianControlInput::stamp, "[s] when the measurement was sampled");
  vector_field(in, "q", &CartesianControlInput::q, "(nq) [rad]");
  vector_field(in, "qd", &CartesianControlInput::qd, "(nq) [rad/s]");
  vector_field(in, "p_ref", &CartesianControlInput::p_ref, "(3) [m] tip position reference");
  vector_field(in, "R_ref", &CartesianControlInput::R_ref, "(3,3) tip orientation reference");
  vector_field(in, "twist_ref", &CartesianControlInput::twist_ref, "(6) [m/s; rad/s]");
  vector_field(in, "accel_ref", &CartesianControlInput::accel_ref, "(6) [m/s^2; rad/s^2]");
  vector_field(in, "wrench_ref", &CartesianControlInput::wrench_ref, "(6) [N; N m] wrench to apply");
  vector_field(in, "wrench_measured", &CartesianControlInput::wrench_measured,
               "(6) [N; N m] measured wrench the tip applies on the environment");
  py::class_<CartesianControlOutput> out(m, "CartesianControlOutput");
  out.def(py::init<>()).def_readwrite("status", &CartesianControlOutput::status);
  vector_field(out, "tau", &CartesianControlOutput::tau, "(nq) [N m]");
  vector_field(out, "pose_error", &CartesianControlOutput::pose_error, "(6) [m; rad]");
  vector_field(out, "wrench_command", &CartesianControlOutput::wrench_command, "(6) [N; N m]");
  // counters: StatusCounters (bind_status.cpp).

  py::class_<CartesianCommonConfig>(m, "CartesianCommonConfig")
      .def(py::init<>())
      .def_readwrite("gravity", &CartesianCommonConfig::gravity)
      .def_readwrite("max_measurement_age", &CartesianCommonConfig::max_measurement_age)
      .def_readwrite("singular_damping", &CartesianCommonConfig::singular_damping)
      .def_readwrite("stop_damping", &CartesianCommonConfig::stop_damping);
  py::class_<CartesianImpedanceConfig>(m, "CartesianImpedanceConfig")
      .def(py::init<>())
      .def_readwrite("common", &CartesianImpedanceConfig::common)
      .def_readwrite("stiffness", &CartesianImpedanceConfig::stiffness)
      .def_readwrite("damping_ratio", &CartesianImpedanceConfig::damping_ratio);
  py::class_<HybridForcePositionConfig>(m, "HybridForcePositionConfig")
      .def(py::init<>())
      .def_readwrite("common", &HybridForcePositionConfig::common)
      .def_readwrite("selection", &HybridForcePositionConfig::selection)
      .def_readwrite("task_rotation", &HybridForcePositionConfig::task_rotation)
      .def_readwrite("kp", &HybridForcePositionConfig::kp)
      .def_readwrite("kd", &HybridForcePositionConfig::kd)
      .def_readwrite("kf", &HybridForcePositionConfig::kf)
      .def_readwrite("ki", &HybridForcePositionConfig::ki)
      .def_readwrite("kv", &HybridForcePositionConfig::kv)
      .def_readwrite("integral_limit", &HybridForcePositionConfig::integral_limit)
      .def_readwrite("project_motion_wrench", &HybridForcePositionConfig::project_motion_wrench);

  bind_cartesian_controller<CartesianImpedanceController, CartesianImpedanceConfig>(
      m, "CartesianImpedanceController", "F = Lambda a_ref + K e + D (v_ref - v); tau = J^T F + C qd + g");
  bind_cartesian_controller<HybridForcePositionController, HybridForcePositionConfig>(
      m, "HybridForcePositionController", "selection-matrix hybrid force/motion control (operational space)")
      .def_property_readonly("force_integral", &HybridForcePositionController::force_integral);
}

}  // namespace kiloloop::py_glue
