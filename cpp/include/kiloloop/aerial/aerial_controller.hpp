#pragma once
// AerialController: the 1 kHz controller of a multirotor (n >= 4 rotors, any layout) carrying a
// serial arm of 0..n joints, or none. step() is a short list of named stages over a per-tick
// scratch (AerialTick) kept in the workspace:
//   check_measurements -> load_references -> arm_reference (joints, or end-effector position by
//   damped IK) -> position_loop -> thrust_and_attitude -> arm_dynamics (arm computed torque with
//   the body's motion and the reaction wrench, FloatingBaseRne, one pass; feed-forward) ->
//   allocate -> arm_output -> guard_output (a last finite-output check).
// The model: the arm's chain from the body link to the end effector
// (RobotModel.from_urdf(path, root=base, tip=ee)), or, for a vehicle without an arm, the whole
// tree (no chain; every link rigid). The body is the root link plus every link rigidly
// attached to it off the arm; its centre of mass may be anywhere: the attitude dynamics, the rotor
// geometry and the reaction torque are all taken about it (RotorAllocationConfig::positions are
// in the base link frame; the controller shifts them). The position loop acts on the base link
// origin (what the references and the state describe).
//
// Reaction feed-forward (switchable): coupled inverse dynamics. The attitude law runs on the body
// alone and yields the body's angular acceleration; one RNE pass of the arm on the body moving
// as measured (rates, accelerometer) and as commanded (that angular acceleration) gives the arm's
// computed torque and the wrench the body must apply to the arm; the rotors add its torque and
// its vertical force (the lateral force would need a tilt: it is left to the position loop).
// Off, the vehicle is treated as one rigid body of the total mass with the arm frozen at its
// nominal pose (the usual multirotor controller) and the arm's motion is a disturbance left to
// feedback; the arm's computed torque still includes the body's motion.
// Separately (hold_com, with or without the feed-forward), the position loop can hold the
// vehicle's centre of mass rather than the body origin, so the body gives way to the arm's
// internal motion instead of tilting against it.
#include <string>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "kiloloop/aerial/attitude_controller.hpp"
#include "kiloloop/aerial/floating_base_rne.hpp"
#include "kiloloop/aerial/position_controller.hpp"
#include "kiloloop/aerial/rotor_allocation.hpp"
#include "kiloloop/control/rules.hpp"
#include "kiloloop/dynamics/dynamics.hpp"
#include "kiloloop/model/robot_model.hpp"
#include "kiloloop/status.hpp"

