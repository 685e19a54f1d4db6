#pragma once
// A sensor dropout as a stage of the native loop's measurement path (sensor_stage.hpp): from
// tick time `start` [s] for `duration` [s] the slice y[offset .. offset + count) stays frozen at
// the last value it had before the dropout (a bus that stops updating while its driver repeats
// the last sample; the controller is not told). Outside the window the slice passes unchanged.
// The held copy is sized at configure: apply allocates nothing.
#include <string>
#include <vector>

#include "sil/sensor_stage.hpp"

namespace kiloloop::sil {

class DropoutStage final : public SensorStage {
 public:
  DropoutStage(int offset, int count, double start, double duration)
      : offset_(offset), count_(count), start_(start), end_(start + duration) {}
  bool configure(int n, std::string* why) override;
  void apply(double t, double* y) noexcept override;

 private:
  int offset_, count_;
  double start_, end_;          // [s] the window [start, end)
  std::vector<double> held_;    // (count) the slice's last value before the window
  bool have_ = false;           // a value was seen before the window
};

}  // namespace kiloloop::sil
