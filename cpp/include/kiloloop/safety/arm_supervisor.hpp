#pragma once
// ArmSupervisor: the last stage between an arm controller and the motors, at 1 kHz.
// In NORMAL mode it passes the controller's torque through (clipped to the effort limits) and
// watches:
//   joint position  - trips when the braking distance at the stop deceleration would carry a joint
//                     past its limit: q + sign(qd) qd^2 / (2 a_stop) outside [lower, upper];
//   joint velocity  - |qd| > velocity limit;
//   joint accel.    - |qdd| > acceleration limit, qdd from the measured qd (low-pass filtered);
//   torque          - instantaneous: |tau| above the effort limit is clipped (kSaturated), and a
//                     command beyond peak_trip_ratio x effort (a controller gone wrong) trips;
//                     sustained: a first-order I^2 t thermal state per joint,
//                       theta' = ((tau / tau_rated)^2 - theta) / T_thermal, trips at theta >= 1
//                     (an RMS torque above tau_rated held for about T_thermal);
//   singularity     - SingularityMonitor: warning only (kNearSingularity), the torque passes;
//   e-stop input    - trips.
// A trip latches a CONTROLLED STOP (IEC 60204-1 category 2): from the state at the trip, every
// joint's velocity ramps to zero at its stop deceleration (stop time max_j |qd_j| / a_stop_j,
// distance qd_j^2 / (2 a_stop_j)), tracked by computed torque, then HOLDS the final position.
// Back to NORMAL only through `reset` while the e-stop is released and the arm holds.
// Bad measurement (size, NaN/Inf, stale or out of order: MeasurementGate): nothing can be checked. In NORMAL the output is gravity
// at the last valid q; max_bad_ticks consecutive bad ticks latch a stop (trip kStaleMeasurement)
// from the last valid (q, qd). While STOPPING or HOLDING without a measurement the stop goes on
// open loop: the inverse dynamics of the planned stop reference (its braking deceleration, then
// gravity at the final position), so an outage never lets a stop coast. Open loop cannot hold for
// long (gravity on a pose off the planned one acts as a negative stiffness): an outage that
// outlasts the stop needs the motor brakes, which are outside this class.
// step() is noexcept, allocation-free, never throws; statuses and counters say what happened.
#include <string>

#include <Eigen/Core>

#include "kiloloop/control/rules.hpp"
#include "kiloloop/dynamics/dynamics.hpp"
#include "kiloloop/safety/singularity_monitor.hpp"

