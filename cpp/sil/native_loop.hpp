#pragma once
// The native SIL loop: the 1 kHz closed loop in C++, on the mjModel/mjData the Python plant
// built (python/kiloloop/sil/rig.py configures it). Per tick k (t = k * control_dt):
//   y_raw = sensordata[measurement]          plant signals (MuJoCo sensors, current state; or
//                                            qpos / qvel entries: a motion-capture stand-in)
//   y     = SensorModel(y_raw)               noise, quantization (seeded)
//   stamp, y = MeasurementDelay(t, y)        whole ticks
//   log t and the ground-truth probes        (what a scenario's observe() records; computed
//                                            ones, contact counts and distances, first)
//   fire the events due (t >= time)
//   disturbances: this tick's wrench per body (wind drag, ...) from the current state
//   u     = adapter.step(t, stamp, y)        compiled controller
//   ctrl[actuators] = MotorModel(u)          transport delay, first-order lag
//   substeps x (xfrc_applied of the pushed bodies; mj_step2; [contact forces on the last]; mj_step1)
//                                            so sensors describe the new state (sil/plant.py)
//   stop after this tick if the stop probe fell below its bound (a fall ends a trot run), or
//   (stop_nonfinite) if the physics left a non-finite qpos (a diverged flight)
// Deterministic: no clock, no shared state, a seeded RNG; the same inputs give the same log on
// any thread. Allocation only in configure.
#include <memory>
#include <string>
#include <vector>

#include <mujoco/mujoco.h>

#include "sil/adapter.hpp"
#include "sil/events.hpp"
#include "sil/contact_forces.hpp"
#include "sil/disturbance.hpp"
#include "sil/log_buffer.hpp"
#include "sil/sensor_stage.hpp"
#include "sil/signal_models.hpp"

