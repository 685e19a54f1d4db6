#pragma once
// QuadrupedController: the 1 kHz trot/stand controller of a 12-DoF quadruped.
//   estimator -> safety -> gait schedule -> contact detection -> trunk wrench -> force QP ->
//   stance torques tau = -J^T f, swing legs: Raibert foothold, 7th-order swing, leg IK, joint PD.
// Joints are ordered leg-major FL, FR, RL, RR x (abduction, hip pitch, knee); joint_names() gives
// the model's names in that order so glue code can map by name.
#include <array>
#include <string>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "kiloloop/control/rules.hpp"
#include "kiloloop/kinematics/leg_gravity.hpp"
#include "kiloloop/kinematics/leg_kinematics.hpp"
#include "kiloloop/model/robot_model.hpp"
#include "kiloloop/quadruped/contact_detector.hpp"
#include "kiloloop/quadruped/free_leg_inertia.hpp"
#include "kiloloop/quadruped/gait_scheduler.hpp"
#include "kiloloop/quadruped/in_flight.hpp"
#include "kiloloop/quadruped/leg_joint_inertia.hpp"
#include "kiloloop/quadruped/stance_force.hpp"
#include "kiloloop/quadruped/trunk_rotation.hpp"
#include "kiloloop/quadruped/state_estimator.hpp"
#include "kiloloop/status.hpp"

