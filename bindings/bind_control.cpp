#include "common.hpp"
#include "kiloloop/control/computed_torque.hpp"
#include "kiloloop/control/joint_pd_gravity.hpp"

namespace kiloloop::py_glue {
namespace {

template <class Config>
void bind_joint_config(py::module_& m, const char* name) {
  py::class_<Config>(m, name)
      .def(py::init<>())
      .def_readwrite("kp", &Config::kp)
      .def_readwrite("kd", &Config::kd)
      .def_readwrite("gravity", &Config::gravity)
      .def_readwrite("max_measurement_age", &Config::max_measurement_age)
      .def_readwrite("friction", &Config::friction);
}

template <class Controller, class Config>
void bind_joint_controller(py::module_& m, const char* name, const char* doc) {
  py::class_<Controller>(m, name, doc)
      .def(py::init([](std::shared_ptr<RobotModel> model, const std::optional<Config>& config) {
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
      .def("reset", &Controller::reset, "forget the last valid state and the measurement order")
      .def_property_readonly("counters", &Controller::counters);
}

}  // namespace

void bind_control(py::module_& m) {
  py::class_<JointFrictionConfig>(m, "JointFrictionConfig",
                                  "Compensated joint friction: b qd_ref + fc tanh(qd_ref / v_s)")
      .def(py::init<>())
      .def_readwrite("viscous", &JointFrictionConfig::viscous, "(1 or nq) [N m s/rad]")
      .def_readwrite("coulomb", &JointFrictionConfig::coulomb, "(1 or nq) [N m]")
      .def_readwrite("smoothing_speed", &JointFrictionConfig::smoothing_speed, "[rad/s]");

  py::class_<JointControlInput> in(m, "JointControlInput");
  in.def(py::init<>())
      .def_readwrite("t", &JointControlInput::t, "[s] controller time of this tick")
      .def_readwrite("stamp", &JointControlInput::stamp, "[s] time the measurement was sampled");
  vector_field(in, "q", &JointControlInput::q, "(nq) [rad] measured position");
  vector_field(in, "qd", &JointControlInput::qd, "(nq) [rad/s] measured velocity");
  vector_field(in, "q_ref", &JointControlInput::q_ref, "(nq) [rad] reference position");
  vector_field(in, "qd_ref", &JointControlInput::qd_ref, "(nq) [rad/s] reference velocity");
  vector_field(in, "qdd_ref", &JointControlInput::qdd_ref, "(nq) [rad/s^2] reference acceleration");

  py::class_<JointControlOutput> out(m, "JointControlOutput");
  out.def(py::init<>()).def_readwrite("status", &JointControlOutput::status);
  vector_field(out, "tau", &JointControlOutput::tau, "(nq) [N m] torque command");

  // counters: StatusCounters (bind_status.cpp).

  bind_joint_config<ComputedTorqueConfig>(m, "ComputedTorqueConfig");
  bind_joint_config<JointPdGravityConfig>(m, "JointPdGravityConfig");
  bind_joint_controller<ComputedTorqueController, ComputedTorqueConfig>(
      m, "ComputedTorqueController", "tau = M(q)(qdd_ref + Kd e_dot + Kp e) + C(q,qd)qd + g(q)");
  bind_joint_controller<JointPdGravityController, JointPdGravityConfig>(
      m, "JointPdGravityController", "tau = Kp e + Kd e_dot + g(q)");
}

}  // namespace kiloloop::py_glue