namespace kiloloop::sil {

// A ground-truth signal logged every tick (never seen by the controller). kBodiesPos and
// kContactForce take several body ids and log (bodies x 3): their origins [m], and the contact
// force on each during the last physics step [N] (world; sil/contact_forces.hpp). kSitesPos:
// several site ids, their positions (sites x 3) [m] (world; the quadruped's foot sphere centres).
// kSubtreeCom: {body id}, the centre of mass of the body and its descendants [m] (world);
// kActuatorForce: actuator ids, their force (gain x activation for a rotor) [N]; kBodyMat:
// {body id}, its rotation (3 x 3, world <- body). Computed each tick (one value each):
// kContactCount: geom ids, the number of the data's contacts (d->ncon entries) that involve any
// of them (a contact is counted once; arm-rrt's "no contact with the box"); kGeomDistance:
// {geom, others...}, the smallest signed distance [m] from geom to any other (mj_geomDistance,
// capped at kGeomDistanceMax).
struct Probe {
  enum class Source : int { kSensor = 0, kSitePos = 1, kSiteMat = 2, kBodyPos = 3, kBodyQuat = 4,
                            kQpos = 5, kQvel = 6, kBodiesPos = 7, kContactForce = 8,
                            kSubtreeCom = 9, kActuatorForce = 10, kBodyMat = 11, kSitesPos = 12,
                            kContactCount = 13, kGeomDistance = 14 };
  static constexpr int kLastSource = 14;
  // [m] kGeomDistance's distmax: farther pairs read this (arm_scene.min_distance's default).
  static constexpr double kGeomDistanceMax = 1.0;
  std::string name;
  Source source = Source::kSensor;
  std::vector<int> index;  // sensordata / qpos / qvel addresses, or {site id} / {body id}
};

struct RolloutConfig {
  double control_dt = 0.001;          // [s] controller period
  int ticks = 0;                      // control ticks to run
  std::vector<int> measurement;       // sensordata addresses forming y_raw (adapter's layout)
  // Per element of measurement, where its address points: 0 sensordata, 1 qpos, 2 qvel (the
  // ground truth a motion-capture system stands in for). Empty: all sensordata.
  std::vector<int> measurement_source;
  std::vector<int> actuators;         // ctrl indices written from u (adapter's layout)
  int delay_ticks = 0;                // measurement delay [ticks]
  SensorModelConfig sensor;
  // After the sensor model, in order (an IMU model, ...); each rollout owns its own.
  std::vector<std::shared_ptr<SensorStage>> sensor_stages;
  MotorModelConfig motor;
  std::vector<Event> events;
  // Once per tick after the events (each rollout owns its own).
  std::vector<std::shared_ptr<Disturbance>> disturbances;
  std::vector<Probe> probes;
  // Early stop: the run ends after the first tick whose probes[stop_probe][stop_element] is
  // below stop_below (-1: never).
  int stop_probe = -1;
  int stop_element = 0;
  double stop_below = 0.0;
  // The run ends after a tick whose physics left a non-finite qpos (RolloutResult::diverged).
  bool stop_nonfinite = false;
};

struct RolloutResult {
  int ticks = 0;            // ticks completed
  int warnings = 0;         // MuJoCo warnings raised during the run (instability, ...)
  bool ok = false;          // no error so far (a stopped or unfinished run may be ok)
  bool stopped = false;     // the stop probe (or a divergence) ended the run early
  bool diverged = false;    // stop_nonfinite: the physics state became non-finite
  std::string error;        // why the run stopped early (empty when ok)
};

class Rollout {
 public:
  // model/data: borrowed (the caller keeps them alive and gives each concurrent rollout its own
  // data); adapter shared with the caller. False with why on inconsistent sizes or addresses.
  bool configure(const mjModel* model, mjData* data, std::shared_ptr<Adapter> adapter,
                 RolloutConfig config, std::string* why);
  // Runs the remaining ticks (all config.ticks on a fresh rollout) from the data's current
  // state; never throws.
  const RolloutResult& run() noexcept;
  // Runs up to n more ticks (fewer at the end or after a stop): a caller that acts between
  // chunks (a gym environment) keeps one rollout per episode.
  const RolloutResult& advance(int n) noexcept;
  bool finished() const { return result_.stopped || !result_.error.empty() || k_ >= config_.ticks; }
  Adapter& adapter() { return *adapter_; }
  const RolloutResult& result() const { return result_; }
  const LogBuffer& log() const { return log_; }
  LogBuffer& log() { return log_; }
  // Before the first tick: keep every tick's controller input and output records from now on
  // (the back-to-back log's, adapter.io_record_bytes(); the buffer is allocated here), so a
  // recorded run stays in C++. False with why when the adapter has none or ticks already ran.
  bool record_io(std::string* why);
  // Per tick run, the input record then the output record (io_sizes() bytes; empty unless
  // record_io).
  const std::vector<unsigned char>& io_records() const { return io_; }
  IoRecordBytes io_sizes() const { return io_bytes_; }

 private:
  void tick(int k);
  void fire_events(double t) noexcept;
  void physics_step(bool last) noexcept;
  bool stop_due(int k) noexcept;
  void compute_probes() noexcept;

  const mjModel* m_ = nullptr;
  mjData* d_ = nullptr;
  std::shared_ptr<Adapter> adapter_;
  RolloutConfig config_;
  int substeps_ = 1;
  SensorModel sensor_;
  MeasurementDelay delay_;
  MotorModel motor_;
  std::vector<double> y_raw_, y_, u_, u_applied_;
  std::vector<const double*> y_src_;  // per element of y_raw: where in the data it is read
  std::vector<int> force_bodies_;  // bodies whose xfrc_applied the force events and disturbances own
  std::vector<double> wrenches_;   // (disturbances x 6) this tick's
  std::vector<int> push_steps_;    // per event: physics steps its force still acts (0: none)
  size_t next_event_ = 0;
  int k_ = 0;                      // next tick
  std::vector<ContactForces> contact_forces_;  // per probe (empty unless kContactForce)
  std::vector<double> probe_values_;     // per probe: the value a computed probe (contacts,
                                         // distance) writes each tick before the copy
  std::vector<int> computed_probes_;     // indices of the computed probes (kContactCount,
                                         // kGeomDistance): the only ones compute_probes visits
  std::vector<const double*> probe_src_;  // every probe element's source, in log order
  std::vector<size_t> probe_end_;         // per probe: one past its last entry in probe_src_
  LogBuffer log_;
  IoRecordBytes io_bytes_;
  std::vector<unsigned char> io_;  // (ticks x io_bytes_.total()) with record_io, else empty
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