namespace kiloloop {

using Vector12d = Eigen::Matrix<double, 12, 1>;
using Vector6d = Eigen::Matrix<double, 6, 1>;

// The stance-force QP's settings as the controller starts from them: the moment entries of
// wrench_weight 0, i.e. derived at configure (QuadrupedConfig::force).
inline StanceForceConfig derived_stance_force() {
  StanceForceConfig f;
  f.wrench_weight.tail<3>().setZero();
  return f;
}

// Every default is generic or derived at configure from the model (masses, inertias, leg
// geometry, effort limits) and the declared actuation delay; a field documented "0: derived" is
// an override. QuadrupedController::config() returns the configuration with all of it resolved.
// Robot-specific tuning lives in the robot file (models/<robot>/robot.toml, [controller]).
struct QuadrupedConfig {
  std::string trunk_link = "trunk";  // the URDF link of the trunk (floating base)
  // The URDF links of the four feet (FL, FR, RL, RR): each leg is the chain trunk -> foot.
  std::array<std::string, 4> feet{"FL_foot", "FR_foot", "RL_foot", "RR_foot"};
  // Knee bend per leg (FL, FR, RL, RR); kAuto: the bend the knee's joint limits allow, and where
  // they allow both, the one whose standing knee angle lies nearer the URDF's zero pose
  // (QuadrupedController::knee_nearer_zero: ANYmal's hind knees forward, its front ones backward).
  std::array<KneeDirection, 4> knees{KneeDirection::kAuto, KneeDirection::kAuto,
                                     KneeDirection::kAuto, KneeDirection::kAuto};
  double dt = 0.001;                  // [s] control period
  double foot_radius = 0.0;           // [m] foot sphere radius (contact point below its centre)
  // [m] the foot sphere's centre in the foot link's frame: the point the leg kinematics, the
  // estimator and the footholds track. Zero: the link origin (Unitree, our model). ANYmal's
  // sphere sits 0.023 m up the shank: taken as the origin, the feet of the more bent legs stood
  // that much higher on their spheres and the robot dropped. Finite, shorter than the shank.
  Eigen::Vector3d foot_offset = Eigen::Vector3d::Zero();
  // [m] trunk origin above the ground, along world z. 0: derived so that each foot stands
  // stand_extension of the leg's length straight below its hip pitch axis.
  double body_height = 0.0;
  // [-] hip -> foot distance standing / (l_thigh + l_shank). Where a leg's joint limits forbid
  // it (its foot there, or the swing apex above it, out of reach with any knee bend it may
  // take), the derived body_height moves to the nearest extension in [0.40, 0.90] where every
  // leg reaches both, and config() reports that one; none: configure fails naming the leg and
  // its limits.
  double stand_extension = 0.58;
  double crouch_extension = 0.30;     // [-] the same in the safe-stop crouch (raised if the limits forbid it)
  // Gait period 0: derived by Froude scaling, 2.4 sqrt(leg length / g) (Go1: 0.50 s, a 0.28 m
  // leg: 0.41 s; measured on both, 0.45 s rolled the light one 2.6 deg RMS at 0.3 m/s, 0.41 s 0.9).
  GaitConfig gait{0.0, 0.6};
  ContactConfig contact;              // force_on / force_off: set from contact_force_on/off
  EstimatorConfig estimator;  // the trunk state estimator (IMU + leg kinematics)
  // fz_min / fz_max: set from the weight fractions below. wrench_weight: the forces weigh 1 per
  // N^2; a moment entry 0 is derived as (m h / I_axis)^2 per (N m)^2, h the CoM's height above
  // the ground standing, I the composite inertia: a force error dF and a moment error dM then
  // weigh as the accelerations they cause, dF / m of the CoM against h dM / I of the trunk's
  // rotation at the feet (a lateral ground force is also a moment h F about the CoM: this is
  // the trade the QP makes on two diagonal feet). Roll: our model ~250, Go1 ~710. Measured
  // with the earlier fixed 100 on every axis: Go1's 0.4 N s/kg push at 10 ms swayed the
  // trunk 86 mm sideways in one diagonal stance and rolled it 5.10 deg (limit 5).
  StanceForceConfig force = derived_stance_force();
  // Forces as fractions of the robot's weight m g (newtons at configure).
  double contact_force_on = 0.145;    // [-] estimated normal force that confirms a touch-down
  double contact_force_off = 0.058;   // [-] ... below which an unloading foot lifts off
  double fz_min = 0.029;              // [-] least normal force of a stance foot
  double fz_max = 1.74;               // [-] largest normal force of a stance foot
  // Trunk PD, as accelerations per unit error (multiplied by mass / composite inertia inside):
  // natural frequencies squared and 2 zeta omega. Bounded by the actuation delay (phase lag
  // omega * delay at crossover); the feedback acts on the state predicted over the delay.
  // x, y: along and across the commanded heading (the position target integrates the velocity
  // command), z: height. Across the heading the hold is dropped (y set to 0) where the delay
  // lowers the roll loop (kp_orientation[0], below): a walk-back sideways on two diagonal feet
  // asks for a roll moment that loop then corrects too slowly. Measured (realistic, seeds 0-4):
  // Go1's 0.4 N s/kg push at 35 ms rolled 1.02-1.30 deg after recovery on 3 of 5 seeds (limit 1)
  // with the hold, 0.71-0.82 without; at 10 ms, where nothing is lowered, dropping it made
  // ANYmal C's trot fall on a seed (docs/robots.md).
  Eigen::Vector3d kp_position{20.0, 20.0, 300.0};  // [1/s^2]
  Eigen::Vector3d kd_velocity{8.0, 8.0, 35.0};     // [1/s]
  Eigen::Vector3d kp_orientation{250.0, 250.0, 150.0};  // [1/s^2] roll, pitch, yaw (body axes)
  Eigen::Vector3d kd_angular{20.0, 20.0, 20.0};    // [1/s]
  // [rad] phase the delay may take at a trunk loop's natural frequency: a frequency sqrt(kp)
  // above trunk_delay_margin / (actuation_delay + dt) is lowered to it, the damping ratio kept
  // (measured: Go1 standing with a 35 ms delay oscillates in roll at 10 Hz with 250/20 and
  // stands with 100/12.6; at 10 ms nothing is lowered).
  double trunk_delay_margin = 0.36;
  // Swing legs.
  double swing_height = 0.0;          // [m] apex above lift-off -> touch-down; 0: 0.16 leg lengths
  // [s] foothold shift per m/s of velocity error (capture-point value sqrt(h/g) shortened for
  // the feet landing early; 0.13 measured best on the 17.6 kg model, a fraction 0.75 of sqrt(h/g)).
  double raibert_gain = 0.0;          // 0: 0.75 sqrt(body_height / g)
  double touchdown_depth = 0.0;       // [m] aim this far below the ground; 0: 0.02 leg lengths
  bool swing_reaction_feedforward = true;  // stance forces also cancel the swing motors' reaction
  // [m] trunk-frame shift of all footholds from their nominal place: under the hips, moved along
  // x to the whole-robot CoM so that each diagonal support line passes through it.
  Eigen::Vector2d foothold_shift = Eigen::Vector2d::Zero();
  // Swing joint PD from a natural frequency and damping ratio on each joint's own inertia (the
  // leg's joint-space mass matrix diagonal at the standing pose). The delayed derivative action
  // limits them: a joint's natural frequency (given gains included) above
  // swing_delay_margin / (actuation_delay + dt) is lowered to it, its damping ratio kept. So is
  // the leg's coupled one: the largest sqrt(eig(H^-1 Kp)), H the full 3x3 mass matrix at the
  // standing pose and at the swing's apex (the foot swing_height above its standing place), where
  // a folded leg is lightest. Measured on ANYmal B and C: 66 and 70 rad/s at the apex against
  // 46 standing (a heavy thigh folded onto the abduction axis); at 10 ms the swing legs rang at
  // ~150 rad/s, read as contacts, and the trot fell. Unitree-class legs and ours stay below it.
  double swing_frequency = 30.0;      // [rad/s]
  double swing_damping = 0.7;         // [-]
  // [-] the damping ratio where the joint predictor is on (predict_swing: delays above 12.3 ms at
  // the default swing_frequency): critical. Measured on Go1 at 35 ms (realistic, seed 0), 0.7 -> 1.0: the
  // swing apex above lift-off median 71 -> 66 mm, largest 106 -> 76 (68 planned); the peak force
  // on a landing foot before the acting schedule's stance median 61 -> 48 N (12.5 at 10 ms); the
  // feet still land a median 52 ms before it (28 at 10 ms); the trot fell at 13.3 s and passes
  // (0.80 deg RMS; seeds 1-4 too, up to 1.45). Not used below that delay: at 10 ms 1.0 made Go1's
  // slope-trot fall.
  double swing_damping_predicted = 1.0;
  double swing_delay_margin = 0.55;   // [rad] omega * delay (the 17.6 kg model's knee: 50 rad/s at 10 ms)
  // Swing joints also get I qdd of the swing trajectory (joint inertia diagonal x the joint
  // acceleration the foot's reference acceleration asks for), the reference taken one delay
  // ahead. Off by default: measured at 10 ms it sped the trot up (0.51 -> 0.55 m/s at 0.5) and
  // tipped the light robot over; at 35 ms it did not save the trot either.
  bool swing_feedforward = false;
  // Joint-level Smith predictor for the swing legs: the swing PD acts on each swing joint's q, qd
  // predicted one actuation delay ahead (when its command lands) from the joint accelerations
  // still in flight, M_leg^-1 (tau - gravity) with M_leg the leg's joint-space inertia standing.
  // The delay left in the loop is then only the predictor's error, so the gains are capped with
  // swing_prediction_residual * actuation_delay (+ dt) instead of the whole delay. Used only
  // where the delay takes a phase swing_frequency * (actuation_delay + dt) above
  // swing_predict_from; config() reports whether it is on.
  bool predict_swing = true;
  // [rad] Below it (10 ms at 30 rad/s: 0.33) the swing legs run without the joint predictor; at
  // 0.48 (15 ms) they need it. Measured on Go1: with the switch at swing_delay_margin (0.55) it
  // was off at 15 ms and the trot fell, while 20 and 25 ms passed; with it on at 15 ms the trot
  // passes (0.22 deg roll/pitch RMS).
  double swing_predict_from = 0.4;
  double swing_prediction_residual = 0.3;  // [-] fraction of the delay the predictor leaves
  // The joint predictor's M_leg at the pose each command lands in (first order, q + delay qd;
  // leg_joint_inertia.hpp) instead of the standing pose's: the folded swing leg is lighter about
  // the hip (Go1: 0.023 -> 0.012 kg m^2 at the apex), so the standing H under-predicted the swing
  // joints' motion over the delay. Measured at 35 ms (realistic, seeds 0-4): Go1's trot-synchronous
  // roll 2.84 -> 0.57 deg peak to peak (seed 0), trot roll/pitch RMS 0.78-0.81 -> 0.23-0.55 deg,
  // 0.4 N s/kg push 2.46-2.84 -> 0.81-1.30 deg. Our model needs its derived swing gains with it
  // (models/quadruped/robot.toml). false: the standing pose's M_leg.
  bool swing_inertia_at_pose = true;
  Eigen::Vector3d swing_kp = Eigen::Vector3d::Zero();  // [N m/rad] abd, pitch, knee; 0: derived
  Eigen::Vector3d swing_kd = Eigen::Vector3d::Zero();  // [N m s/rad]; 0: derived
  double max_acceleration = 1.0;      // [m/s^2] ramp on the commanded velocity
  // [m] how far the horizontal position target may lead or trail the trunk: it integrates the
  // velocity command (no steady velocity error), but after a push the robot should not walk back
  // the whole way, only settle.
  double max_position_lag = 0.05;
  // [s] known command-to-motor latency: feedback uses the state predicted this far ahead
  // (0 disables). A command sent at t acts at t + delay: the gait schedule runs for the commands
  // (stance/swing choice, swing reference, load ramps), and contact detection and the estimator
  // compare against the schedule of the commands acting now (the one sent a delay ago).
  double actuation_delay = 0.010;
  // How the state is predicted over the delay. true: with the model (composite mass and inertia)
  // and the trunk accelerations commanded in the last actuation_delay seconds, still in flight
  // (a Smith predictor), and contact forces estimated from the torque acting now, not the one
  // just sent; false: first order (x + delay * xdot) only.
  bool predict_in_flight = true;
  // The trunk rotation the in-flight moments cause, predicted with the inertia those moments meet
  // within the delay: the swing legs' joints free, the stance legs locked (free_leg_inertia.hpp;
  // all free, roll is 3.6x below the composite on Go1, 2.4x on our model). false: the composite
  // inertia. Measured at 25 ms: with the composite, Go1's trot rolled at 9-11 Hz, growing until
  // it fell (a delayed roll loop at its limit: the predictor expected 1/3 of the roll it got).
  bool predict_legs_free = true;
  // The trunk rotation predicted from the joint torques sent, through the floating base's dynamics
  // with the legs' masses (trunk_rotation.hpp: stance feet pinned, their forces the constraint's,
  // swing legs free) instead of the contact moment over a rigid inertia. Measured on Go1: the
  // trunk's roll over a 30 ms delay followed the abduction torques in flight (correlation -0.90),
  // not the contact moment (0.17). false: predict_legs_free's rigid model.
  bool predict_leg_dynamics = true;
  // [s] the estimator's trust in a stance leg ramps up over this time after touch-down and down
  // over this time before its scheduled lift-off (a landing foot still sinks in).
  double trust_ramp = 0.03;
  // [s] a stance foot's share of the load ramps up over this time after its scheduled touch-down
  // and down over this time before its lift-off (0: switch at once).
  double load_ramp = 0.03;
  // Safety.
  double max_tilt = 15.0 * 3.14159265358979323846 / 180.0;  // [rad] trunk tilt that trips safe stop
  // Safe stop: a soft pull to the crouch, stiffness as a fraction of each joint's effort limit
  // per radian, damping over a time constant; derived gains at most a swing leg's without the
  // joint predictor (a leg in the air must not ring; quadruped_controller.cpp).
  double safe_stiffness = 0.4;        // [1/rad] kp_j = safe_stiffness * effort_j
  double safe_time_constant = 0.1;    // [s] kd_j = safe_time_constant * kp_j
  double safe_kp = 0.0;               // [N m/rad] override (0: derived)
  double safe_kd = 0.0;               // [N m s/rad] override (0: derived)
  double max_measurement_age = 0.005; // [s]
  // Model overrides (0: from the model): total mass and composite inertia used by the wrench.
  double mass = 0.0;                  // [kg] total robot mass
  Eigen::Vector3d inertia_diag = Eigen::Vector3d::Zero();  // [kg m^2] whole robot about its CoM, trunk axes
};

// Once, at configure: ranges and consistency; the reason in *why.
Status validate(const QuadrupedConfig& config, std::string* why);

struct QuadrupedInput {
  double t = 0.0;         // [s] controller time
  double stamp = 0.0;     // [s] when the sensors were sampled
  Vector12d q = Vector12d::Zero();    // [rad] encoders, controller joint order
  Vector12d qd = Vector12d::Zero();   // [rad/s]
  Eigen::Vector3d gyro = Eigen::Vector3d::Zero();    // [rad/s] body frame
  Eigen::Vector3d accel = Eigen::Vector3d(0, 0, 9.81);  // [m/s^2] specific force, body frame
  // External AHRS orientation w, x, y, z (world <- body); read only with estimator.external_attitude.
  Eigen::Vector4d quat = Eigen::Vector4d(1, 0, 0, 0);
  // Command.
  Gait gait = Gait::kStand;
  Eigen::Vector3d velocity_command = Eigen::Vector3d::Zero();  // [m/s, m/s, rad/s] vx, vy (heading frame), yaw rate
  // [m] per foot (FL, FR, RL, RR x (x, y, z)), trunk frame: added to each swing leg's foothold
  // (a learned policy's residual). Clamped to +-kMaxFootholdOffset leg lengths per component;
  // non-finite is a bad input (status, safe output).
  Vector12d foothold_offset = Vector12d::Zero();
  // Debugging: run on ground truth instead of the estimate.
  bool use_ground_truth = false;
  Eigen::Vector3d true_position = Eigen::Vector3d::Zero();  // [m] world
  Eigen::Vector3d true_velocity = Eigen::Vector3d::Zero();  // [m/s] world
  Eigen::Vector4d true_quat = Eigen::Vector4d(1, 0, 0, 0);
};

struct QuadrupedOutput {
  Vector12d tau = Vector12d::Zero();     // [N m] joint torques, always finite, within effort
  Status status = Status::kNotConfigured;
  Vector12d foot_force = Vector12d::Zero();  // [N] ground reaction per foot, world (QP result)
  Eigen::Vector4d contact = Eigen::Vector4d::Zero();    // 1 where the detector says contact
  // 1 where the commands acting now schedule stance (the gait schedule one delay ago)
  Eigen::Vector4d scheduled = Eigen::Vector4d::Zero();
  Eigen::Vector4d foot_clearance = Eigen::Vector4d::Zero();  // [m] feet above the estimated ground
  Eigen::Vector3d position = Eigen::Vector3d::Zero();   // [m] estimated trunk position, world
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();   // [m/s] estimated, world
  Eigen::Vector4d quat = Eigen::Vector4d(1, 0, 0, 0);   // estimated orientation w, x, y, z
  Eigen::Vector3d ground_normal = Eigen::Vector3d::UnitZ();
  Vector6d wrench = Vector6d::Zero();    // desired [F; tau] at the CoM, world
  double tilt = 0.0;                     // [rad] trunk tilt from vertical
  bool safe_stop = false;
  int qp_iterations = 0;
};

class QuadrupedController {
 public:
  static constexpr int kLegs = 4;
  // [leg lengths] bound on each component of QuadrupedInput::foothold_offset: a quarter leg keeps
  // the shifted foothold inside the leg's workspace around its nominal place.
  static constexpr double kMaxFootholdOffset = 0.25;
  static Status configure(const QuadrupedConfig& config, RobotModelPtr model,
                          QuadrupedController* out, std::string* why);
  Status step(const QuadrupedInput& in, QuadrupedOutput& out) noexcept;