namespace kiloloop {

// Flight mode: position (the position loop sets the attitude) or attitude (quat_ref sets it; the
// collective thrust still holds the altitude).
enum class FlightMode : int { kPosition = 0, kAttitude = 1 };
// Arm reference: joints (q_ref, qd_ref, qdd_ref) or the end-effector position (world).
enum class ArmMode : int { kJoints = 0, kEndEffector = 1 };

struct AerialConfig {
  double dt = 0.001;                                        // [s] control period
  Eigen::Vector3d gravity = Eigen::Vector3d(0.0, 0.0, -9.81);  // [m/s^2] world
  PositionControlConfig position;  // outer loop: position error -> thrust and attitude target
  AttitudeControlConfig attitude;  // inner loop: attitude error -> body torque
  RotorAllocationConfig rotors;    // rotor geometry and limits: body wrench -> rotor thrusts
  // Arm computed torque: e'' + kd e' + kp e = 0 per joint (1 value or nq).
  Eigen::VectorXd arm_kp = Eigen::VectorXd::Constant(1, 400.0);  // [1/s^2]
  Eigen::VectorXd arm_kd = Eigen::VectorXd::Constant(1, 40.0);   // [1/s]
  Eigen::VectorXd arm_q_nominal = Eigen::VectorXd();  // (nq) [rad] for the rigid model; empty = 0
  // Identified joint friction, compensated on top of the computed torque (1 value or nq; 0 = off):
  // viscous b qd and Coulomb f_c tanh(v_c / arm_friction_velocity), with v_c = qd_ref +
  // (kp / kd) (q_ref - q) the velocity the servo asks for (so a joint at rest with an error still
  // gets past its breakaway torque). A light arm's computed torques are of the order of its
  // friction: without this, the yaw joint (1e-5 kg m^2 about its axis) sticks.
  Eigen::VectorXd arm_viscous = Eigen::VectorXd::Zero(1);   // [N m s/rad]
  Eigen::VectorXd arm_coulomb = Eigen::VectorXd::Zero(1);   // [N m]
  double arm_friction_velocity = 0.05;                       // [rad/s] smoothing of the sign
  // [rad] position errors below this do not count in v_c: the encoder's quantization (0.1 deg)
  // would otherwise dither the compensation at rest and shake the body through the joint
  // (measured: aerial-arm-sweep's feed-forward reduction fell from 64 % to 55 %).
  double arm_friction_deadband = 0.005;
  double ik_damping = 0.01;  // [m] damped least squares lambda of the end-effector IK
  int ik_iterations = 3;     // per tick (warm-started from the last tick's solution)
  bool reaction_feedforward = true;  // cancel the arm's reaction wrench on the body (feed-forward)
  // The position loop holds the vehicle's centre of mass where the reference puts it with the arm
  // at arm_q_nominal, so the body gives way to the arm's internal motion (momentum conservation)
  // instead of tilting against its lateral push. Independent of reaction_feedforward. The shift
  // comes from the arm's reference (q_ref, smooth; no encoder noise), its rate by differencing.
  bool hold_com = true;
  // [s] lead on the fed-forward reaction torque, tau_ff + lead d(tau_ff)/dt: the rotors deliver
  // it through their lag while the arm's reaction is immediate; set it to the rotor time constant
  // to cancel the lag to first order, 0 for none. The rate is low-passed (reaction_lead_filter).
  double reaction_lead = 0.0;
  double reaction_lead_filter = 0.01;  // [s] time constant of the rate's low-pass
  // The body's linear acceleration in the arm's dynamics: true, the accelerometer (what the body
  // actually does); false, the position loop's command (which the body reaches only after the
  // attitude has turned: in attitude mode or at the tilt limit it never does).
  bool measured_acceleration = true;
  // Safety.
  double max_tilt = 60.0 * 3.14159265358979323846 / 180.0;  // [rad] beyond: motors off, latched
  double max_measurement_age = 0.02;  // [s] older state -> failsafe
  // Failsafe on bad or stale measurements: every rotor at this fraction of the hover thrust
  // (a level-ish slow descent, the vehicle being blind) and zero arm torque.
  double failsafe_thrust_fraction = 0.9;
};

Status validate(const AerialConfig& config, int nq, std::string* why);

struct AerialInput {
  double t = 0.0;       // [s] controller time
  double stamp = 0.0;   // [s] when the state below was measured
  // State (an estimator's or a motion-capture system's), SI, world frame z up.
  Eigen::Vector3d position = Eigen::Vector3d::Zero();   // [m] body origin, world
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();   // [m/s] world
  Eigen::Vector4d quat = Eigen::Vector4d(1, 0, 0, 0);   // w, x, y, z, world <- body
  Eigen::Vector3d gyro = Eigen::Vector3d::Zero();       // [rad/s] body
  // [m/s^2] accelerometer at the body origin: specific force (a - g), body frame (+g up at rest).
  Eigen::Vector3d accel = Eigen::Vector3d(0.0, 0.0, 9.81);
  Eigen::VectorXd q;    // (nq) [rad] arm encoders, chain order
  Eigen::VectorXd qd;   // (nq) [rad/s]
  // Body references.
  Eigen::Vector3d position_ref = Eigen::Vector3d::Zero();      // [m] world
  Eigen::Vector3d velocity_ref = Eigen::Vector3d::Zero();      // [m/s]
  Eigen::Vector3d acceleration_ref = Eigen::Vector3d::Zero();  // [m/s^2]
  double yaw_ref = 0.0;                                        // [rad]
  // FlightMode::kAttitude: quat_ref replaces the attitude the position loop asks for.
  FlightMode flight_mode = FlightMode::kPosition;
  Eigen::Vector4d quat_ref = Eigen::Vector4d(1, 0, 0, 0);  // w, x, y, z, world <- body
  ArmMode arm_mode = ArmMode::kJoints;
  Eigen::VectorXd q_ref;    // (nq) [rad]
  Eigen::VectorXd qd_ref;   // (nq) [rad/s]
  Eigen::VectorXd qdd_ref;  // (nq) [rad/s^2]
  Eigen::Vector3d ee_position_ref = Eigen::Vector3d::Zero();  // [m] world
  Eigen::Vector3d ee_velocity_ref = Eigen::Vector3d::Zero();  // [m/s] world
};

struct AerialOutput {
  Eigen::VectorXd thrust;                            // (n rotors) [N] commands, within limits
  Eigen::VectorXd tau;                               // (nq) [N m] arm torques, within effort
  Status status = Status::kNotConfigured;
  Eigen::Vector4d wrench = Eigen::Vector4d::Zero();           // [N; N m] commanded T, tau (body)
  Eigen::Vector4d wrench_achieved = Eigen::Vector4d::Zero();  // what the thrusts produce
  Vector6d reaction = Vector6d::Zero();  // [N; N m] wrench body -> arm, body frame (fed forward)
  Eigen::Vector3d acceleration_des = Eigen::Vector3d::Zero();  // [m/s^2] world
  Eigen::Vector4d quat_des = Eigen::Vector4d(1, 0, 0, 0);      // w, x, y, z
  Eigen::Vector3d attitude_error = Eigen::Vector3d::Zero();    // [rad] e_R of the law
  Eigen::VectorXd q_ref;                                       // (nq) [rad] arm target used
  Eigen::Vector3d ee_position = Eigen::Vector3d::Zero();       // [m] world, from the state
  double tilt = 0.0;                                           // [rad] from vertical
  bool rotors_saturated = false;
  bool safe_stop = false;
};

// What one stage hands the next within a tick (workspace scratch, fixed size: no allocation).
struct AerialTick {
  Status status = Status::kOk;       // worst degradation so far this tick
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();                 // world <- body
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();          // world <- body
  Eigen::Vector3d a_des = Eigen::Vector3d::Zero();                 // [m/s^2] world
  Eigen::Quaterniond q_des = Eigen::Quaterniond::Identity();      // attitude target
  double collective = 0.0;                                         // [N] along body z
  Eigen::Vector3d tau_body = Eigen::Vector3d::Zero();  // [N m] about the body CoM, body frame
  Eigen::Vector3d alpha = Eigen::Vector3d::Zero();     // [rad/s^2] asked of the body
  Vector6d W = Vector6d::Zero();  // [N; N m] body -> arm, body frame, about the body origin
  Eigen::Vector4d wrench = Eigen::Vector4d::Zero();    // [N; N m] to the allocation
};

class AerialController {
 public:
  static Status configure(const AerialConfig& config, RobotModelPtr model, AerialController* out,
                          std::string* why);
  Status step(const AerialInput& in, AerialOutput& out) noexcept;

