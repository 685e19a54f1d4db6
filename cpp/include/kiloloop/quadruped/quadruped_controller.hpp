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

#include "kiloloop/kinematics/leg_gravity.hpp"
#include "kiloloop/kinematics/leg_kinematics.hpp"
#include "kiloloop/model/robot_model.hpp"
#include "kiloloop/quadruped/contact_detector.hpp"
#include "kiloloop/quadruped/gait_scheduler.hpp"
#include "kiloloop/quadruped/stance_force.hpp"
#include "kiloloop/quadruped/state_estimator.hpp"
#include "kiloloop/status.hpp"

namespace kiloloop {

using Vector12d = Eigen::Matrix<double, 12, 1>;
using Vector6d = Eigen::Matrix<double, 6, 1>;

struct QuadrupedConfig {
  std::string trunk_link = "trunk";
  std::array<std::string, 4> feet{"FL_foot", "FR_foot", "RL_foot", "RR_foot"};
  double dt = 0.001;                  // [s] control period
  double foot_radius = 0.02;          // [m] foot sphere radius (contact point below its centre)
  double body_height = 0.30;          // [m] trunk origin above the ground, along world z
  GaitConfig gait;
  ContactConfig contact;
  EstimatorConfig estimator;
  StanceForceConfig force;
  // Trunk PD, as accelerations per unit error (multiplied by mass / inertia inside).
  Eigen::Vector3d kp_position{20.0, 20.0, 300.0};  // [1/s^2] x, y (integrated velocity command), z
  Eigen::Vector3d kd_velocity{8.0, 8.0, 35.0};     // [1/s]
  // Roll/pitch gains are bounded by the 10 ms motor delay. With the force QP realizing the moment
  // about the diagonal support line (wrench_weight), 500/35 oscillates and falls in SIL; 250/20
  // gives the smallest trot roll measured (RMS 0.15 deg at 0.5 m/s, noise and delay on).
  Eigen::Vector3d kp_orientation{250.0, 250.0, 150.0};  // [1/s^2] roll, pitch, yaw (body axes)
  Eigen::Vector3d kd_angular{20.0, 20.0, 20.0};    // [1/s]
  // Swing legs.
  double swing_height = 0.08;         // [m] apex above the line lift-off -> touch-down
  // [s] foothold shift per m/s of velocity error. The capture-point value sqrt(h/g) is 0.175; with
  // the feet landing ~30 ms early and the 10 ms delay, 0.13 recovered 12 N s pushes with 4 of 4
  // seeds (0.15: 2 of 4; 0.17: 0 of 2) and tracks 1 m/s better (measured in SIL).
  double raibert_gain = 0.13;
  double touchdown_depth = 0.01;      // [m] aim this far below the ground to make contact
  bool swing_reaction_feedforward = true;  // stance forces also cancel the swing motors' reaction
  // [m] trunk-frame shift of all footholds from their nominal place: under the hips, moved along
  // x to the whole-robot CoM so that each diagonal support line passes through it.
  Eigen::Vector2d foothold_shift = Eigen::Vector2d::Zero();
  // Swing gains are limited by the motor command delay (10 ms by default in SIL): with the light
  // shank, kd above ~1 N m s/rad turns the delayed derivative action unstable. The abduction
  // torque of a swing leg reacts on the trunk as a roll moment that the stance feet do not see
  // coming: abduction 40/0.8 made the trot roll +-1.1 deg, 20/0.4 +-0.7 deg (measured).
  Eigen::Vector3d swing_kp{20.0, 40.0, 20.0};  // [N m/rad] abduction, pitch, knee
  Eigen::Vector3d swing_kd{0.4, 0.8, 0.4};     // [N m s/rad]
  double max_acceleration = 1.0;      // [m/s^2] ramp on the commanded velocity
  // [m] how far the horizontal position target may lead or trail the trunk: it integrates the
  // velocity command (no steady velocity error), but after a push the robot should not walk back
  // the whole way, only settle.
  double max_position_lag = 0.05;
  // [s] known command-to-motor latency: feedback uses the state predicted this far ahead
  // (0 disables; SIL's default motor delay is 10 ms).
  double actuation_delay = 0.010;
  // [s] the estimator's trust in a stance leg ramps up over this time after touch-down and down
  // over this time before its scheduled lift-off (a landing foot still sinks in).
  double trust_ramp = 0.03;
  // [s] a stance foot's share of the load ramps up over this time after its scheduled touch-down
  // and down over this time before its lift-off (0: switch at once).
  double load_ramp = 0.03;
  // Safety.
  double max_tilt = 15.0 * 3.14159265358979323846 / 180.0;  // [rad] trunk tilt that trips safe stop
  Eigen::Vector3d stand_pose{0.0, 0.9, -1.8};  // [rad] per leg: nominal standing joints (CoM, IK seed)
  Eigen::Vector3d crouch{0.0, 1.3, -2.6};  // [rad] per leg: safe-stop posture
  double safe_kp = 15.0;              // [N m/rad] soft pull to the crouch
  double safe_kd = 1.5;               // [N m s/rad] joint damping in safe stop
  double max_measurement_age = 0.005; // [s]
  // Model overrides (0/empty: from the model): trunk mass and inertia used by the wrench.
  double mass = 0.0;                  // [kg] total robot mass
  Eigen::Vector3d inertia_diag = Eigen::Vector3d::Zero();  // [kg m^2] trunk + legs, body axes
};

struct QuadrupedInput {
  double t = 0.0;         // [s] controller time
  double stamp = 0.0;     // [s] when the sensors were sampled
  Vector12d q = Vector12d::Zero();    // [rad] encoders, controller joint order
  Vector12d qd = Vector12d::Zero();   // [rad/s]
  Eigen::Vector3d gyro = Eigen::Vector3d::Zero();    // [rad/s] body frame
  Eigen::Vector3d accel = Eigen::Vector3d(0, 0, 9.81);  // [m/s^2] specific force, body frame
  Eigen::Vector4d quat = Eigen::Vector4d(1, 0, 0, 0);   // IMU orientation w, x, y, z (world <- body)
  // Command.
  int gait = 0;                                      // 0 stand, 1 trot
  Eigen::Vector3d velocity_command = Eigen::Vector3d::Zero();  // [m/s, m/s, rad/s] vx, vy (heading frame), yaw rate
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
  Eigen::Vector4d scheduled = Eigen::Vector4d::Zero();  // 1 where the gait schedules stance
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
  static Status configure(const QuadrupedConfig& config, RobotModelPtr model,
                          QuadrupedController* out, std::string* why);
  Status step(const QuadrupedInput& in, QuadrupedOutput& out) noexcept;

