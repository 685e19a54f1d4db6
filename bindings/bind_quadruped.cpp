#include "common.hpp"
#include "kiloloop/quadruped/quadruped_controller.hpp"

namespace kiloloop::py_glue {

void bind_quadruped(py::module_& m) {
  py::class_<GaitConfig>(m, "GaitConfig")
      .def(py::init<>())
      .def_readwrite("period", &GaitConfig::period)
      .def_readwrite("duty", &GaitConfig::duty);
  py::class_<ContactConfig>(m, "ContactConfig")
      .def(py::init<>())
      .def_readwrite("force_on", &ContactConfig::force_on)
      .def_readwrite("force_off", &ContactConfig::force_off)
      .def_readwrite("early_touchdown", &ContactConfig::early_touchdown)
      .def_readwrite("touchdown_clearance", &ContactConfig::touchdown_clearance);
  py::class_<AttitudeFilterConfig>(m, "AttitudeFilterConfig")
      .def(py::init<>())
      .def_readwrite("gyro_noise_density", &AttitudeFilterConfig::gyro_noise_density)
      .def_readwrite("accel_noise_density", &AttitudeFilterConfig::accel_noise_density)
      .def_readwrite("crossover", &AttitudeFilterConfig::crossover)
      .def_readwrite("accel_tolerance", &AttitudeFilterConfig::accel_tolerance)
      .def_readwrite("max_gyro_bias", &AttitudeFilterConfig::max_gyro_bias)
      .def_readwrite("gyro_bias_random_walk", &AttitudeFilterConfig::gyro_bias_random_walk)
      .def_readwrite("gyro_turn_on_bias", &AttitudeFilterConfig::gyro_turn_on_bias);
  py::class_<EstimatorConfig>(m, "EstimatorConfig")
      .def(py::init<>())
      .def_readwrite("external_attitude", &EstimatorConfig::external_attitude)
      .def_readwrite("attitude", &EstimatorConfig::attitude)
      .def_readwrite("attitude_gain", &EstimatorConfig::attitude_gain)
      .def_readwrite("velocity_aiding", &EstimatorConfig::velocity_aiding)
      .def_readwrite("accel_noise", &EstimatorConfig::accel_noise)
      .def_readwrite("leg_velocity_noise", &EstimatorConfig::leg_velocity_noise)
      .def_readwrite("foothold_noise", &EstimatorConfig::foothold_noise)
      .def_readwrite("velocity_gate", &EstimatorConfig::velocity_gate)
      .def_readwrite("ground_filter", &EstimatorConfig::ground_filter)
      .def("validate", [](const EstimatorConfig& c) {
        std::string why;
        raise_if_failed(validate(c, &why), why);
      }, "raises ValueError with the reason when a setting is out of range");
  py::class_<StanceForceConfig>(m, "StanceForceConfig")
      .def(py::init<>())
      .def_readwrite("wrench_weight", &StanceForceConfig::wrench_weight)
      .def_readwrite("regularization", &StanceForceConfig::regularization)
      .def_readwrite("smoothing", &StanceForceConfig::smoothing)
      .def_readwrite("mu", &StanceForceConfig::mu)
      .def_readwrite("fz_min", &StanceForceConfig::fz_min)
      .def_readwrite("fz_max", &StanceForceConfig::fz_max)
      .def_readwrite("max_iterations", &StanceForceConfig::max_iterations);

  py::enum_<Gait>(m, "Gait", "gait the quadruped is asked for")
      .value("STAND", Gait::kStand)
      .value("TROT", Gait::kTrot);
  py::implicitly_convertible<py::int_, Gait>();

  py::enum_<KneeDirection>(m, "KneeDirection", "which way a leg's knee bends")
      .value("AUTO", KneeDirection::kAuto)
      .value("BACKWARD", KneeDirection::kBackward)
      .value("FORWARD", KneeDirection::kForward);

  py::class_<QuadrupedConfig>(m, "QuadrupedConfig")
      .def(py::init<>())
      .def_readwrite("trunk_link", &QuadrupedConfig::trunk_link)
      .def_readwrite("feet", &QuadrupedConfig::feet)
      .def_readwrite("knees", &QuadrupedConfig::knees)
      .def_readwrite("stand_extension", &QuadrupedConfig::stand_extension)
      .def_readwrite("crouch_extension", &QuadrupedConfig::crouch_extension)
      .def_readwrite("contact_force_on", &QuadrupedConfig::contact_force_on)
      .def_readwrite("contact_force_off", &QuadrupedConfig::contact_force_off)
      .def_readwrite("fz_min", &QuadrupedConfig::fz_min)
      .def_readwrite("fz_max", &QuadrupedConfig::fz_max)
      .def_readwrite("swing_frequency", &QuadrupedConfig::swing_frequency)
      .def_readwrite("swing_damping", &QuadrupedConfig::swing_damping)
      .def_readwrite("swing_damping_predicted", &QuadrupedConfig::swing_damping_predicted)
      .def_readwrite("swing_delay_margin", &QuadrupedConfig::swing_delay_margin)
      .def_readwrite("trunk_delay_margin", &QuadrupedConfig::trunk_delay_margin)
      .def_readwrite("safe_stiffness", &QuadrupedConfig::safe_stiffness)
      .def_readwrite("safe_time_constant", &QuadrupedConfig::safe_time_constant)
      .def_readwrite("dt", &QuadrupedConfig::dt)
      .def_readwrite("foot_radius", &QuadrupedConfig::foot_radius)
      .def_readwrite("foot_offset", &QuadrupedConfig::foot_offset)
      .def_readwrite("body_height", &QuadrupedConfig::body_height)
      .def_readwrite("gait", &QuadrupedConfig::gait)
      .def_readwrite("contact", &QuadrupedConfig::contact)
      .def_readwrite("estimator", &QuadrupedConfig::estimator)
      .def_readwrite("force", &QuadrupedConfig::force)
      .def_readwrite("kp_position", &QuadrupedConfig::kp_position)
      .def_readwrite("kd_velocity", &QuadrupedConfig::kd_velocity)
      .def_readwrite("kp_orientation", &QuadrupedConfig::kp_orientation)
      .def_readwrite("kd_angular", &QuadrupedConfig::kd_angular)
      .def_readwrite("swing_height", &QuadrupedConfig::swing_height)
      .def_readwrite("raibert_gain", &QuadrupedConfig::raibert_gain)
      .def_readwrite("touchdown_depth", &QuadrupedConfig::touchdown_depth)
      .def_readwrite("foothold_shift", &QuadrupedConfig::foothold_shift)
      .def_readwrite("swing_feedforward", &QuadrupedConfig::swing_feedforward)
      .def_readwrite("predict_swing", &QuadrupedConfig::predict_swing)
      .def_readwrite("swing_inertia_at_pose", &QuadrupedConfig::swing_inertia_at_pose)
      .def_readwrite("swing_predict_from", &QuadrupedConfig::swing_predict_from)
      .def_readwrite("swing_prediction_residual", &QuadrupedConfig::swing_prediction_residual)
      .def_readwrite("swing_kp", &QuadrupedConfig::swing_kp)
      .def_readwrite("swing_kd", &QuadrupedConfig::swing_kd)
      .def_readwrite("max_acceleration", &QuadrupedConfig::max_acceleration)
      .def_readwrite("actuation_delay", &QuadrupedConfig::actuation_delay)
      .def_readwrite("predict_in_flight", &QuadrupedConfig::predict_in_flight)
      .def_readwrite("predict_legs_free", &QuadrupedConfig::predict_legs_free)
      .def_readwrite("predict_leg_dynamics", &QuadrupedConfig::predict_leg_dynamics)
      .def_readwrite("trust_ramp", &QuadrupedConfig::trust_ramp)
      .def_readwrite("load_ramp", &QuadrupedConfig::load_ramp)
      .def_readwrite("max_position_lag", &QuadrupedConfig::max_position_lag)
      .def_readwrite("swing_reaction_feedforward", &QuadrupedConfig::swing_reaction_feedforward)
      .def_readwrite("max_tilt", &QuadrupedConfig::max_tilt)
      .def_readwrite("safe_kp", &QuadrupedConfig::safe_kp)
      .def_readwrite("safe_kd", &QuadrupedConfig::safe_kd)
      .def_readwrite("max_measurement_age", &QuadrupedConfig::max_measurement_age)
      .def_readwrite("mass", &QuadrupedConfig::mass)
      .def_readwrite("inertia_diag", &QuadrupedConfig::inertia_diag)
      .def("validate", [](const QuadrupedConfig& c) {
        std::string why;
        raise_if_failed(validate(c, &why), why);
      }, "raises ValueError with the reason when a setting is out of range");

  py::class_<QuadrupedInput> in(m, "QuadrupedInput");
  in.def(py::init<>())
      .def_readwrite("t", &QuadrupedInput::t)
      .def_readwrite("stamp", &QuadrupedInput::stamp)
      .def_readwrite("gait", &QuadrupedInput::gait, "Gait.STAND or Gait.TROT")
      .def_readwrite("use_ground_truth", &QuadrupedInput::use_ground_truth);
  vector_field(in, "q", &QuadrupedInput::q, "(12) [rad] encoders, controller joint order");
  vector_field(in, "qd", &QuadrupedInput::qd, "(12) [rad/s]");
  vector_field(in, "gyro", &QuadrupedInput::gyro, "(3) [rad/s] body");
  vector_field(in, "accel", &QuadrupedInput::accel, "(3) [m/s^2] specific force, body");
  vector_field(in, "quat", &QuadrupedInput::quat, "(4) IMU orientation w, x, y, z");
  vector_field(in, "velocity_command", &QuadrupedInput::velocity_command, "(3) vx, vy [m/s], yaw rate [rad/s]");
  vector_field(in, "foothold_offset", &QuadrupedInput::foothold_offset,
               "(12) [m] per foot (FL, FR, RL, RR x xyz), trunk frame, added to the swing footholds");
  vector_field(in, "true_position", &QuadrupedInput::true_position, "(3) [m] world (debug)");
  vector_field(in, "true_velocity", &QuadrupedInput::true_velocity, "(3) [m/s] world (debug)");
  vector_field(in, "true_quat", &QuadrupedInput::true_quat, "(4) w, x, y, z (debug)");

  py::class_<QuadrupedOutput> out(m, "QuadrupedOutput");
  out.def(py::init<>())
      .def_readwrite("status", &QuadrupedOutput::status)
      .def_readonly("tilt", &QuadrupedOutput::tilt)
      .def_readonly("safe_stop", &QuadrupedOutput::safe_stop)
      .def_readonly("qp_iterations", &QuadrupedOutput::qp_iterations);
  vector_field(out, "tau", &QuadrupedOutput::tau, "(12) [N m]");
  vector_field(out, "foot_force", &QuadrupedOutput::foot_force, "(12) [N] world, per foot");
  vector_field(out, "contact", &QuadrupedOutput::contact, "(4) 1 = contact detected");
  vector_field(out, "scheduled", &QuadrupedOutput::scheduled, "(4) 1 = stance scheduled");
  vector_field(out, "foot_clearance", &QuadrupedOutput::foot_clearance, "(4) [m] feet above the estimated ground");
  vector_field(out, "position", &QuadrupedOutput::position, "(3) [m] estimated, world");
  vector_field(out, "velocity", &QuadrupedOutput::velocity, "(3) [m/s] estimated, world");
  vector_field(out, "quat", &QuadrupedOutput::quat, "(4) estimated w, x, y, z");
  vector_field(out, "ground_normal", &QuadrupedOutput::ground_normal, "(3)");
  vector_field(out, "wrench", &QuadrupedOutput::wrench, "(6) desired [F; tau], world");

  py::class_<QuadrupedController>(m, "QuadrupedController", "1 kHz stand/trot controller, 12 joints")
      .def(py::init([](std::shared_ptr<RobotModel> model, const std::optional<QuadrupedConfig>& config) {
             QuadrupedController c;
             std::string why;
             raise_if_failed(QuadrupedController::configure(config.value_or(QuadrupedConfig{}), model, &c, &why),
                             why);
             return c;
           }),
           py::arg("model"), py::arg("config") = py::none())
      .def("step", &QuadrupedController::step, py::arg("input"), py::arg("output"))
      .def_property_readonly("joint_names", &QuadrupedController::joint_names)
      .def_property_readonly("effort_limit", &QuadrupedController::effort_limit)
      .def_property_readonly("mass", &QuadrupedController::mass)
      .def_property_readonly("config", &QuadrupedController::config,
                             "the configuration with everything derived filled in")
      .def_property_readonly("stand_pose", &QuadrupedController::stand_pose, "(12) [rad] derived")
      .def_property_readonly("crouch_pose", &QuadrupedController::crouch_pose, "(12) [rad] safe stop")
      .def_property_readonly("com", &QuadrupedController::com, "(3) [m] CoM standing, trunk frame")
      .def_property_readonly("inertia", &QuadrupedController::inertia,
                             "(3, 3) [kg m^2] composite inertia about the CoM, trunk axes")
      .def_property_readonly("inertia_free", &QuadrupedController::inertia_free,
                             "(3, 3) [kg m^2] about the CoM with the leg joints free")
      .def("reset", &QuadrupedController::reset,
           "leave a latched safe stop and forget the measurement order")
      .def_property_readonly("counters", &QuadrupedController::counters)
      .def_property_readonly("estimated_gyro_bias",
                             [](const QuadrupedController& c) { return Eigen::Vector3d(c.estimator().gyro_bias()); },
                             "(3) [rad/s] the estimator's gyro-bias estimate, trunk frame (diagnostics)")
      .def("foot_position",
           [](const QuadrupedController& c, int leg, const Eigen::Vector3d& q) {
             if (leg < 0 || leg >= QuadrupedController::kLegs) throw py::index_error("leg: 0..3");
             return Eigen::Vector3d(c.leg(leg).foot_position(q));
           },
           py::arg("leg"), py::arg("q"), "(3) [m] foot centre in the trunk frame for the leg's 3 joints");
}

}  // namespace kiloloop::py_glue