  AerialInput make_input() const;    // sized for this model, hovering at the origin
  AerialOutput make_output() const;
  int nq() const { return nq_; }
  int n_rotors() const { return allocation_.n(); }
  bool has_arm() const { return has_arm_; }
  const RotorAllocation& allocation() const { return allocation_; }
  // [m] body frame: the body's own centre of mass, and the vehicle's with the arm at nominal.
  const Eigen::Vector3d& body_com() const { return c_body_; }
  const Eigen::Vector3d& vehicle_com() const { return c_vehicle_; }
  double body_mass() const { return m_body_; }       // [kg]
  double total_mass() const { return m_total_; }     // [kg] body + arm
  const Eigen::Matrix3d& body_inertia() const { return J_body_; }  // [kg m^2] about body_com
  const Eigen::Matrix3d& rigid_inertia() const { return J_rigid_; }  // with the arm at nominal
  double hover_thrust() const { return m_total_ * gravity_norm_; }   // [N] total
  const AerialConfig& config() const { return cfg_; }
  // Clears integrators, references, the measurement order and a latched safe stop (counters kept).
  void reset() noexcept;
  // The statuses step returned since configure (one StatusCounters for every controller).
  const StatusCounters& counters() const { return counters_; }

 private:
  // The stages of step(), in order; each reads and writes tick_ and the workspace.
  // Sizes, latched stop, tilt, finite and fresh state; a failure is returned with the failsafe
  // already written.
  Status check_measurements(const AerialInput& in, AerialOutput& out) noexcept;
  // Takes valid references (kBadSize / kNonFiniteReference keep the previous ones, or hold the
  // current state when there are none yet).
  void load_references(const AerialInput& in) noexcept;
  void arm_reference(const AerialInput& in, AerialOutput& out) noexcept;
  void position_loop(const AerialInput& in, AerialOutput& out) noexcept;
  void thrust_and_attitude(const AerialInput& in, AerialOutput& out) noexcept;
  Status arm_dynamics(const AerialInput& in, AerialOutput& out) noexcept;
  void allocate(AerialOutput& out) noexcept;
  Status arm_output(const AerialInput& in, AerialOutput& out) noexcept;  // clip_effort's status
  Status guard_output(AerialOutput& out, Status torques) noexcept;

