// Arm supervisor and singularity monitor (glue only).
#include "common.hpp"
#include "kiloloop/safety/arm_supervisor.hpp"

namespace kiloloop::py_glue {

void bind_safety(py::module_& m) {
  py::enum_<SupervisorMode>(m, "SupervisorMode")
      .value("NORMAL", SupervisorMode::kNormal)
      .value("STOPPING", SupervisorMode::kStopping)
      .value("HOLDING", SupervisorMode::kHolding);
  py::class_<SingularityMonitorConfig>(m, "SingularityMonitorConfig")
      .def(py::init<>())
      .def_readwrite("characteristic_length", &SingularityMonitorConfig::characteristic_length)
      .def_readwrite("manipulability_warn", &SingularityMonitorConfig::manipulability_warn)
      .def_readwrite("condition_warn", &SingularityMonitorConfig::condition_warn)
      .def_readwrite("horizon", &SingularityMonitorConfig::horizon);
  py::class_<SingularityState>(m, "SingularityState")
      .def(py::init<>())
      .def_readonly("manipulability", &SingularityState::manipulability)
      .def_readonly("condition", &SingularityState::condition)
      .def_readonly("sigma_min", &SingularityState::sigma_min)
      .def_readonly("rate", &SingularityState::rate)
      .def_readonly("warning", &SingularityState::warning);
  py::class_<ArmSupervisorConfig>(m, "ArmSupervisorConfig")
      .def(py::init<>())
      .def_readwrite("gravity", &ArmSupervisorConfig::gravity)
      .def_readwrite("lower", &ArmSupervisorConfig::lower)
      .def_readwrite("upper", &ArmSupervisorConfig::upper)
      .def_readwrite("velocity_limit", &ArmSupervisorConfig::velocity_limit)
      .def_readwrite("acceleration_limit", &ArmSupervisorConfig::acceleration_limit)
      .def_readwrite("effort_limit", &ArmSupervisorConfig::effort_limit)
      .def_readwrite("stop_deceleration", &ArmSupervisorConfig::stop_deceleration)
      .def_readwrite("peak_trip_ratio", &ArmSupervisorConfig::peak_trip_ratio)
      .def_readwrite("rated_torque_fraction", &ArmSupervisorConfig::rated_torque_fraction)
      .def_readwrite("thermal_time_constant", &ArmSupervisorConfig::thermal_time_constant)
      .def_readwrite("acceleration_filter", &ArmSupervisorConfig::acceleration_filter)
      .def_readwrite("max_measurement_age", &ArmSupervisorConfig::max_measurement_age)
      .def_readwrite("max_bad_ticks", &ArmSupervisorConfig::max_bad_ticks)
      .def_readwrite("stop_kp", &ArmSupervisorConfig::stop_kp)
      .def_readwrite("stop_kd", &ArmSupervisorConfig::stop_kd)
      .def_readwrite("singularity", &ArmSupervisorConfig::singularity);

  py::class_<SupervisorInput> in(m, "SupervisorInput");
  in.def(py::init<>())
      .def_readwrite("t", &SupervisorInput::t)
      .def_readwrite("stamp", &SupervisorInput::stamp)
      .def_readwrite("estop", &SupervisorInput::estop)
      .def_readwrite("reset", &SupervisorInput::reset);
  vector_field(in, "q", &SupervisorInput::q, "(nq) [rad]");
  vector_field(in, "qd", &SupervisorInput::qd, "(nq) [rad/s]");
  vector_field(in, "tau_command", &SupervisorInput::tau_command, "(nq) [N m] the controller's torque");
  py::class_<SupervisorOutput> out(m, "SupervisorOutput");
  out.def(py::init<>())
      .def_readonly("mode", &SupervisorOutput::mode)
      .def_readonly("status", &SupervisorOutput::status)
      .def_readonly("trip", &SupervisorOutput::trip)
      .def_readonly("singularity", &SupervisorOutput::singularity)
      .def_readonly("stop_time", &SupervisorOutput::stop_time);
  vector_field(out, "tau", &SupervisorOutput::tau, "(nq) [N m] to the motors");
  vector_field(out, "thermal", &SupervisorOutput::thermal, "(nq) I^2 t state (trips at 1)");
  // Step statuses (StatusCounters) plus the supervisor's events.
  py::class_<SupervisorCounters, StatusCounters>(m, "SupervisorCounters")
      .def_readonly("estops", &SupervisorCounters::estops)
      .def_readonly("position_trips", &SupervisorCounters::position_trips)
      .def_readonly("velocity_trips", &SupervisorCounters::velocity_trips)
      .def_readonly("acceleration_trips", &SupervisorCounters::acceleration_trips)
      .def_readonly("overload_trips", &SupervisorCounters::overload_trips)
      .def_readonly("bad_command_trips", &SupervisorCounters::bad_command_trips)
      .def_readonly("clipped", &SupervisorCounters::clipped, "ticks with clipped torque")
      .def_readonly("singularity_warnings", &SupervisorCounters::singularity_warnings)
      .def_property_readonly("bad_measurement", &SupervisorCounters::bad_measurements)
      .def_readonly("measurement_trips", &SupervisorCounters::measurement_trips)
      .def_readonly("resets", &SupervisorCounters::resets);
  py::class_<ArmSupervisor>(m, "ArmSupervisor",
                            "Limits, I^2 t overload, singularity warning, e-stop -> controlled stop and hold")
      .def(py::init([](std::shared_ptr<RobotModel> model, const std::optional<ArmSupervisorConfig>& config) {
             ArmSupervisor s;
             std::string why;
             raise_if_failed(ArmSupervisor::configure(config.value_or(ArmSupervisorConfig{}), model, &s, &why), why);
             return s;
           }),
           py::arg("model"), py::arg("config") = py::none())
      .def("step", &ArmSupervisor::step, py::arg("input"), py::arg("output"))
      .def_property_readonly("nq", &ArmSupervisor::nq)
      .def_property_readonly("mode", &ArmSupervisor::mode)
      .def("make_input", &ArmSupervisor::make_input)
      .def("make_output", &ArmSupervisor::make_output)
      .def("reset", &ArmSupervisor::reset,
           "forget the measurement order (leaving a stop is input.reset)")
      .def_property_readonly("counters", &ArmSupervisor::counters);
}

}  // namespace kiloloop::py_glue