  const std::array<std::string, 12>& joint_names() const { return joint_names_; }
  const Vector12d& effort_limit() const { return effort_; }
  double mass() const { return mass_; }
  const LegKinematics& leg(int i) const { return legs_[i]; }
  // The configuration with everything derived filled in (body_height, gains, thresholds...).
  const QuadrupedConfig& config() const { return cfg_; }
  const Vector12d& stand_pose() const { return stand_q_; }   // [rad] derived standing joints
  const Vector12d& crouch_pose() const { return crouch_q_; } // [rad] safe-stop posture
  const Eigen::Vector3d& com() const { return com_; }        // [m] whole-robot CoM standing, trunk frame
  const Eigen::Matrix3d& inertia() const { return inertia_; } // [kg m^2] composite, about the CoM
  // [kg m^2] about the CoM with all the leg joints free (free_leg_inertia.hpp)
  Eigen::Matrix3d inertia_free() const { return inertia_free_.rotational({true, true, true, true}); }
  // The statuses step returned since configure (one StatusCounters for every controller).
  const StatusCounters& counters() const { return counters_; }
  // The state estimator (diagnostics: its gyro bias, ground plane...).
  const StateEstimator& estimator() const { return estimator_; }
  // Leaves a latched safe stop and forgets the measurement order (a new run, a new clock); the
  // estimate, the gait and the counters are kept.
  void reset() noexcept {
    safe_stop_ = false;
    gate_.reset();
  }

