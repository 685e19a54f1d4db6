#pragma once
// Trunk state estimate for a legged robot from the IMU and leg kinematics.
//  - Orientation: complementary filter. The gyro is integrated every tick; the IMU's own
//    orientation output pulls the estimate back with a small gain (it drifts less, is noisier).
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
// Fixed-size Eigen throughout: update() is noexcept and allocation-free.
#include <array>
#include <string>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "kiloloop/status.hpp"

namespace kiloloop {

struct EstimatorConfig {
  double dt = 0.001;                 // [s]
  double attitude_gain = 0.005;      // per tick pull toward the IMU orientation (0 = gyro only)
  double accel_noise = 0.5;          // [m/s^2] process noise on the acceleration input
  double leg_velocity_noise = 0.05;  // [m/s] per-leg velocity measurement noise
  double foothold_noise = 0.01;      // [m] per-leg position measurement noise
  double ground_filter = 0.05;       // per touch-down low-pass weight of the ground normal update
};

// Finite; dt > 0; 0 <= attitude_gain <= 1 and 0 <= ground_filter <= 1 (per-tick blend weights);
// accel_noise, leg_velocity_noise, foothold_noise > 0 (the Kalman filter divides by them). The
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
  // First call (or after reset): initialise orientation from the IMU and position from feet.
  void reset(const Eigen::Quaterniond& q_imu, const std::array<LegMeasurement, kLegs>& legs,
             double foot_radius);
  // Returns kEstimatorDegraded when no leg was in contact (prediction only).
  Status update(const Eigen::Vector3d& gyro, const Eigen::Vector3d& accel,
                const Eigen::Quaterniond& q_imu, const std::array<LegMeasurement, kLegs>& legs) noexcept;

  bool initialised() const { return initialised_; }
  const Eigen::Quaterniond& orientation() const { return q_; }  // world <- body
  Eigen::Matrix3d rotation() const { return q_.toRotationMatrix(); }
  Eigen::Vector3d position() const { return x_.head<3>(); }   // world [m]
  Eigen::Vector3d velocity() const { return x_.tail<3>(); }   // world [m/s]
  const Eigen::Vector3d& angular_velocity() const { return omega_; }  // body [rad/s]
  const Eigen::Vector3d& ground_normal() const { return normal_; }
  double ground_height(double x, double y) const { return plane_[0] + plane_[1] * x + plane_[2] * y; }
  const Eigen::Vector3d& foothold(int leg) const { return footholds_[leg]; }
  // Debugging switch: overwrite the estimate with ground truth.
  void set_truth(const Eigen::Vector3d& p, const Eigen::Vector3d& v, const Eigen::Quaterniond& q) noexcept;

 private:
  void fit_ground() noexcept;

  EstimatorConfig cfg_;
  bool initialised_ = false;
  Eigen::Quaterniond q_ = Eigen::Quaterniond::Identity();
  Eigen::Vector3d omega_ = Eigen::Vector3d::Zero();
  Eigen::Matrix<double, 6, 1> x_ = Eigen::Matrix<double, 6, 1>::Zero();
  Eigen::Matrix<double, 6, 6> P_ = Eigen::Matrix<double, 6, 6>::Identity();
  std::array<Eigen::Vector3d, kLegs> footholds_{};
  std::array<bool, kLegs> foothold_latched_{true, true, true, true};
  Eigen::Vector3d normal_ = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d plane_ = Eigen::Vector3d::Zero();  // z = a + b x + c y
  double foot_radius_ = 0.0;
};

}  // namespace kiloloop
