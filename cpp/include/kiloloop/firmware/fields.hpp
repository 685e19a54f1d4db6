#pragma once
// Every field of the three families' configs, inputs and outputs, listed ONCE, in declaration
// order: `visit_fields(x, v)` calls `v(name, member)` for each. Three users share the lists:
//   - `kiloloop export` writes each config field as a constexpr member (firmware/settings.hpp),
//   - the back-to-back log writes each input/output field as raw bytes (firmware/record.hpp),
//   - the firmware replay reads them back and compares outputs field by field, naming the first
//     that differs.
// A field added to a struct and not here is neither exported nor compared: the b2b test of its
// family then fails on the first tick where that field matters (a config field) or stays silent
// (an output field): keep the lists complete.
//
// Names are dotted C++ member paths ("gait.period", "feet[0]"), string literals: visiting
// allocates nothing (the replay visits every tick).
#include "kiloloop/aerial/aerial_controller.hpp"
#include "kiloloop/control/computed_torque.hpp"
#include "kiloloop/control/joint_io.hpp"
#include "kiloloop/quadruped/quadruped_controller.hpp"

namespace kiloloop {

// --- arm: the computed-torque controller of the arm scenarios ---------------------------------
template <class V>
void visit_fields(ComputedTorqueConfig& c, V&& v) {
  v("kp", c.kp);
  v("kd", c.kd);
  v("gravity", c.gravity);
  v("max_measurement_age", c.max_measurement_age);
  v("friction.viscous", c.friction.viscous);
  v("friction.coulomb", c.friction.coulomb);
  v("friction.smoothing_speed", c.friction.smoothing_speed);
}

template <class V>
void visit_fields(JointControlInput& in, V&& v) {
  v("t", in.t);
  v("stamp", in.stamp);
  v("q", in.q);
  v("qd", in.qd);
  v("q_ref", in.q_ref);
  v("qd_ref", in.qd_ref);
  v("qdd_ref", in.qdd_ref);
}

template <class V>
void visit_fields(JointControlOutput& out, V&& v) {
  v("tau", out.tau);
  v("status", out.status);
}

// --- quadruped --------------------------------------------------------------------------------
template <class V>
void visit_fields(QuadrupedConfig& c, V&& v) {
  v("trunk_link", c.trunk_link);
  v("feet[0]", c.feet[0]);
  v("feet[1]", c.feet[1]);
  v("feet[2]", c.feet[2]);
  v("feet[3]", c.feet[3]);
  v("knees[0]", c.knees[0]);
  v("knees[1]", c.knees[1]);
  v("knees[2]", c.knees[2]);
  v("knees[3]", c.knees[3]);
  v("dt", c.dt);
  v("foot_radius", c.foot_radius);
  v("foot_offset", c.foot_offset);
  v("body_height", c.body_height);
  v("stand_extension", c.stand_extension);
  v("crouch_extension", c.crouch_extension);
  v("gait.period", c.gait.period);
  v("gait.duty", c.gait.duty);
  v("contact.force_on", c.contact.force_on);
  v("contact.force_off", c.contact.force_off);
  v("contact.early_touchdown", c.contact.early_touchdown);
  v("contact.touchdown_clearance", c.contact.touchdown_clearance);
  v("estimator.dt", c.estimator.dt);
  v("estimator.external_attitude", c.estimator.external_attitude);
  v("estimator.attitude_gain", c.estimator.attitude_gain);
  v("estimator.attitude.gyro_noise_density", c.estimator.attitude.gyro_noise_density);
  v("estimator.attitude.accel_noise_density", c.estimator.attitude.accel_noise_density);
  v("estimator.attitude.crossover", c.estimator.attitude.crossover);
  v("estimator.attitude.accel_tolerance", c.estimator.attitude.accel_tolerance);
  v("estimator.attitude.max_gyro_bias", c.estimator.attitude.max_gyro_bias);
  v("estimator.attitude.gyro_bias_random_walk", c.estimator.attitude.gyro_bias_random_walk);
  v("estimator.attitude.gyro_turn_on_bias", c.estimator.attitude.gyro_turn_on_bias);
  v("estimator.velocity_aiding", c.estimator.velocity_aiding);
  v("estimator.accel_noise", c.estimator.accel_noise);
  v("estimator.leg_velocity_noise", c.estimator.leg_velocity_noise);
  v("estimator.foothold_noise", c.estimator.foothold_noise);
  v("estimator.velocity_gate", c.estimator.velocity_gate);
  v("estimator.ground_filter", c.estimator.ground_filter);
  v("force.wrench_weight", c.force.wrench_weight);
  v("force.regularization", c.force.regularization);
  v("force.smoothing", c.force.smoothing);
  v("force.mu", c.force.mu);
  v("force.fz_min", c.force.fz_min);
  v("force.fz_max", c.force.fz_max);
  v("force.max_iterations", c.force.max_iterations);
  v("contact_force_on", c.contact_force_on);
  v("contact_force_off", c.contact_force_off);
  v("fz_min", c.fz_min);
  v("fz_max", c.fz_max);
  v("kp_position", c.kp_position);
  v("kd_velocity", c.kd_velocity);
  v("kp_orientation", c.kp_orientation);
  v("kd_angular", c.kd_angular);
  v("trunk_delay_margin", c.trunk_delay_margin);
  v("swing_height", c.swing_height);
  v("raibert_gain", c.raibert_gain);
  v("touchdown_depth", c.touchdown_depth);
  v("swing_reaction_feedforward", c.swing_reaction_feedforward);
  v("foothold_shift", c.foothold_shift);
  v("swing_frequency", c.swing_frequency);
  v("swing_damping", c.swing_damping);
  v("swing_damping_predicted", c.swing_damping_predicted);
  v("swing_delay_margin", c.swing_delay_margin);
  v("swing_feedforward", c.swing_feedforward);
  v("predict_swing", c.predict_swing);
  v("swing_inertia_at_pose", c.swing_inertia_at_pose);
  v("swing_predict_from", c.swing_predict_from);
  v("swing_prediction_residual", c.swing_prediction_residual);
  v("swing_kp", c.swing_kp);
  v("swing_kd", c.swing_kd);
  v("max_acceleration", c.max_acceleration);
  v("max_position_lag", c.max_position_lag);
  v("actuation_delay", c.actuation_delay);
  v("predict_in_flight", c.predict_in_flight);
  v("predict_legs_free", c.predict_legs_free);
  v("predict_leg_dynamics", c.predict_leg_dynamics);
  v("trust_ramp", c.trust_ramp);
  v("load_ramp", c.load_ramp);
  v("max_tilt", c.max_tilt);
  v("safe_stiffness", c.safe_stiffness);
  v("safe_time_constant", c.safe_time_constant);
  v("safe_kp", c.safe_kp);
  v("safe_kd", c.safe_kd);
  v("max_measurement_age", c.max_measurement_age);
  v("mass", c.mass);
  v("inertia_diag", c.inertia_diag);
}

template <class V>
void visit_fields(QuadrupedInput& in, V&& v) {
  v("t", in.t);
  v("stamp", in.stamp);
  v("q", in.q);
  v("qd", in.qd);
  v("gyro", in.gyro);
  v("accel", in.accel);
  v("quat", in.quat);
  v("gait", in.gait);
  v("velocity_command", in.velocity_command);
  v("use_ground_truth", in.use_ground_truth);
  v("true_position", in.true_position);
  v("true_velocity", in.true_velocity);
  v("true_quat", in.true_quat);
}

template <class V>
void visit_fields(QuadrupedOutput& out, V&& v) {
  v("tau", out.tau);
  v("status", out.status);
  v("foot_force", out.foot_force);
  v("contact", out.contact);
  v("scheduled", out.scheduled);
  v("foot_clearance", out.foot_clearance);
  v("position", out.position);
  v("velocity", out.velocity);
  v("quat", out.quat);
  v("ground_normal", out.ground_normal);
  v("wrench", out.wrench);
  v("tilt", out.tilt);
  v("safe_stop", out.safe_stop);
  v("qp_iterations", out.qp_iterations);
}

// --- aerial -----------------------------------------------------------------------------------
template <class V>
void visit_fields(AerialConfig& c, V&& v) {
  v("dt", c.dt);
  v("gravity", c.gravity);
  v("position.kp", c.position.kp);
  v("position.kd", c.position.kd);
  v("position.ki", c.position.ki);
  v("position.integral_limit", c.position.integral_limit);
  v("position.max_tilt", c.position.max_tilt);
  v("position.dt", c.position.dt);
  v("attitude.law", c.attitude.law);
  v("attitude.gains.kp", c.attitude.gains.kp);
  v("attitude.gains.kd", c.attitude.gains.kd);
  v("attitude.gains.ki", c.attitude.gains.ki);
  v("attitude.integral_limit", c.attitude.integral_limit);
  v("attitude.hysteresis", c.attitude.hysteresis);
  v("attitude.dt", c.attitude.dt);
  v("rotors.positions", c.rotors.positions);
  v("rotors.axes", c.rotors.axes);
  v("rotors.spin", c.rotors.spin);
  v("rotors.torque_coefficient", c.rotors.torque_coefficient);
  v("rotors.thrust_min", c.rotors.thrust_min);
  v("rotors.thrust_max", c.rotors.thrust_max);
  v("rotors.lag_compensation", c.rotors.lag_compensation);
  v("rotors.time_constant", c.rotors.time_constant);
  v("rotors.dt", c.rotors.dt);
  v("arm_kp", c.arm_kp);
  v("arm_kd", c.arm_kd);
  v("arm_q_nominal", c.arm_q_nominal);
  v("arm_viscous", c.arm_viscous);
  v("arm_coulomb", c.arm_coulomb);
  v("arm_friction_velocity", c.arm_friction_velocity);
  v("arm_friction_deadband", c.arm_friction_deadband);
  v("ik_damping", c.ik_damping);
  v("ik_iterations", c.ik_iterations);
  v("reaction_feedforward", c.reaction_feedforward);
  v("hold_com", c.hold_com);
  v("reaction_lead", c.reaction_lead);
  v("reaction_lead_filter", c.reaction_lead_filter);
  v("measured_acceleration", c.measured_acceleration);
  v("max_tilt", c.max_tilt);
  v("max_measurement_age", c.max_measurement_age);
  v("failsafe_thrust_fraction", c.failsafe_thrust_fraction);
}

template <class V>
void visit_fields(AerialInput& in, V&& v) {
  v("t", in.t);
  v("stamp", in.stamp);
  v("position", in.position);
  v("velocity", in.velocity);
  v("quat", in.quat);
  v("gyro", in.gyro);
  v("accel", in.accel);
  v("q", in.q);
  v("qd", in.qd);
  v("position_ref", in.position_ref);
  v("velocity_ref", in.velocity_ref);
  v("acceleration_ref", in.acceleration_ref);
  v("yaw_ref", in.yaw_ref);
  v("flight_mode", in.flight_mode);
  v("quat_ref", in.quat_ref);
  v("arm_mode", in.arm_mode);
  v("q_ref", in.q_ref);
  v("qd_ref", in.qd_ref);
  v("qdd_ref", in.qdd_ref);
  v("ee_position_ref", in.ee_position_ref);
  v("ee_velocity_ref", in.ee_velocity_ref);
}

template <class V>
void visit_fields(AerialOutput& out, V&& v) {
  v("thrust", out.thrust);
  v("tau", out.tau);
  v("status", out.status);
  v("wrench", out.wrench);
  v("wrench_achieved", out.wrench_achieved);
  v("reaction", out.reaction);
  v("acceleration_des", out.acceleration_des);
  v("quat_des", out.quat_des);
  v("attitude_error", out.attitude_error);
  v("q_ref", out.q_ref);
  v("ee_position", out.ee_position);
  v("tilt", out.tilt);
  v("rotors_saturated", out.rotors_saturated);
  v("safe_stop", out.safe_stop);
}

}  // namespace kiloloop