  Status accept_references(const AerialInput& in) noexcept;
  const Eigen::Vector3d& arm_moment_at_reference() noexcept;
  Status arm_target(const Eigen::Matrix3d& R, const AerialInput& in) noexcept;
  void failsafe(AerialOutput& out, bool motors_off) noexcept;

  AerialConfig cfg_;
  RobotModelPtr model_;
  int nq_ = 0;
  bool has_arm_ = false;  // a chain from the body (nq may still be 0: a rigid payload)
  AerialTick tick_;
  Dynamics kin_;  // FK and Jacobian of the arm in the body frame
  FloatingBaseRne rne_;
  PositionController position_;
  AttitudeController attitude_body_, attitude_rigid_;  // J_body (feed-forward on) / J_rigid (off)
  RotorAllocation allocation_;
  double m_body_ = 0.0, m_total_ = 0.0, gravity_norm_ = 9.81;
  Eigen::Matrix3d J_body_ = Eigen::Matrix3d::Identity(), J_rigid_ = Eigen::Matrix3d::Identity();
  Eigen::Vector3d c_body_ = Eigen::Vector3d::Zero();     // [m] body CoM, base link frame
  Eigen::Vector3d c_vehicle_ = Eigen::Vector3d::Zero();  // [m] vehicle CoM at nominal
  Eigen::VectorXd failsafe_thrust_;                      // (n) [N] per rotor
  Eigen::VectorXd kp_, kd_, viscous_, coulomb_, lower_, upper_, effort_;
  // Scratch and state, sized at configure.
  Eigen::VectorXd q_ref_, qd_ref_, qdd_ref_, q_ik_, qdd_cmd_, tau_;
  Eigen::MatrixXd J_;
  Eigen::Matrix4d T_;
  Eigen::Vector3d tip_;  // [m] end effector at the measured q, body frame (arm_dynamics' pass)
  Eigen::Vector3d p_ref_, v_ref_, a_ref_, ee_ref_, ee_vel_ref_;
  Eigen::Quaterniond quat_ref_ = Eigen::Quaterniond::Identity();
  double yaw_ref_ = 0.0;
  FlightMode flight_mode_ = FlightMode::kPosition;
  ArmMode arm_mode_ = ArmMode::kJoints;
  bool have_ref_ = false, have_ik_ = false;
  bool saturated_prev_ = false;
  double reaction_z_ = 0.0;  // [N] last tick's vertical reaction force (world)
  Eigen::Vector3d com_nominal_ = Eigen::Vector3d::Zero();  // [m] arm's CoM shift at nominal
  Eigen::Vector3d com_shift_prev_ = Eigen::Vector3d::Zero();  // [m] body frame, last tick
  bool have_com_ = false;
  Eigen::VectorXd moment_q_;                         // the q_ref moment_ was computed at
  Eigen::Vector3d moment_ = Eigen::Vector3d::Zero();  // [kg m] arm first moment there, body frame
  bool have_moment_ = false;
  Eigen::Vector3d reaction_tau_prev_ = Eigen::Vector3d::Zero();  // [N m] for the lead's rate
  Eigen::Vector3d reaction_tau_rate_ = Eigen::Vector3d::Zero();  // [N m/s] low-passed
  bool have_reaction_ = false;
  MeasurementGate gate_;  // max_measurement_age and the order of the stamps
  StatusCounters counters_;
  bool safe_stop_ = false;
  bool configured_ = false;
};

}  // namespace kiloloop
