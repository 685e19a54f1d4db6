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
// measurement instead (velocity aiding). The raw accelerometer counts with a weight w falling
// linearly from 1 at |a| = g to 0 at | |a| - g | = accel_tolerance g (stance impacts, hops). An
// aided reading counts in full (w = 1, or the caller's weight): what is left of it off g is not the trunk's acceleration
// but the legs' velocity correction, which is where the tilt information is (a tilt error
// dtheta makes the legs correct -g dtheta horizontally, on average exactly). The gate dropped
// just those ticks, as the legs correct horizontally and vertically at once (feet landing,
// sinking): measured on soft ground (quadruped-compliant, realistic sensors, t 1-10 s) the legs'
// mean horizontal correction was -0.56 m/s^2 (= -g x the 2-4 deg pitch error, nose down), the
// gate's weighted mean -0.09, and the estimate stayed level while the trunk pitched down.
// In the start-up alignment the aided reading is gated as the raw one: there the gain 1 / T moves
// the estimate by a good part of one reading's tilt, and the legs' first corrections are large
// (measured: Go1 dropping onto soft ground, |c| 15 m/s^2 in the first 20 ms, pitch estimate -14
// deg while level, fell).
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
  // One tick: gyro [rad/s], accel (specific force) [m/s^2], both in the body frame (finite: the
  // caller checks). The accelerometer counts with the weight w of | |a| - g |.
  void update(const Eigen::Vector3d& gyro, const Eigen::Vector3d& accel) noexcept;
  // One tick, velocity-aided: trunk_accel [m/s^2, body] is the caller's estimate of the trunk's
  // acceleration, removed from accel; the rest counts with the caller's weight in [0, 1] (1 while
  // its estimate holds, see the header comment; not the gate of | |a| - g |).
  void update_aided(const Eigen::Vector3d& gyro, const Eigen::Vector3d& accel,
                    const Eigen::Vector3d& trunk_accel, double weight = 1.0) noexcept;
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

  // The raw accelerometer's weight: 1 at |a| = g, 0 at | |a| - g | >= accel_tolerance g.
  double gate(const Eigen::Vector3d& accel) const noexcept;
  // The Mahony step with the gravity reading accel [m/s^2, body] counted with weight w in [0, 1].
  void correct(const Eigen::Vector3d& gyro, const Eigen::Vector3d& accel, double w) noexcept;
};

}  // namespace kiloloop
