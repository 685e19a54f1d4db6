// Aerial manipulator: configs, the composed controller, and its parts that tests call directly
// (rotor allocation, floating-base RNE). Glue only.
#include "common.hpp"
#include "kiloloop/aerial/aerial_controller.hpp"

namespace kiloloop::py_glue {

void bind_aerial(py::module_& m) {
  py::enum_<AttitudeLawType>(m, "AttitudeLaw", "attitude control law of the aerial controller")
      .value("QUATERNION_PD", AttitudeLawType::kQuaternionPd)
      .value("GEOMETRIC_SO3", AttitudeLawType::kGeometricSo3);

  py::enum_<FlightMode>(m, "FlightMode", "position loop or attitude reference")
      .value("POSITION", FlightMode::kPosition)
      .value("ATTITUDE", FlightMode::kAttitude);
  py::enum_<ArmMode>(m, "ArmMode", "arm reference: joints or end-effector position")
      .value("JOINTS", ArmMode::kJoints)
      .value("END_EFFECTOR", ArmMode::kEndEffector);

  py::class_<AttitudeGains>(m, "AttitudeGains")
      .def(py::init<>())
      .def_readwrite("kp", &AttitudeGains::kp, "(3) [1/s^2] roll, pitch, yaw")
      .def_readwrite("kd", &AttitudeGains::kd, "(3) [1/s]")
      .def_readwrite("ki", &AttitudeGains::ki, "(3) [1/s^3]");
  py::class_<AttitudeControlConfig>(m, "AttitudeControlConfig")
      .def(py::init<>())
      .def_readwrite("law", &AttitudeControlConfig::law)
      .def_readwrite("gains", &AttitudeControlConfig::gains)
      .def_readwrite("integral_limit", &AttitudeControlConfig::integral_limit, "(3) [rad/s^2]")
      .def_readwrite("hysteresis", &AttitudeControlConfig::hysteresis);
  py::class_<PositionControlConfig>(m, "PositionControlConfig")
      .def(py::init<>())
      .def_readwrite("kp", &PositionControlConfig::kp, "(3) [1/s^2]")
      .def_readwrite("kd", &PositionControlConfig::kd, "(3) [1/s]")
      .def_readwrite("ki", &PositionControlConfig::ki, "(3) [1/s^3]")
      .def_readwrite("integral_limit", &PositionControlConfig::integral_limit, "(3) [m/s^2]")
      .def_readwrite("max_tilt", &PositionControlConfig::max_tilt, "[rad]");
  py::class_<RotorAllocationConfig>(m, "RotorAllocationConfig")
      .def(py::init<>())
      .def_readwrite("positions", &RotorAllocationConfig::positions, "(3, n) [m] base link frame")
      .def_readwrite("axes", &RotorAllocationConfig::axes, "(3, n) thrust directions; (3, 0): +z")
      .def_readwrite("spin", &RotorAllocationConfig::spin,
                     "(n) +1: counter-clockwise about the axis (drag torque along -axis)")
      .def_readwrite("torque_coefficient", &RotorAllocationConfig::torque_coefficient,
                     "(1 or n) [m] drag torque / thrust")
      .def_readwrite("thrust_min", &RotorAllocationConfig::thrust_min, "[N]")
      .def_readwrite("thrust_max", &RotorAllocationConfig::thrust_max, "(1 or n) [N]")
      .def_readwrite("lag_compensation", &RotorAllocationConfig::lag_compensation)
      .def_readwrite("time_constant", &RotorAllocationConfig::time_constant, "[s]")
      .def_readwrite("dt", &RotorAllocationConfig::dt, "[s]");

  py::class_<RotorAllocation>(m, "RotorAllocation", "body wrench [T, tau] -> n rotor thrusts")
      .def(py::init([](const std::optional<RotorAllocationConfig>& config) {
             RotorAllocation a;
             std::string why;
             raise_if_failed(RotorAllocation::configure(config.value_or(RotorAllocationConfig{}),
                                                        &a, &why),
                             why);
             return a;
           }),
           py::arg("config") = py::none())
      .def(
          "allocate",
          [](RotorAllocation& a, const Array& wrench) {
            Eigen::VectorXd f = Eigen::VectorXd::Zero(a.n());
            Eigen::Vector4d achieved;
            const Status s = a.allocate(vector_arg(wrench, 4, "wrench"), f, &achieved);
            return py::make_tuple(s, f, achieved);
          },
          py::arg("wrench"), "(status, thrust (n) [N], achieved wrench (4))")
      .def_property_readonly("n", &RotorAllocation::n)
      .def_property_readonly("mixer", &RotorAllocation::mixer, "(4, n) [T; tau] = A thrust")
      .def_property_readonly("effectiveness", &RotorAllocation::effectiveness,
                             "(6, n) [F; tau] = B thrust")
      .def_property_readonly("collective_share", &RotorAllocation::collective_share, "(n)")
      .def_property_readonly("uses_lateral_rows", &RotorAllocation::uses_lateral_rows)
      .def_property_readonly("max_collective", &RotorAllocation::max_collective, "[N]");

  py::class_<FloatingBaseRne>(m, "FloatingBaseRne", "RNE of a serial arm on a moving base")
      .def(py::init([](std::shared_ptr<RobotModel> model) {
             FloatingBaseRne r;
             std::string why;
             raise_if_failed(FloatingBaseRne::configure(model, &r, &why), why);
             return r;
           }),
           py::arg("model"))
      .def(
          "compute",
          [](FloatingBaseRne& r, const Array& q, const Array& qd, const Array& qdd,
             const Array& v, const Array& omega, const Array& specific_force,
             const Array& alpha) {
            BaseMotion base;
            base.v = vector_arg(v, 3, "v");
            base.omega = vector_arg(omega, 3, "omega");
            base.specific_force = vector_arg(specific_force, 3, "specific_force");
            base.alpha = vector_arg(alpha, 3, "alpha");
            Eigen::VectorXd tau = Eigen::VectorXd::Zero(r.nq());
            Vector6d W;
            const Status s = r.compute(vector_arg(q, r.nq(), "q"), vector_arg(qd, r.nq(), "qd"),
                                       vector_arg(qdd, r.nq(), "qdd"), base, tau, &W);
            return py::make_tuple(s, tau, W);
          },
          py::arg("q"), py::arg("qd"), py::arg("qdd"), py::arg("v"), py::arg("omega"),
          py::arg("specific_force"), py::arg("alpha"),
          "base motion in the body frame -> (status, tau (nq) [N m], wrench body->arm (6))")
      .def(
          "first_moment",
          [](const FloatingBaseRne& r, const Array& q) {
            Eigen::Vector3d moment = Eigen::Vector3d::Zero();
            double mass = 0.0;
            const Status s = r.first_moment(vector_arg(q, r.nq(), "q"), &moment, &mass);
            raise_if_failed(s, "FloatingBaseRne.first_moment: bad q");
            return py::make_tuple(moment, mass);
          },
          py::arg("q"), "(sum m_i c_i (3) [kg m] in the body frame, arm mass [kg]) at q");

  py::class_<AerialConfig>(m, "AerialConfig")
      .def(py::init<>())
      .def_readwrite("dt", &AerialConfig::dt)
      .def_readwrite("gravity", &AerialConfig::gravity)
      .def_readwrite("position", &AerialConfig::position)
      .def_readwrite("attitude", &AerialConfig::attitude)
      .def_readwrite("rotors", &AerialConfig::rotors)
      .def_readwrite("arm_kp", &AerialConfig::arm_kp)
      .def_readwrite("arm_kd", &AerialConfig::arm_kd)
      .def_readwrite("arm_q_nominal", &AerialConfig::arm_q_nominal)
      .def_readwrite("arm_viscous", &AerialConfig::arm_viscous)
      .def_readwrite("arm_coulomb", &AerialConfig::arm_coulomb)
      .def_readwrite("arm_friction_velocity", &AerialConfig::arm_friction_velocity)
      .def_readwrite("arm_friction_deadband", &AerialConfig::arm_friction_deadband)
      .def_readwrite("ik_damping", &AerialConfig::ik_damping)
      .def_readwrite("ik_iterations", &AerialConfig::ik_iterations)
      .def_readwrite("reaction_feedforward", &AerialConfig::reaction_feedforward)
      .def_readwrite("measured_acceleration", &AerialConfig::measured_acceleration)
      .def_readwrite("hold_com", &AerialConfig::hold_com)
      .def_readwrite("reaction_lead", &AerialConfig::reaction_lead)
      .def_readwrite("reaction_lead_filter", &AerialConfig::reaction_lead_filter)
      .def_readwrite("max_tilt", &AerialConfig::max_tilt)
      .def_readwrite("max_measurement_age", &AerialConfig::max_measurement_age)
      .def_readwrite("failsafe_thrust_fraction", &AerialConfig::failsafe_thrust_fraction);

  py::class_<AerialInput> in(m, "AerialInput");
  in.def(py::init<>())
      .def_readwrite("t", &AerialInput::t)
      .def_readwrite("stamp", &AerialInput::stamp)
      .def_readwrite("yaw_ref", &AerialInput::yaw_ref)
      .def_readwrite("flight_mode", &AerialInput::flight_mode)
      .def_readwrite("arm_mode", &AerialInput::arm_mode);
  vector_field(in, "position", &AerialInput::position, "(3) [m] world");
  vector_field(in, "velocity", &AerialInput::velocity, "(3) [m/s] world");
  vector_field(in, "quat", &AerialInput::quat, "(4) w, x, y, z world <- body");
  vector_field(in, "gyro", &AerialInput::gyro, "(3) [rad/s] body");
  vector_field(in, "accel", &AerialInput::accel, "(3) [m/s^2] specific force, body");
  vector_field(in, "q", &AerialInput::q, "(nq) [rad]");
  vector_field(in, "qd", &AerialInput::qd, "(nq) [rad/s]");
  vector_field(in, "position_ref", &AerialInput::position_ref, "(3) [m] world");
  vector_field(in, "velocity_ref", &AerialInput::velocity_ref, "(3) [m/s] world");
  vector_field(in, "acceleration_ref", &AerialInput::acceleration_ref, "(3) [m/s^2] world");
  vector_field(in, "quat_ref", &AerialInput::quat_ref, "(4) w, x, y, z (attitude mode)");
  vector_field(in, "q_ref", &AerialInput::q_ref, "(nq) [rad]");
  vector_field(in, "qd_ref", &AerialInput::qd_ref, "(nq) [rad/s]");
  vector_field(in, "qdd_ref", &AerialInput::qdd_ref, "(nq) [rad/s^2]");
  vector_field(in, "ee_position_ref", &AerialInput::ee_position_ref, "(3) [m] world");
  vector_field(in, "ee_velocity_ref", &AerialInput::ee_velocity_ref, "(3) [m/s] world");

  py::class_<AerialOutput> out(m, "AerialOutput");
  out.def(py::init<>())
      .def_readwrite("status", &AerialOutput::status)
      .def_readonly("tilt", &AerialOutput::tilt)
      .def_readonly("rotors_saturated", &AerialOutput::rotors_saturated)
      .def_readonly("safe_stop", &AerialOutput::safe_stop);
  vector_field(out, "thrust", &AerialOutput::thrust, "(n) [N] rotor commands");
  vector_field(out, "tau", &AerialOutput::tau, "(nq) [N m] arm torques");
  vector_field(out, "wrench", &AerialOutput::wrench, "(4) commanded T [N], tau [N m], body");
  vector_field(out, "wrench_achieved", &AerialOutput::wrench_achieved, "(4)");
  vector_field(out, "reaction", &AerialOutput::reaction, "(6) wrench body -> arm, body frame");
  vector_field(out, "acceleration_des", &AerialOutput::acceleration_des, "(3) [m/s^2] world");
  vector_field(out, "quat_des", &AerialOutput::quat_des, "(4) w, x, y, z");
  vector_field(out, "attitude_error", &AerialOutput::attitude_error, "(3) [rad] e_R");
  vector_field(out, "q_ref", &AerialOutput::q_ref, "(nq) [rad] arm target used");
  vector_field(out, "ee_position", &AerialOutput::ee_position, "(3) [m] world");

  py::class_<AerialController>(m, "AerialController",
                               "1 kHz multirotor + arm controller (model: body -> ee chain)")
      .def(py::init([](std::shared_ptr<RobotModel> model,
                       const std::optional<AerialConfig>& config) {
             AerialController c;
             std::string why;
             raise_if_failed(AerialController::configure(config.value_or(AerialConfig{}), model, &c,
                                                         &why),
                             why);
             return c;
           }),
           py::arg("model"), py::arg("config") = py::none())
      .def("step", &AerialController::step, py::arg("input"), py::arg("output"))
      .def("make_input", &AerialController::make_input)
      .def("make_output", &AerialController::make_output)
      .def("reset", &AerialController::reset,
           "clear integrators, references, the measurement order and a latched safe stop")
      .def_property_readonly("counters", &AerialController::counters)
      .def_property_readonly("nq", &AerialController::nq)
      .def_property_readonly("body_mass", &AerialController::body_mass)
      .def_property_readonly("total_mass", &AerialController::total_mass)
      .def_property_readonly("body_inertia", &AerialController::body_inertia)
      .def_property_readonly("rigid_inertia", &AerialController::rigid_inertia)
      .def_property_readonly("hover_thrust", &AerialController::hover_thrust)
      .def_property_readonly("n_rotors", &AerialController::n_rotors)
      .def_property_readonly("has_arm", &AerialController::has_arm)
      .def_property_readonly("body_com", &AerialController::body_com, "(3) [m] base link frame")
      .def_property_readonly("vehicle_com", &AerialController::vehicle_com,
                             "(3) [m] with the arm at nominal")
      .def_property_readonly("allocation", &AerialController::allocation,
                             py::return_value_policy::reference_internal);
}

}  // namespace kiloloop::py_glue
