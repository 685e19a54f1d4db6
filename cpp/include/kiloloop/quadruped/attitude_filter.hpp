#pragma once
// The controller's own trunk orientation from gyro + accelerometer: an explicit complementary
// filter with gyro-bias estimation (Mahony, Hamel, Pflimlin 2008, "Nonlinear complementary
// filters on the special orthogonal group"). Per tick, in the body frame:
//   v  = R^T e_z                   where the estimate puts "up"
//   e  = (a / |a|) x v             rotation from the estimate's up to the measured one [rad]
//   b <- b + k_b e                 gyro-bias estimate (clamped to +-max_gyro_bias)
//   R <- R exp((gyro - b) dt + k_t e)
// with the gains k_t, k_b of a Kalman filter on [tilt, bias] (below; about k_p w dt and -k_i w dt
// of Mahony's fixed gains once settled).
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
// Gains: after the start-up, a Kalman filter per tilt axis on [tilt, gyro bias], from the IMU's
// Allan parameters. For small angles each tilt axis integrates the gyro (white noise, density N_g;
// bias b, a random walk of density K_g, 1 sigma B0 at start: the turn-on bias) and is measured by
// the accelerometer's direction (white noise of density N_a / g, r = (N_a / g)^2 [rad^2 s]). Per
// tick, with one reading's variance r / dt and S = P_tt + r / dt, the gains are k_t = w P_tt / S
// and k_b = w P_tb / S (the weight w taken as the probability that the reading is gravity, as in
// probabilistic data association: P -= w K S K^T), and P is propagated exactly (F = [1 -dt; 0 1],
// Q from N_g^2 and K_g^2):
//   R <- R exp((gyro - b) dt + k_t e),   b <- b + k_b e            (k_b < 0: P_tb < 0)
// Settled, this is the Kalman-Bucy filter of the model: k_p = sqrt(N_g^2 / r + 2 K_g / sqrt(r))
// [rad/s] (BMI088: 1.47) and k_i = K_g / sqrt(r) [rad/s^2] (0.114); the crossover c = N_g g / N_a
// = 1.39 rad/s is the white-noise part. Why not Mahony's fixed k_i = k_p^2 / 4: the turn-on bias
// (BMI088 after calibration: 2.6e-3 rad/s, 1 sigma) is there from the first tick, and a fixed
// integral gain learns it only as the tilt error it leaves, b t exp(-k_p t / 2) (measured:
// quadruped-push 7 N s, seed 0, roll bias -5.84e-3 rad/s: the roll estimate 0.17 deg off at 1-2 s
// and still 0.13 at 3-4 s, the recovery criterion missed by 0.011 deg; the gyro bias alone
// reproduces it, the other sensor errors add < 0.04 deg). With P_bb = B0^2 when the alignment
// ends the Kalman gains learn it within about a second, then fall to the random walk's. The bias
// gain is kept at most the critically damped one of the tilt gain, -k_b <= (k_t / dt)^2 / 4 dt
// (k_i <= k_p^2 / 4: the tilt/bias loop does not overshoot; right after the alignment the
// Kalman's own k_i reaches 23 rad/s^2 against k_p 6.7 and overshot that bias by half). The same
// run now: bias estimate -5.4e-3 to -5.7e-3 rad/s from 2.9 s on, the roll estimate within 0.015
// deg of the truth on average there, 0.909 deg after recovery.
// Start-up (initial alignment, aligning(): 1 / T > c): a fresh filter knows little of its tilt
// (the robot may start in the air: measured, the SIL plant's accelerometer reads 0 in the first
// ticks of a drop, so the first tick's tilt from gravity is level while the robot stands on a
// 15 deg slope; with k_p alone the 0.26 rad error decays with 1 / k_p = 0.7 s, and the robot fell
// acting on it). The gain of an uninformative prior is 1 / T, T [s] the time the accelerometer has
// counted (sum of w dt): the estimate is the average of the gravity directions seen, falling to c
// at T = 0.72 s; the gain is min(max(c, 1 / T), 1 / dt) w dt, and P_tt = r min(max(c, 1 / T), 1 /
// dt) the variance it stands for. The bias is held there: the start-up's readings (a drop, feet
// sinking into soft ground, a shove) are no steady gravity to learn a bias from (measured with the
// Kalman gains from the first tick: the tilt-stop's shove at 0.5 s was taken for bias, the stop 11
// ticks late; our model on compliant ground read its pitch 14 deg off within 40 ms and fell).
// update() is noexcept and allocation-free.
#include <Eigen/Core>
#include <Eigen/Geometry>

namespace kiloloop {

struct AttitudeFilterConfig {
  double gyro_noise_density = 2.44e-4;   // [rad/s/sqrt(Hz)] N_g (BMI088: 0.014 deg/s/sqrt(Hz))
  double accel_noise_density = 1.72e-3;  // [m/s^2/sqrt(Hz)] N_a (BMI088: 175 ug/sqrt(Hz))
  double crossover = 0.0;                // [rad/s] k_p override; 0: derived N_g g / N_a
  double accel_tolerance = 0.2;          // [-] | |a| - g | / g at which the accelerometer stops counting
  double max_gyro_bias = 0.1;            // [rad/s] bound of the bias estimate (a MEMS gyro: < 0.05)
  double gyro_bias_random_walk = 2.0e-5; // [rad/s^2/sqrt(Hz)] K_g (BMI088-class Allan figure)
  double gyro_turn_on_bias = 2.6e-3;     // [rad/s] B0, 1 sigma at start (BMI088: 0.015 deg/s/K x 10 K)
};

class AttitudeFilter {
 public:
  // Fills in the derived crossover; false on non-positive densities, tolerance or dt, or a
  // negative bias bound, random walk or turn-on bias.
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
  // This tick's gains (see the header comment): tilt [-] and bias [rad/s per rad] per reading.
  double tilt_gain() const { return k_tilt_; }
  double bias_gain() const { return k_bias_; }
  // Still in the start-up alignment (1 / T > k_p): the tilt may yet move by the start error.
  bool aligning() const { return aligned_time_ * kp_ < 1.0; }

 private:
  AttitudeFilterConfig cfg_;
  double dt_ = 0.001, kp_ = 0.0;  // kp_: the crossover c [rad/s] (aligning())
  double r_ = 0.0, q_gyro_ = 0.0, q_bias_ = 0.0;  // [rad^2 s], [rad^2/s], [rad^2/s^3] noise densities
  double p_tt_ = 0.0, p_tb_ = 0.0, p_bb_ = 0.0;   // covariance of [tilt; bias] per tilt axis
  double k_tilt_ = 0.0, k_bias_ = 0.0;
  Eigen::Quaterniond q_ = Eigen::Quaterniond::Identity();
  Eigen::Vector3d bias_ = Eigen::Vector3d::Zero(), rate_ = Eigen::Vector3d::Zero();
  double aligned_time_ = 0.0;  // [s] T: time the accelerometer has counted since reset

  // The raw accelerometer's weight: 1 at |a| = g, 0 at | |a| - g | >= accel_tolerance g.
  double gate(const Eigen::Vector3d& accel) const noexcept;
  // The Mahony step with the gravity reading accel [m/s^2, body] counted with weight w in [0, 1].
  void correct(const Eigen::Vector3d& gyro, const Eigen::Vector3d& accel, double w) noexcept;
};

}  // namespace kiloloop
