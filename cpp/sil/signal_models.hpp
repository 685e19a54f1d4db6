#pragma once
// Sensor and actuator models of the native SIL loop, over flat signal vectors so that every robot
// family uses the same code (an arm measures [q; qd], a quadruped adds its IMU):
//   plant signals -> SensorModel (Gaussian noise, quantization) -> MeasurementDelay (whole ticks)
//   -> adapter -> controller -> MotorModel (transport delay in ticks, first-order lag) -> ctrl
// Buffers are sized at configure; apply/push never allocate. Units are those of the signal.
#include <string>
#include <vector>

#include "sil/rng.hpp"

namespace kiloloop::sil {

// sigma and quantum cover y's first entries: n of them, or fewer (the entries after them pass
// through untouched and draw no noise: ground truth appended to a measurement, whose noise stream
// then stays the one of the shorter y), or none (empty).
struct SensorModelConfig {
  std::vector<double> sigma;    // (<= n) white-noise standard deviation per element; empty: none
  std::vector<double> quantum;  // (<= n) quantization step per element (0: none); empty: none
  unsigned long long seed = 0;  // noise stream
};

class SensorModel {
 public:
  // Fails (false, why) on more than n entries, or negative / non-finite entries.
  bool configure(const SensorModelConfig& config, int n, std::string* why);
  // y = quantum * round((x + sigma * N(0, 1)) / quantum), rounding half to even (numpy.round).
  // With any sigma > 0 one normal is drawn per element of sigma every call, whatever the sigmas,
  // so a seed's stream does not depend on which elements are noisy.
  void apply(const double* x, double* y) noexcept;
  int size() const { return n_; }

 private:
  int n_ = 0;
  std::vector<double> sigma_, quantum_;
  bool noisy_ = false;
  int noisy_n_ = 0;                   // elements that draw a normal (sigma's given length)
  bool quantized_ = false;            // any quantum > 0
  std::vector<int> quantized_index_;  // the elements whose quantum > 0
  Rng rng_;
};

// Measurements wait `ticks` control ticks, a FIFO: while fewer than ticks + 1 samples have
// arrived the newest one is used.
class MeasurementDelay {
 public:
  void configure(int n, int ticks);
  // Pushes (t, x) and returns the (stamp, y) the controller sees at this tick (without a delay,
  // y is x itself: valid while x is).
  void push(double t, const double* x, double* stamp, const double** y) noexcept;

 private:
  int n_ = 0, ticks_ = 0, head_ = 0, count_ = 0;
  std::vector<double> times_, values_;  // ring of ticks + 1 samples
};

struct MotorModelConfig {
  int delay_ticks = 0;          // [ticks] command transport delay; zeros until the first arrives
  double time_constant = 0.0;   // [s] first-order lag of the produced torque (0: none)
  double dt = 0.001;            // [s] control period
  std::vector<double> limit;    // (n) |output| bound per element after the lag (saturation); empty: none
  // Before the first command has travelled through: false, zeros (a drive with no command
  // outputs nothing); true, the first command (no start-up sag: a hovering vehicle's rotors).
  bool hold_first = false;
};

class MotorModel {
 public:
  bool configure(const MotorModelConfig& config, int n, std::string* why);
  // Queues this tick's command u and writes what the motors produce now:
  //   y_k = y_k-1 + alpha (u_{k-delay} - y_k-1),  alpha = dt / (time_constant + dt)
  // (backward Euler of T y' + y = u; alpha = 1 without lag, y_-1 = 0), then clipped to +-limit
  // (the lag state itself is not clipped: the limit is the drive's, after the motor).
  void push(const double* u, double* y) noexcept;
  int size() const { return n_; }

 private:
  int n_ = 0, ticks_ = 0, head_ = 0;
  bool hold_first_ = false, primed_ = false;
  double alpha_ = 1.0;
  std::vector<double> fifo_, state_, limit_;
};

}  // namespace kiloloop::sil