namespace kiloloop {

struct ArmSupervisorConfig {
  Eigen::Vector3d gravity = Eigen::Vector3d(0.0, 0.0, -9.81);  // [m/s^2] chain root frame
  // Each limit vector: empty = the model's limit, 1 entry = broadcast, or nq entries.
  Eigen::VectorXd lower, upper;              // [rad] position limits
  Eigen::VectorXd velocity_limit;            // [rad/s]
  Eigen::VectorXd acceleration_limit = Eigen::VectorXd::Constant(1, 20.0);  // [rad/s^2]
  Eigen::VectorXd effort_limit;              // [N m] peak torque (clip)
  Eigen::VectorXd stop_deceleration = Eigen::VectorXd::Constant(1, 4.0);    // [rad/s^2] a_stop
  double peak_trip_ratio = 1.5;              // |tau_command| > this x effort trips at once
  double rated_torque_fraction = 0.5;        // continuous rating tau_rated / effort
  double thermal_time_constant = 2.0;        // [s] T_thermal of the I^2 t model
  double acceleration_filter = 0.005;        // [s] time constant of the qdd low-pass
  double max_measurement_age = 0.005;        // [s]
  int max_bad_ticks = 20;                    // consecutive bad measurements that latch a stop
  double stop_kp = 400.0;                    // [1/s^2] computed-torque gains of the stop/hold
  double stop_kd = 40.0;                     // [1/s]
  SingularityMonitorConfig singularity;      // manipulability thresholds of the slow-down and stop
};

Status validate(const ArmSupervisorConfig& config, int nq, std::string* why);

enum class SupervisorMode : int { kNormal = 0, kStopping = 1, kHolding = 2 };

struct SupervisorInput {
  double t = 0.0;             // [s] controller time
  double stamp = 0.0;         // [s] when q, qd were sampled
  Eigen::VectorXd q;          // (nq) [rad]
  Eigen::VectorXd qd;         // (nq) [rad/s]
  Eigen::VectorXd tau_command;  // (nq) [N m] the arm controller's output
  bool estop = false;         // emergency-stop input (true = pressed)
  bool reset = false;         // request to leave HOLD (honoured when estop is false)
};

struct SupervisorOutput {
  Eigen::VectorXd tau;        // (nq) [N m] to the motors: finite, within the effort limits
  SupervisorMode mode = SupervisorMode::kNormal;
  Status status = Status::kNotConfigured;
  Status trip = Status::kOk;  // why the current stop/hold happened (kOk in NORMAL)
  SingularityState singularity;
  Eigen::VectorXd thermal;    // (nq) I^2 t state theta (trips at 1)
  double stop_time = 0.0;     // [s] planned duration of the current controlled stop
};

// The step statuses (StatusCounters, as every controller) plus the supervisor's events: trips
// are counted once when they latch (the status then repeats every tick of the stop), warnings and
// clipping per tick whatever the tick's final status.
struct SupervisorCounters : StatusCounters {
  std::uint64_t estops = 0;
  std::uint64_t position_trips = 0;
  std::uint64_t velocity_trips = 0;
  std::uint64_t acceleration_trips = 0;
  std::uint64_t overload_trips = 0;      // sustained (I^2 t) and instantaneous (peak) trips
  std::uint64_t bad_command_trips = 0;   // NaN/Inf or wrong-size torque from the controller
  std::uint64_t clipped = 0;             // ticks with clipped torque
  std::uint64_t singularity_warnings = 0;  // ticks with a warning
  std::uint64_t measurement_trips = 0;   // stops latched by max_bad_ticks bad measurements
  std::uint64_t resets = 0;
  // Ticks with a bad measurement (size, NaN/Inf, stale): their step status says which.
  std::uint64_t bad_measurements() const noexcept {
    return count(Status::kBadSize) + count(Status::kNonFiniteMeasurement) +
           count(Status::kStaleMeasurement);
  }
};

class ArmSupervisor {
 public:
  static Status configure(const ArmSupervisorConfig& config, RobotModelPtr model, ArmSupervisor* out,
                          std::string* why);

  Status step(const SupervisorInput& in, SupervisorOutput& out) noexcept;
  // Forgets the measurement order (a new run, a new clock); counters kept. Leaving a stop is
  // `in.reset` (an operator's act, through the input).
  void reset() noexcept { gate_.reset(); }

  int nq() const { return dyn_.nq(); }
  SupervisorInput make_input() const;
  SupervisorOutput make_output() const;
  const SupervisorCounters& counters() const { return counters_; }
  SupervisorMode mode() const { return mode_; }

 private:
  void trip(Status why, double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd) noexcept;
  void stop_reference(double t) noexcept;
  Status stop_torque(const SupervisorInput& in, Eigen::Ref<Eigen::VectorXd> tau) noexcept;
  Status blind_torque(const SupervisorInput& in, Eigen::Ref<Eigen::VectorXd> tau) noexcept;
  Status clip(Status s, Eigen::Ref<Eigen::VectorXd> tau) noexcept;
  Status run(const SupervisorInput& in, SupervisorOutput& out) noexcept;  // step, uncounted

  Dynamics dyn_;
  ArmSupervisorConfig config_;
  SingularityMonitor singularity_;
  Eigen::VectorXd lower_, upper_, vmax_, amax_, effort_, astop_;
  // State.
  SupervisorMode mode_ = SupervisorMode::kNormal;
  Status trip_ = Status::kOk;
  Eigen::VectorXd thermal_, qd_prev_, qdd_filt_, last_valid_q_, last_valid_qd_;
  bool has_prev_ = false, has_valid_q_ = false;
  int bad_ticks_ = 0;  // consecutive bad measurements
  double t_prev_ = 0.0;
  // Controlled stop: started at t_stop_ from q_stop_, qd_stop_.
  double t_stop_ = 0.0, stop_time_ = 0.0;
  Eigen::VectorXd q_stop_, qd_stop_;
  // Scratch.
  Eigen::MatrixXd J_;
  Eigen::VectorXd q_ref_, qd_ref_, qdd_ref_, v_;
  MeasurementGate gate_;
  SupervisorCounters counters_;
  bool configured_ = false;
};

}  // namespace kiloloop
