#pragma once
// A stage of the native loop's measurement path after the SensorModel (white noise,
// quantization) and before the MeasurementDelay: it rewrites the flat measurement vector y in
// place at tick time t [s]. Stages run in the order given (RolloutConfig::sensor_stages). An IMU
// model (bias, random walk) is one: it owns the IMU slice of y, whose place the adapter's layout
// documents (quadruped: y[24..33] = gyro, accel, quat). Each rollout must own its stages (they
// carry state and random streams), as it owns its mjData.
#include <string>

namespace kiloloop::sil {

class SensorStage {
 public:
  virtual ~SensorStage() = default;
  // Configure time: the length of y; false with why when the stage does not fit it.
  virtual bool configure(int n, std::string* why) = 0;
  virtual void apply(double t, double* y) noexcept = 0;
};

}  // namespace kiloloop::sil