 private:
  Eigen::Vector3d heading_frame_position_feedback(const Eigen::Vector3d& e_p) const noexcept;
  static double coupled_swing_frequency(const QuadrupedController& c, const QuadrupedConfig& cfg);
  static LegGeometry knee_nearer_zero(const LegGeometry& g, const QuadrupedConfig& cfg);
  // Per-tick scratch: what one stage of run() hands to the next (fixed size, in the workspace).
  struct Tick {
    Status status = Status::kOk;
    Eigen::Vector3d command = Eigen::Vector3d::Zero();  // [m/s, m/s, rad/s] validated command
    Gait requested = Gait::kStand;
    Eigen::Quaterniond q_imu = Eigen::Quaterniond::Identity();   // the AHRS input (external_attitude)
    Eigen::Quaterniond q_prior = Eigen::Quaterniond::Identity(); // orientation before this tick's estimate
    std::array<LegMeasurement, kLegs> meas{};
    std::array<Eigen::Matrix3d, kLegs> J{};          // foot Jacobians, trunk frame
    std::array<Eigen::Vector3d, kLegs> tau_gravity{}; // [N m] per leg
    std::array<double, kLegs> normal_force{}, clearance{}, load{};  // [N], [m], [-]
    std::array<bool, kLegs> stance{};                // scheduled and detected on the ground
    int n_stance = 0;
    Eigen::Matrix3d R = Eigen::Matrix3d::Identity(); // world <- trunk, estimated
    Eigen::Vector3d p = Eigen::Vector3d::Zero(), v = Eigen::Vector3d::Zero();  // world [m], [m/s]
    Eigen::Vector3d w_body = Eigen::Vector3d::Zero(); // [rad/s] trunk frame
    Eigen::Vector3d v_des = Eigen::Vector3d::Zero();  // [m/s] world
    Vector6d wrench = Vector6d::Zero();              // desired [F; tau] at the CoM, world
    Eigen::Vector3d swing_reaction = Eigen::Vector3d::Zero();  // [N m] trunk frame
    Vector6d accel = Vector6d::Zero();  // [m/s^2; rad/s^2] world: what this tick's command does to the trunk
    Vector12d qdd = Vector12d::Zero();  // [rad/s^2] what this tick's swing torques do to their joints
    // Trunk state predicted one delay ahead, when this tick's command lands (world; body rates).
    Eigen::Vector3d p_pred = Eigen::Vector3d::Zero(), v_pred = Eigen::Vector3d::Zero();
    Eigen::Matrix3d R_pred = Eigen::Matrix3d::Identity();
    Eigen::Vector3d w_pred_body = Eigen::Vector3d::Zero();
  };

