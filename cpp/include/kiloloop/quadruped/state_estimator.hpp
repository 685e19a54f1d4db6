#pragma once
// Trunk state estimate for a legged robot from the IMU and leg kinematics.
//  - Orientation (AttitudeFilter, attitude_filter.hpp): by default the controller's own
//    explicit complementary filter on gyro + accelerometer, with gyro-bias estimation; yaw is
//    not observed (no magnetometer) and drifts with the gyro's z bias. Velocity aiding
//    (velocity_aiding): the accelerometer reads the trunk's acceleration on top of gravity, and
//    the filter alone takes both for "up" (measured in a 0.5 m/s trot without aiding: the trot's
//    vertical bounce moves | |a| - g | so far that the accelerometer counted with a mean weight
//    of 0.32, zero on 27% of the ticks, and the counted directions were 0.9 deg off in pitch and
//    0.4 in roll; the reduced weight also slowed the gyro-bias learning, and a 5.8 mrad/s roll
//    bias left 0.4 deg of roll error 5 s in). Aided, the filter is handed the velocity filter's
//    own trunk acceleration of the last tick, a = R f + g + c (c: the legs' velocity correction
//    per second), and takes f - R^T a = R^T (-g - c) as gravity: the trot's accelerations cancel
//    and what is left tilts only by what the legs had to correct. In steady state c = -(R - R_true)
//    f exactly, so the measurement is R_true^T (-g): the true up, whatever the trunk does (also in
//    the start-up alignment; measured before: a shove at 0.5 s, the raw accelerometer at the
//    alignment's high gain put the tipping trunk's estimate 0.7 deg behind, the safe stop 3 ticks
//    late). After a tick without stance legs the raw specific force is taken (free fall: ignored).
//    With external_attitude
//    an external AHRS's quaternion is followed instead: the gyro is integrated and the estimate
//    pulled toward the AHRS output by attitude_gain per tick.
//  - Position and velocity: linear Kalman filter on x = [p; v] (world). Prediction uses the
//    accelerometer (rotated to world, gravity removed); the correction uses legs in contact:
//      velocity: a stance foot does not move, so v = -R (J qd + w x r) for each stance leg;
//      position: p = p_foot - R r, with p_foot latched once the foot has settled.
//    Each leg counts with a trust in [0, 1] (MIT Cheetah's phase-based trust): a foot that has
//    just landed still sinks into the ground and one about to lift off is unloading; both move,
//    and counting them biases the height (measured: +12 mm/s of z drift in a trot with full
//    trust). While trust < 1 the foothold follows the foot; it is latched when trust reaches 1.
//  - Ground plane: least-squares plane through the four latest foothold positions, giving the
//    ground normal (friction cones follow it on slopes) and the height of the ground under the trunk.
//    While the own attitude filter is still aligning (AttitudeFilter::aligning: the first ~0.7 s)
//    the stance footholds are not latched and the plane is refit unfiltered each tick: footholds
//    latched with a start orientation that was off (measured: level, a drop's accelerometer reads
//    0, on a 15 deg slope) kept the plane level for good, the friction cones wrong, and the robot
//    slid 1.7 m down the slope in 5.5 s.
// Fixed-size Eigen throughout: update() is noexcept and allocation-free.
#include <array>
#include <string>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "kiloloop/quadruped/attitude_filter.hpp"
#include "kiloloop/quadruped/axis_covariance.hpp"
#include "kiloloop/status.hpp"

