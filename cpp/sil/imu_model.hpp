#pragma once
// MEMS IMU error model of the SIL loops (the Python quadruped rig calls it per tick through the
// bindings; the native loop can call it directly). Per axis and per tick k (dt = sample period):
//   y_k   = x_k + b_k + n_k             n_k ~ N(0, N^2 / dt)          white noise (angle / velocity
//                                                                     random walk, Allan slope -1/2)
//   b_k+1 = b_k + w_k                   w_k ~ N(0, K^2 dt)            bias random walk (rate random
//                                                                     walk, Allan slope +1/2)
//   b_0   ~ N(0, B0^2)                                                turn-on bias, seeded constant
// N [unit/sqrt(Hz)] is the noise density, K [unit/s/sqrt(Hz)] the bias random walk coefficient,
// B0 [unit] the turn-on bias; unit = rad/s for the gyro, m/s^2 for the accelerometer. The
// discretisation keeps the Allan deviation of the continuous model at every averaging time
// tau >= dt: sigma_A(tau) = N / sqrt(tau) for the white part, K sqrt(tau / 3) for the walk.
//
// Defaults: Bosch BMI088 (datasheet BST-BMI088-DS001), the IMU of many legged robots.
//   gyro  noise density 0.014 deg/s/sqrt(Hz) = 2.44e-4 rad/s/sqrt(Hz)
//   accel noise density 175 ug/sqrt(Hz)       = 1.72e-3 m/s^2/sqrt(Hz)
//   Turn-on bias: the datasheet's raw offsets (gyro +-1 deg/s, accel +-20 mg) are calibrated out
//   on the bench once; what is left is the temperature drift over +-10 K from the calibration
//   temperature: gyro 0.015 deg/s/K -> 0.15 deg/s = 2.6e-3 rad/s, accel 0.2 mg/K -> 2 mg =
//   0.0196 m/s^2 (1 sigma).
//   Bias random walk: not on the datasheet; of the order of Allan-variance characterisations of
//   BMI088-class parts: gyro 2e-5 rad/s^2/sqrt(Hz), accel 3e-4 m/s^3/sqrt(Hz).
// configure() may allocate; apply() is noexcept and allocation-free. Same seed, same stream.
#include <string>
#include <vector>

#include "sil/rng.hpp"

namespace kiloloop::sil {

// Allan-variance parameters of one triaxial sensor (the same on each axis).
struct InertialNoise {
  double noise_density = 0.0;     // N  [unit/sqrt(Hz)]
  double bias_random_walk = 0.0;  // K  [unit/s/sqrt(Hz)]
  double turn_on_bias = 0.0;      // B0 [unit], 1 sigma of the seeded constant
};

struct ImuModelConfig {
  InertialNoise gyro{2.44e-4, 2.0e-5, 2.6e-3};    // rad/s units: BMI088 (see above)
  InertialNoise accel{1.72e-3, 3.0e-4, 0.0196};   // m/s^2 units: BMI088 (see above)
  double dt = 0.001;              // [s] sample period
  unsigned long long seed = 0;
};

class ImuModel {
 public:
  static constexpr int kSize = 6;  // [gyro (3) rad/s; accel (3) m/s^2], body frame
  // Fails (false, why) on a negative or non-finite parameter or dt <= 0. Draws the turn-on bias.
  bool configure(const ImuModelConfig& config, std::string* why);
  // y = x + bias + white noise, then the bias takes one random-walk step. x, y: kSize entries
  // (may alias). Six white and six walk normals are drawn every call, whatever the parameters,
  // so a seed's stream does not depend on which effects are on.
  void apply(const double* x, double* y) noexcept;
  // [gyro (3); accel (3)] bias of the next sample.
  const double* bias() const noexcept { return bias_; }
  const ImuModelConfig& config() const noexcept { return cfg_; }

 private:
  ImuModelConfig cfg_;
  double white_[kSize] = {};  // per-sample sigma N / sqrt(dt)
  double walk_[kSize] = {};   // per-sample bias step sigma K sqrt(dt)
  double bias_[kSize] = {};
  Rng rng_;
};

// Joint velocity from the difference of two successive encoder readings:
//   qd_k = (Q(q_k) - Q(q_k-1)) / dt,  Q(q) = resolution * round(q / resolution)
// resolution [rad] is that of the encoder the drive differentiates (a motor-side encoder behind
// the gear: finer than the joint's output encoder by the reduction), so qd comes in steps of
// resolution / dt. The first sample after configure/reset reads 0 (no previous position).
class EncoderVelocity {
 public:
  bool configure(int n, double resolution, double dt, std::string* why);
  void reset() noexcept { primed_ = false; }
  void apply(const double* q, double* qd) noexcept;
  int size() const noexcept { return n_; }

 private:
  int n_ = 0;
  double resolution_ = 0.0, dt_ = 0.001;
  bool primed_ = false;
  std::vector<double> previous_;
};

}  // namespace kiloloop::sil