  const std::array<std::string, 12>& joint_names() const { return joint_names_; }
  const Vector12d& effort_limit() const { return effort_; }
  double mass() const { return mass_; }
  const LegKinematics& leg(int i) const { return legs_[i]; }
  void reset_safe_stop() noexcept { safe_stop_ = false; }

 private:
  Status run(const QuadrupedInput& in, QuadrupedOutput& out) noexcept;
  void safe_output(const QuadrupedInput& in, Vector12d& tau) const noexcept;
  void saturate(Vector12d& tau, Status* status) const noexcept;

  QuadrupedConfig cfg_;
  RobotModelPtr model_;
  std::array<LegKinematics, kLegs> legs_;
  std::array<LegGravity, kLegs> leg_gravity_;
  std::array<std::string, 12> joint_names_;
  Vector12d effort_ = Vector12d::Zero();
  double mass_ = 0.0;
  Eigen::Vector3d com_ = Eigen::Vector3d::Zero();  // [m] whole-robot CoM, trunk frame, standing
  Eigen::Matrix3d inertia_ = Eigen::Matrix3d::Identity();
  GaitScheduler gait_;
  ContactDetector contacts_;
  StateEstimator estimator_;
  StanceForceQp force_qp_;
  // Per-tick state carried across ticks.
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