namespace kiloloop {

struct EstimatorConfig {
  double dt = 0.001;                 // [s]
  bool external_attitude = false;    // true: follow QuadrupedInput.quat (an external AHRS)
  double attitude_gain = 0.005;      // external_attitude: per tick pull toward the AHRS (0 = gyro only)
  AttitudeFilterConfig attitude;     // the own filter (external_attitude false)
  bool velocity_aiding = true;       // own filter: tilt from the legs' velocity correction
  double accel_noise = 0.5;          // [m/s^2] process noise on the acceleration input
  double leg_velocity_noise = 0.05;  // [m/s] per-leg velocity measurement noise
  double foothold_noise = 0.01;      // [m] per-leg position measurement noise
  // Stance legs gated by consistency: a leg whose implied trunk velocity differs from the
  // predicted one by e, with d^2 = e^T S^-1 e (S = the filter's velocity covariance + the leg's
  // noise), counts with its trust times min(1, velocity_gate / d^2). What it gates: a stance
  // foot's estimated world velocity is -e, so a leg far outside it is a foot that does not
  // stand (measured on Go1 with a 35 ms delay: a landing foot that bounced and was then driven
  // down at -3 to -4.5 m/s by stance torques counted as standing, and the estimated vertical
  // velocity jumped to +0.63 m/s with the true one +0.11). Default: the chi-square 99 % point
  // of 3 degrees of freedom (a statistical value, not measured); 0 disables.
  double velocity_gate = 11.34;
  double ground_filter = 0.05;       // per touch-down low-pass weight of the ground normal update
};

// Finite; dt > 0; 0 <= attitude_gain <= 1 and 0 <= ground_filter <= 1 (per-tick blend weights);
// accel_noise, leg_velocity_noise, foothold_noise > 0 (the Kalman filter divides by them);
// attitude: noise densities and accel_tolerance > 0, crossover, max_gyro_bias, gyro_bias_random_walk
// and gyro_turn_on_bias >= 0. The
// reason in *why.
Status validate(const EstimatorConfig& config, std::string* why);

struct LegMeasurement {
  bool contact = false;
  bool touched_down = false;       // contact began this tick: latch the foothold
  Eigen::Vector3d r;               // foot position in the trunk frame [m]
  Eigen::Vector3d v_rel;           // foot velocity from joint motion, J qd, trunk frame [m/s]
  double trust = 1.0;              // [0, 1] weight of this stance leg in the correction
};

class StateEstimator {
 public:
  static constexpr int kLegs = 4;
  // kInvalidConfig (why) unless validate(config) passes.
  Status configure(const EstimatorConfig& config, std::string* why);
  const EstimatorConfig& config() const { return cfg_; }  // attitude crossover resolved
  // The orientation a first call starts from: the AHRS's (external_attitude), else roll and
  // pitch from the accelerometer's gravity direction, yaw 0.
  Eigen::Quaterniond initial_orientation(const Eigen::Vector3d& accel, const Eigen::Quaterniond& q_imu) const noexcept;
  // First call (or after reset): orientation q0 (initial_orientation) and position from feet.
  void reset(const Eigen::Quaterniond& q0, const std::array<LegMeasurement, kLegs>& legs,
             double foot_radius);
  // Returns kEstimatorDegraded when no leg was in contact (prediction only). q_imu is read only
  // with external_attitude.
  Status update(const Eigen::Vector3d& gyro, const Eigen::Vector3d& accel,
                const Eigen::Quaterniond& q_imu, const std::array<LegMeasurement, kLegs>& legs) noexcept;

  bool initialised() const { return initialised_; }
  const Eigen::Quaterniond& orientation() const { return q_; }  // world <- body
  Eigen::Matrix3d rotation() const { return q_.toRotationMatrix(); }
  Eigen::Vector3d position() const { return x_.head<3>(); }   // world [m]
  Eigen::Vector3d velocity() const { return x_.tail<3>(); }   // world [m/s]
  const Eigen::Vector3d& angular_velocity() const { return omega_; }  // body [rad/s], bias removed
  const Eigen::Vector3d& gyro_bias() const { return attitude_.gyro_bias(); }  // body [rad/s]
  const Eigen::Vector3d& ground_normal() const { return normal_; }
  double ground_height(double x, double y) const { return plane_[0] + plane_[1] * x + plane_[2] * y; }
  const Eigen::Vector3d& foothold(int leg) const { return footholds_[leg]; }
  // Debugging switch: overwrite the estimate with ground truth.
  void set_truth(const Eigen::Vector3d& p, const Eigen::Vector3d& v, const Eigen::Quaterniond& q) noexcept;

 private:
  void update_orientation(const Eigen::Vector3d& gyro, const Eigen::Vector3d& accel,
                          const Eigen::Quaterniond& q_imu, bool aided) noexcept;
  void fit_ground() noexcept;
  // The velocity filter's trunk acceleration [m/s^2, body frame] of the last tick (velocity aiding).
  Eigen::Vector3d trunk_acceleration(const Eigen::Vector3d& accel) const noexcept;
  // Weight in [0, 1] of the aided tilt reading: 0 once the legs' correction exceeds what a tilt
  // error can explain (velocity_correction_ above g).
  double aiding_weight() const noexcept;

  EstimatorConfig cfg_;
  bool initialised_ = false;
  bool aligning_ = false;  // the own attitude filter in its start-up alignment
  AttitudeFilter attitude_;
  Eigen::Quaterniond q_ = Eigen::Quaterniond::Identity();
  Eigen::Vector3d omega_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d velocity_correction_ = Eigen::Vector3d::Zero();  // [m/s^2] c: legs' last correction / dt
  bool legs_corrected_ = false;  // the last tick's legs corrected the velocity (c is valid)
  Eigen::Matrix<double, 6, 1> x_ = Eigen::Matrix<double, 6, 1>::Zero();
  AxisCovariance P_;  // of x_, per axis (the 6x6 is [[a I, b I], [c I, d I]])
  std::array<Eigen::Vector3d, kLegs> footholds_{};
  std::array<bool, kLegs> foothold_latched_{true, true, true, true};
  Eigen::Vector3d normal_ = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d plane_ = Eigen::Vector3d::Zero();  // z = a + b x + c y
  double foot_radius_ = 0.0;
};

}  // namespace kiloloop