  Status run(const QuadrupedInput& in, QuadrupedOutput& out) noexcept;
  // The stages of run(), in order.
  bool read_inputs(const QuadrupedInput& in, QuadrupedOutput& out) noexcept;
  void leg_kinematics(const QuadrupedInput& in) noexcept;
  void detect_contacts(const QuadrupedInput& in, QuadrupedOutput& out) noexcept;
  void estimate_state(const QuadrupedInput& in, QuadrupedOutput& out) noexcept;
  bool safety_stop(const QuadrupedInput& in, QuadrupedOutput& out) noexcept;
  void trunk_reference() noexcept;
  void trunk_wrench(QuadrupedOutput& out) noexcept;
  bool commanded_stance(int leg) const noexcept;
  void swing_legs(const QuadrupedInput& in, QuadrupedOutput& out) noexcept;
  void swing_joint_accelerations(const QuadrupedInput& in, const Vector12d& tau) noexcept;
  void trunk_rotation_from_torques(const Vector12d& tau) noexcept;
  void distribute_forces(QuadrupedOutput& out) noexcept;
  void stance_legs(QuadrupedOutput& out) noexcept;
  void safe_output(const QuadrupedInput& in, Vector12d& tau) const noexcept;
  // in.foothold_offset of leg i, clamped (trunk frame [m]).
  Eigen::Vector3d foothold_offset(const QuadrupedInput& in, int leg) const noexcept;
  void saturate(Vector12d& tau, Status* status) const noexcept;

