// Cartesian line trajectory and the Cartesian tracking controller (differential IK + computed torque).
#include "common.hpp"
#include "kiloloop/arm/cartesian_tracking.hpp"
#include "kiloloop/trajectory/cartesian_line.hpp"

namespace kiloloop::py_glue {

void bind_arm(py::module_& m) {
  py::class_<CartesianLine> cartesian_line(m, "CartesianLine",
                                           "Straight line + slerp, quintic time scaling (ctraj)");
  cartesian_line.def(py::init([](const Eigen::Matrix4d& start, const Eigen::Matrix4d& end, double t0, double duration) {
             Eigen::Isometry3d a, b;
             a.matrix() = start;
             b.matrix() = end;
             CartesianLine line;
             std::string why;
             raise_if_failed(CartesianLine::configure(a, b, t0, duration, &line, &why), why);
             return line;
           }),
           py::arg("start"), py::arg("end"), py::arg("t0"), py::arg("duration"))
      .def_property_readonly("start_time", &CartesianLine::start_time)
      .def_property_readonly("end_time", &CartesianLine::end_time)
      .def_property_readonly("length", &CartesianLine::length)
      .def_property_readonly("angle", &CartesianLine::angle)
      .def("sample",
           [](const CartesianLine& line, double t) {
             Eigen::Isometry3d T;
             Vector6d v, a;
             line.sample(t, T, v, a);
             return py::make_tuple(Eigen::Matrix4d(T.matrix()), v, a);
           },
           py::arg("t"), "(pose (4, 4), twist (6), twist derivative (6)) at t [s]");

  py::class_<CartesianTrackingConfig>(m, "CartesianTrackingConfig")
      .def(py::init<>())
      .def_readwrite("joint", &CartesianTrackingConfig::joint, "ComputedTorqueConfig of the inner loop")
      .def_readwrite("dt", &CartesianTrackingConfig::dt, "[s]")
      .def_readwrite("task_gain", &CartesianTrackingConfig::task_gain, "(6) [1/s] CLIK gain")
      .def_readwrite("singular_threshold", &CartesianTrackingConfig::singular_threshold)
      .def_readwrite("max_damping", &CartesianTrackingConfig::max_damping);

  py::class_<CartesianTrackingInput> in(m, "CartesianTrackingInput");
  in.def(py::init<>())
      .def_readwrite("t", &CartesianTrackingInput::t)
      .def_readwrite("stamp", &CartesianTrackingInput::stamp)
      .def_readwrite("pose_ref", &CartesianTrackingInput::pose_ref, "(4, 4) T_root_tip reference")
      .def_readwrite("twist_ref", &CartesianTrackingInput::twist_ref, "(6) [m/s; rad/s]");
  vector_field(in, "q", &CartesianTrackingInput::q, "(nq) [rad]");
  vector_field(in, "qd", &CartesianTrackingInput::qd, "(nq) [rad/s]");

  // Bound once CartesianTrackingInput is: a signature names only types already bound (stubs).
  cartesian_line.def("sample_into",
           [](const CartesianLine& line, double t, CartesianTrackingInput& in) {
             Eigen::Isometry3d T;
             Vector6d a;
             const Status s = line.sample(t, T, in.twist_ref, a);
             in.pose_ref = T.matrix();
             return s;
           },
           py::arg("t"), py::arg("input"), "Writes pose_ref and twist_ref of a CartesianTrackingInput");

  py::class_<CartesianTrackingOutput> out(m, "CartesianTrackingOutput");
  out.def(py::init<>())
      .def_readwrite("status", &CartesianTrackingOutput::status)
      .def_readonly("task_error", &CartesianTrackingOutput::task_error, "(6) [m; rad]")
      .def_readonly("manipulability", &CartesianTrackingOutput::manipulability);
  vector_field(out, "tau", &CartesianTrackingOutput::tau, "(nq) [N m]");
  vector_field(out, "q_ref", &CartesianTrackingOutput::q_ref, "(nq) [rad]");
  vector_field(out, "qd_ref", &CartesianTrackingOutput::qd_ref, "(nq) [rad/s]");
  vector_field(out, "qdd_ref", &CartesianTrackingOutput::qdd_ref, "(nq) [rad/s^2]");

  py::class_<CartesianTrackingController>(m, "CartesianTrackingController",
                                          "Cartesian reference -> differential IK -> computed torque")
      .def(py::init([](std::shared_ptr<RobotModel> model, const std::optional<CartesianTrackingConfig>& config) {
             CartesianTrackingController c;
             std::string why;
             raise_if_failed(CartesianTrackingController::configure(
                                 config.value_or(CartesianTrackingConfig{}), model, &c, &why),
                             why);
             return c;
           }),
           py::arg("model"), py::arg("config") = py::none())
      .def("step", &CartesianTrackingController::step, py::arg("input"), py::arg("output"))
      .def("reset", &CartesianTrackingController::reset)
      .def_property_readonly("nq", &CartesianTrackingController::nq)
      .def("make_input", &CartesianTrackingController::make_input)
      .def("make_output", &CartesianTrackingController::make_output)
      .def_property_readonly("counters", &CartesianTrackingController::counters);
}

}  // namespace kiloloop::py_glue
