#pragma once
// The controller's own trunk orientation from gyro + accelerometer: an explicit complementary
// filter with gyro-bias estimation (Mahony, Hamel, Pflimlin 2008, "Nonlinear complementary
// filters on the special orthogonal group"). Per tick, in the body frame:
//   v  = R^T e_z                   where the estimate puts "up"
//   e  = (a / |a|) x v             rotation from the estimate's up to the measured one [rad]
//   b <- b - k_i w e dt            gyro-bias estimate (clamped to +-max_gyro_bias)
//   R <- R exp((gyro - b + k_p w e) dt)
// The accelerometer measures the specific force f = a_trunk - g: gravity only when the trunk does
// not accelerate. The caller may hand over its own estimate of the trunk's acceleration (body
// frame, e.g. from leg odometry: StateEstimator) and a = f - a_trunk is taken as the gravity
// measurement instead (velocity aiding). The weight w falls linearly from 1 at |a| = g to 0 at
// | |a| - g | = accel_tolerance g (stance impacts, hops).
// Gravity says nothing about yaw: the yaw estimate follows the gyro and drifts with its z bias.
// Gains from the IMU's noise densities (Allan parameters): for small angles each tilt axis is a
// random walk driven by the gyro's white noise (density N_g) and measured by the accelerometer's
// direction with white noise of density N_a / g; the steady-state Kalman-Bucy gain of that
// filter is k_p = sqrt(N_g^2 / (N_a / g)^2) = N_g g / N_a [rad/s], the crossover frequency
// (BMI088: 2.44e-4 * 9.81 / 1.72e-3 = 1.39 rad/s). k_i = k_p^2 / 4 makes the tilt-error loop
// s^2 + k_p s + k_i critically damped, so a gyro bias is learnt in a few 1 / k_p without
// overshoot.
// Start-up (initial alignment): k_p is the steady-state gain, for an estimate already good to
// the noise. A fresh filter knows nothing of its tilt (the robot may start in the air: measured,
// the SIL plant's accelerometer reads 0 in the first ticks of a drop, so the first tick's tilt
// from gravity is level while the robot stands on a 15 deg slope; with k_p alone the 0.26 rad
// error decays with 1 / k_p = 0.7 s, and the robot fell acting on it). The Kalman gain from an
// uninformative prior is 1 / T, T [s] the time the accelerometer has counted (sum of w dt): the
// estimate is the average of the gravity directions seen, falling to k_p once 1 / T < k_p
// (T = 0.7 s). The gain is used as min(max(k_p, 1 / T), 1 / dt). update() is noexcept and
// allocation-free.
#include <Eigen/Core>
#include <Eigen/Geometry>

namespace kiloloop {

struct AttitudeFilterConfig {
  double gyro_noise_density = 2.44e-4;   // [rad/s/sqrt(Hz)] N_g (BMI088: 0.014 deg/s/sqrt(Hz))
  double accel_noise_density = 1.72e-3;  // [m/s^2/sqrt(Hz)] N_a (BMI088: 175 ug/sqrt(Hz))
  double crossover = 0.0;                // [rad/s] k_p override; 0: derived N_g g / N_a
  double accel_tolerance = 0.2;          // [-] | |a| - g | / g at which the accelerometer stops counting
  double max_gyro_bias = 0.1;            // [rad/s] bound of the bias estimate (a MEMS gyro: < 0.05)
};

class AttitudeFilter {
 public:
  // Fills in the derived crossover; false on non-positive densities, tolerance or dt.
  bool configure(const AttitudeFilterConfig& config, double dt);
  const AttitudeFilterConfig& config() const { return cfg_; }  // crossover resolved
  void reset(const Eigen::Quaterniond& q0) noexcept;
  // Roll and pitch that put the measured specific force straight up, yaw 0; identity when the
  // accelerometer does not see about 1 g (falling, or a bad reading).
  static Eigen::Quaterniond from_gravity(const Eigen::Vector3d& accel) noexcept;
  // One tick: gyro [rad/s], accel (specific force) and trunk_accel (the caller's estimate of the
  // trunk's acceleration, removed from accel; zero: none) [m/s^2], all in the body frame
  // (finite: the caller checks).
  void update(const Eigen::Vector3d& gyro, const Eigen::Vector3d& accel,
              const Eigen::Vector3d& trunk_accel = Eigen::Vector3d::Zero()) noexcept;
  const Eigen::Quaterniond& orientation() const { return q_; }  // world <- body
  const Eigen::Vector3d& gyro_bias() const { return bias_; }    // [rad/s]
  const Eigen::Vector3d& rate() const { return rate_; }         // [rad/s] gyro - bias
  // Still in the start-up alignment (1 / T > k_p): the tilt may yet move by the start error.
  bool aligning() const { return aligned_time_ * kp_ < 1.0; }

 private:
  AttitudeFilterConfig cfg_;
  double dt_ = 0.001, kp_ = 0.0, ki_ = 0.0;
  Eigen::Quaterniond q_ = Eigen::Quaterniond::Identity();
  Eigen::Vector3d bias_ = Eigen::Vector3d::Zero(), rate_ = Eigen::Vector3d::Zero();
  double aligned_time_ = 0.0;  // [s] T: time the accelerometer has counted since reset
};

}  // namespace kiloloop