  QuadrupedConfig cfg_;
  RobotModelPtr model_;
  std::array<LegKinematics, kLegs> legs_;
  std::array<LegGravity, kLegs> leg_gravity_;
  std::array<std::string, 12> joint_names_;
  Vector12d effort_ = Vector12d::Zero();
  Vector12d stand_q_ = Vector12d::Zero(), crouch_q_ = Vector12d::Zero();
  Vector12d safe_kp_ = Vector12d::Zero(), safe_kd_ = Vector12d::Zero();
  Eigen::Vector3d swing_inertia_ = Eigen::Vector3d::Zero();  // [kg m^2] joint inertia diagonal, standing
  std::array<Eigen::Matrix3d, kLegs> leg_mass_inverse_{};    // [1/(kg m^2)] M_leg^-1, standing
  std::array<LegJointInertia, kLegs> leg_inertia_{};          // M_leg at any pose (swing_inertia_at_pose)
  double mass_ = 0.0;
  Eigen::Vector3d com_ = Eigen::Vector3d::Zero();  // [m] whole-robot CoM, trunk frame, standing
  Eigen::Matrix3d inertia_ = Eigen::Matrix3d::Identity();
  FreeLegInertia inertia_free_;  // the composite and each leg's coupling, about the CoM
  // [kg m^2] inertia_free_.rotational(legs swinging) for each set of swinging legs (bit i: leg i)
  std::array<Eigen::Matrix3d, 1 << kLegs> inertia_by_swing_set_{};
  GaitScheduler gait_;
  ContactDetector contacts_;
  StateEstimator estimator_;
  StanceForceQp force_qp_;
  Tick tick_;
  MeasurementGate gate_;  // max_measurement_age and the order of the stamps
  StatusCounters counters_;
  // Commands in flight to the motors (actuation_delay / dt ticks): joint torques, and the trunk
  // accelerations [linear; angular] (world) they command.
  InFlight<Vector12d> tau_in_flight_;
  InFlight<Vector6d> accel_in_flight_;
  InFlight<Vector12d> qdd_in_flight_;  // swing joints' commanded accelerations (0: stance legs)
  // The gait schedule of the commands in flight; oldest(0): the one acting now.
  InFlight<std::array<LegPhase, kLegs>> schedule_in_flight_;
  std::array<LegPhase, kLegs> acting_schedule_{};
  // State carried across ticks.
  Vector12d tau_prev_ = Vector12d::Zero();
  Vector12d f_ = Vector12d::Zero();
  std::array<bool, kLegs> was_stance_{true, true, true, true};
  std::array<Eigen::Vector3d, kLegs> swing_start_{}, swing_target_{};
  std::array<Eigen::Vector3d, kLegs> q_leg_valid_{};
  Eigen::Vector3d v_cmd_ = Eigen::Vector3d::Zero();  // ramped command, heading frame
  Eigen::Vector3d p_des_ = Eigen::Vector3d::Zero();  // [m] desired trunk position (world)
  double yaw_des_ = 0.0;
  double late_time_[kLegs] = {0, 0, 0, 0};
  double contact_time_[kLegs] = {1, 1, 1, 1};  // [s] since the detected touch-down
  double stance_time_[kLegs] = {1, 1, 1, 1};   // [s] since the scheduled touch-down
  bool safe_stop_ = false;
  bool have_output_ = false;
  bool configured_ = false;
};

}  // namespace kiloloop
