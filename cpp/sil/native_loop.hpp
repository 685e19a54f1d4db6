#pragma once
// The native SIL loop: the 1 kHz closed loop of sil/loop.py in C++, on the mjModel/mjData the
// Python plant built. Per tick k (t = k * control_dt), in the Python loop's order:
//   y_raw = sensordata[measurement]          plant signals (MuJoCo sensors, current state)
//   y     = SensorModel(y_raw)               noise, quantization (seeded)
//   stamp, y = MeasurementDelay(t, y)        whole ticks
//   log t and the ground-truth probes        (what a scenario's observe() records)
//   fire the events due (t >= time)
//   u     = adapter.step(t, stamp, y)        compiled controller
//   ctrl[actuators] = MotorModel(u)          transport delay, first-order lag
//   xfrc_applied of the bodies with force events
//   substeps x (mj_step2; mj_step1)          so sensors describe the new state (sil/plant.py)
// Deterministic: no clock, no shared state, a seeded RNG; the same inputs give the same log on
// any thread. Allocation only in configure.
#include <memory>
#include <string>
#include <vector>

#include <mujoco/mujoco.h>

#include "sil/adapter.hpp"
#include "sil/events.hpp"
#include "sil/log_buffer.hpp"
#include "sil/signal_models.hpp"

namespace kiloloop::sil {

// A ground-truth signal logged every tick (never seen by the controller).
struct Probe {
  enum class Source : int { kSensor = 0, kSitePos = 1, kSiteMat = 2, kBodyPos = 3, kBodyQuat = 4,
                            kQpos = 5, kQvel = 6 };
  std::string name;
  Source source = Source::kSensor;
  std::vector<int> index;  // sensordata / qpos / qvel addresses, or {site id} / {body id}
};

struct RolloutConfig {
  double control_dt = 0.001;          // [s] controller period
  int ticks = 0;                      // control ticks to run
  std::vector<int> measurement;       // sensordata addresses forming y_raw (adapter's layout)
  std::vector<int> actuators;         // ctrl indices written from u (adapter's layout)
  int delay_ticks = 0;                // measurement delay [ticks]
  SensorModelConfig sensor;
  MotorModelConfig motor;
  std::vector<Event> events;
  std::vector<Probe> probes;
};

struct RolloutResult {
  int ticks = 0;            // ticks completed
  int warnings = 0;         // MuJoCo warnings raised during the run (instability, ...)
  bool ok = false;
  std::string error;        // why the run stopped early (empty when ok)
};

class Rollout {
 public:
  // model/data: borrowed (the caller keeps them alive and gives each concurrent rollout its own
  // data); adapter shared with the caller. False with why on inconsistent sizes or addresses.
  bool configure(const mjModel* model, mjData* data, std::shared_ptr<Adapter> adapter,
                 RolloutConfig config, std::string* why);
  // Runs config.ticks ticks from the data's current state; never throws.
  const RolloutResult& run() noexcept;
  const RolloutResult& result() const { return result_; }
  const LogBuffer& log() const { return log_; }
  LogBuffer& log() { return log_; }

 private:
  void tick(int k);
  void apply_forces(double t) noexcept;

  const mjModel* m_ = nullptr;
  mjData* d_ = nullptr;
  std::shared_ptr<Adapter> adapter_;
  RolloutConfig config_;
  int substeps_ = 1;
  SensorModel sensor_;
  MeasurementDelay delay_;
  MotorModel motor_;
  std::vector<double> y_raw_, y_, u_, u_applied_;
  std::vector<int> force_bodies_;  // bodies whose xfrc_applied the force events own
  size_t next_event_ = 0;
  LogBuffer log_;
  int ch_t_ = 0;
  std::vector<int> ch_probe_;
  RolloutResult result_;
};

// Controller cost reference for the bench: n adapter steps on a fixed measurement y at
// t = k * dt, no physics (into a log the function sizes itself: allocates, not for the loop).
void step_adapter(Adapter& adapter, const double* y, int n, double dt);

// Raw MuJoCo cost reference for the bench: n x mj_step on (model, data). With ctrl (n x k,
// row-major) and actuators (k), row i goes to ctrl[actuators] before step i: replaying a loop's
// commands gives the same motion (contacts and all) without the loop.
void step_raw(const mjModel* model, mjData* data, int n, const double* ctrl = nullptr,
              const int* actuators = nullptr, int k = 0) noexcept;

}  // namespace kiloloop::sil
