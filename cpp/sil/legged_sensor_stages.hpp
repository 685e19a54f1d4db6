#pragma once
// Realistic legged-robot sensors as stages of the measurement path (sil/sensor_stage.hpp): the
// native loop runs them from RolloutConfig::sensor_stages (a test may call one through the
// bindings, SensorStage.apply).
//   ImuStage:          y[offset .. offset+6) = [gyro (3); accel (3)] through the MEMS error model
//                      (sil/imu_model.hpp: white noise, bias random walk, seeded turn-on bias).
//   JointEncoderStage: y[q_offset .. +n) = raw joint angles (the SensorModel must leave them
//                      unquantized); writes y[qd_offset .. +n) = encoder-difference velocity
//                      (EncoderVelocity on the drive's finer encoder, velocity_resolution), then
//                      quantizes q to the joint encoder (q_resolution). The measured velocity is
//                      thereby a finite difference, not the simulator's exact qd.
// configure() allocates; apply() is noexcept and allocation-free.
#include <string>

#include "sil/imu_model.hpp"
#include "sil/sensor_stage.hpp"

namespace kiloloop::sil {

class ImuStage final : public SensorStage {
 public:
  // False (why) on invalid IMU parameters (ImuModel::configure) or a negative offset.
  bool setup(const ImuModelConfig& config, int offset, std::string* why);
  bool configure(int n, std::string* why) override;
  void apply(double t, double* y) noexcept override;
  const ImuModel& model() const { return imu_; }

 private:
  ImuModel imu_;
  int offset_ = 0;
};

class JointEncoderStage final : public SensorStage {
 public:
  // n joints; resolutions [rad] (0: exact); dt [s] the sample period.
  bool setup(int n, int q_offset, int qd_offset, double q_resolution, double velocity_resolution,
             double dt, std::string* why);
  bool configure(int n, std::string* why) override;
  void apply(double t, double* y) noexcept override;

 private:
  EncoderVelocity velocity_;
  int n_ = 0, q_offset_ = 0, qd_offset_ = 0;
  double q_resolution_ = 0.0;
};

}  // namespace kiloloop::sil
