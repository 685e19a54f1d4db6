#include "kiloloop/safety/arm_supervisor.hpp"

#include <cmath>

namespace kiloloop {
namespace {

// Empty -> fallback; 1 entry -> broadcast; nq entries -> as is; anything else -> false.
bool expand(const Eigen::VectorXd& v, const Eigen::VectorXd& fallback, int nq, Eigen::VectorXd* out) {
  if (v.size() == 0) *out = fallback;
  else if (v.size() == 1) *out = Eigen::VectorXd::Constant(nq, v[0]);
  else if (v.size() == nq) *out = v;
  else return false;
  return true;
}

}  // namespace

Status validate(const ArmSupervisorConfig& c, int nq, std::string* why) {
  auto fail = [&](const char* msg) {
    if (why) *why = msg;
    return Status::kInvalidConfig;
  };
  const Eigen::VectorXd inf = Eigen::VectorXd::Constant(nq, INFINITY);
  Eigen::VectorXd v;
  for (const Eigen::VectorXd* x : {&c.lower, &c.upper, &c.velocity_limit, &c.acceleration_limit,
                                   &c.effort_limit, &c.stop_deceleration})
    if (!expand(*x, inf, nq, &v) || v.hasNaN()) return fail("limit vectors must be empty, 1 or nq entries, no NaN");
  if (!expand(c.stop_deceleration, inf, nq, &v) || !v.allFinite() || (v.array() <= 0.0).any())
    return fail("stop_deceleration must be finite and > 0");
  if (!expand(c.acceleration_limit, inf, nq, &v) || (v.array() <= 0.0).any())
    return fail("acceleration_limit must be > 0");
  if (!c.gravity.allFinite()) return fail("gravity must be finite");
  if (!(c.peak_trip_ratio >= 1.0)) return fail("peak_trip_ratio must be >= 1 (inf disables)");
  if (!(c.rated_torque_fraction > 0.0) || !std::isfinite(c.rated_torque_fraction))
    return fail("rated_torque_fraction must be > 0");
  if (!(c.thermal_time_constant > 0.0) || !std::isfinite(c.thermal_time_constant))
    return fail("thermal_time_constant must be > 0");
  if (!(c.acceleration_filter >= 0.0) || !std::isfinite(c.acceleration_filter))
    return fail("acceleration_filter must be finite and >= 0");
  if (!(c.max_measurement_age > 0.0)) return fail("max_measurement_age must be > 0");
  if (c.max_bad_ticks < 1) return fail("max_bad_ticks must be >= 1");
  if (!(c.stop_kp >= 0.0) || !(c.stop_kd >= 0.0) || !std::isfinite(c.stop_kp) || !std::isfinite(c.stop_kd))
    return fail("stop_kp and stop_kd must be finite and >= 0");
  return validate(c.singularity, why);
}

Status ArmSupervisor::configure(const ArmSupervisorConfig& config, RobotModelPtr model,
                                ArmSupervisor* out, std::string* why) {
  if (!model) {
    if (why) *why = "model is null";
    return Status::kModelError;
  }
  const int n = model->nq();
  Status s = validate(config, n, why);
  if (failed(s)) return s;
  ArmSupervisor a;
  s = Dynamics::configure(model, config.gravity, &a.dyn_, why);
  if (failed(s)) return s;
  const Eigen::VectorXd inf = Eigen::VectorXd::Constant(n, INFINITY);
  expand(config.lower, model->lower(), n, &a.lower_);
  expand(config.upper, model->upper(), n, &a.upper_);
  expand(config.velocity_limit, model->velocity_limit(), n, &a.vmax_);
  expand(config.acceleration_limit, inf, n, &a.amax_);
  expand(config.effort_limit, model->effort_limit(), n, &a.effort_);
  expand(config.stop_deceleration, inf, n, &a.astop_);
  if (!a.effort_.allFinite()) {
    if (why) *why = "effort limits must be finite (the I^2 t model needs a rating)";
    return Status::kInvalidConfig;
  }
  a.config_ = config;
  a.singularity_.configure(config.singularity);
  a.thermal_ = a.qd_prev_ = a.qdd_filt_ = a.last_valid_q_ = a.last_valid_qd_ = Eigen::VectorXd::Zero(n);
  a.q_stop_ = a.qd_stop_ = a.q_ref_ = a.qd_ref_ = a.qdd_ref_ = a.v_ = Eigen::VectorXd::Zero(n);
  a.J_ = Eigen::MatrixXd::Zero(6, n);
  a.gate_ = MeasurementGate(config.max_measurement_age);
  a.configured_ = true;
  *out = std::move(a);
  return Status::kOk;
}

SupervisorInput ArmSupervisor::make_input() const {
  SupervisorInput in;
  in.q = in.qd = in.tau_command = Eigen::VectorXd::Zero(nq());
  return in;
}

SupervisorOutput ArmSupervisor::make_output() const {
  SupervisorOutput out;
  out.tau = out.thermal = Eigen::VectorXd::Zero(nq());
  return out;
}

void ArmSupervisor::trip(Status why, double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd) noexcept {
  if (mode_ != SupervisorMode::kNormal) return;  // the first reason latches
  mode_ = SupervisorMode::kStopping;
  trip_ = why;
  t_stop_ = t;
  q_stop_ = q;
  qd_stop_ = qd;
  stop_time_ = 0.0;
  for (int j = 0; j < nq(); ++j) stop_time_ = std::fmax(stop_time_, std::fabs(qd_stop_[j]) / astop_[j]);
  switch (why) {
    case Status::kEmergencyStop: ++counters_.estops; break;
    case Status::kTorqueOverload: ++counters_.overload_trips; break;
    case Status::kNonFiniteReference:
    case Status::kBadSize: ++counters_.bad_command_trips; break;
    case Status::kStaleMeasurement: ++counters_.measurement_trips; break;
    default: break;  // limit trips are counted where they are detected
  }
}

void ArmSupervisor::stop_reference(double t) noexcept {
  // Each joint decelerates at a_stop from its velocity at the trip, then holds.
  const double elapsed = std::fmax(t - t_stop_, 0.0);
  for (int j = 0; j < nq(); ++j) {
    const double v0 = qd_stop_[j], a = astop_[j], sgn = v0 < 0.0 ? -1.0 : 1.0;
    const double T = std::fabs(v0) / a, s = std::fmin(elapsed, T);
    q_ref_[j] = q_stop_[j] + v0 * s - 0.5 * sgn * a * s * s;
    qd_ref_[j] = v0 - sgn * a * s;
    qdd_ref_[j] = elapsed < T ? -sgn * a : 0.0;
  }
  if (elapsed >= stop_time_) mode_ = SupervisorMode::kHolding;
}

Status ArmSupervisor::stop_torque(const SupervisorInput& in, Eigen::Ref<Eigen::VectorXd> tau) noexcept {
  stop_reference(in.t);
  v_ = qdd_ref_ + config_.stop_kd * (qd_ref_ - in.qd) + config_.stop_kp * (q_ref_ - in.q);
  if (failed(dyn_.inverse_dynamics(in.q, in.qd, v_, tau))) {
    if (failed(dyn_.gravity(in.q, tau))) tau.setZero();
  }
  return trip_;
}

Status ArmSupervisor::blind_torque(const SupervisorInput& in, Eigen::Ref<Eigen::VectorXd> tau) noexcept {
  // No trustworthy state: the feed-forward of the planned stop at the planned state. The time of a
  // non-finite tick is the last valid one (the reference pauses, still braking or holding).
  stop_reference(std::isfinite(in.t) ? in.t : t_prev_);
  if (failed(dyn_.inverse_dynamics(q_ref_, qd_ref_, qdd_ref_, tau))) {
    if (failed(dyn_.gravity(q_ref_, tau))) tau.setZero();
  }
  return trip_;
}

Status ArmSupervisor::clip(Status s, Eigen::Ref<Eigen::VectorXd> tau) noexcept {
  const Status c = clip_effort(Status::kOk, tau, effort_);
  if (c != Status::kOk) ++counters_.clipped;
  return worst(s, c);
}

Status ArmSupervisor::step(const SupervisorInput& in, SupervisorOutput& out) noexcept {
  if (!configured_) return out.status = Status::kNotConfigured;
  const Status s = run(in, out);
  counters_.record(s);
  return s;
}

Status ArmSupervisor::run(const SupervisorInput& in, SupervisorOutput& out) noexcept {
  const int n = nq();
  if (out.tau.size() != n || out.thermal.size() != n) return out.status = Status::kBadSize;
  Status s = Status::kOk;
  // A measurement we cannot trust: hold against gravity where the arm last was; nothing else
  // can be checked this tick.
  const bool sizes_ok = in.q.size() == n && in.qd.size() == n;
  Status bad = Status::kOk;
  if (!sizes_ok) bad = Status::kBadSize;
  else if (!in.q.allFinite() || !in.qd.allFinite()) bad = Status::kNonFiniteMeasurement;
  else bad = gate_.check(in.t, in.stamp);
  if (bad != Status::kOk) {
    if (bad_ticks_ < config_.max_bad_ticks) ++bad_ticks_;  // saturates: no overflow in a long outage
    // A long outage is a fault of its own: stop now, from the last valid state carried forward at
    // its velocity (gravity compensation alone lets the arm coast) to this tick.
    if (bad_ticks_ >= config_.max_bad_ticks && has_valid_q_ && mode_ == SupervisorMode::kNormal) {
      // A time that jumped (beyond 1 s, as for dt below) is not trusted for the projection.
      const double gap = std::isfinite(in.t) ? in.t - t_prev_ : 0.0;
      const double t = gap > 0.0 && gap <= 1.0 ? in.t : t_prev_;
      q_ref_ = last_valid_q_ + (t - t_prev_) * last_valid_qd_;
      trip(Status::kStaleMeasurement, t, q_ref_, last_valid_qd_);
    }
    if (mode_ != SupervisorMode::kNormal) {
      blind_torque(in, out.tau);
    } else if (!has_valid_q_ || failed(dyn_.gravity(last_valid_q_, out.tau))) {
      out.tau.setZero();
    }
    clip(bad, out.tau);
    out.mode = mode_;
    out.trip = trip_;
    out.thermal = thermal_;
    out.stop_time = stop_time_;
    return out.status = bad;
  }
  gate_.accept(in.stamp);
  bad_ticks_ = 0;
  last_valid_q_ = in.q;
  last_valid_qd_ = in.qd;
  has_valid_q_ = true;

  // Time step and filtered acceleration from the measured velocity.
  double dt = has_prev_ ? in.t - t_prev_ : 0.0;
  if (!(dt > 0.0) || dt > 1.0) dt = 0.0;
  if (dt > 0.0) {
    const double alpha = dt / (config_.acceleration_filter + dt);
    qdd_filt_ += alpha * ((in.qd - qd_prev_) / dt - qdd_filt_);
  }
  qd_prev_ = in.qd;
  t_prev_ = in.t;
  has_prev_ = true;

  // Singularity: a warning in every mode.
  if (dyn_.jacobian(in.q, J_) == Status::kOk &&
      singularity_.update(J_, dt, &out.singularity) == Status::kNearSingularity) {
    ++counters_.singularity_warnings;
    s = Status::kNearSingularity;
  }

  if (mode_ == SupervisorMode::kHolding && !in.estop && in.reset) {
    mode_ = SupervisorMode::kNormal;
    trip_ = Status::kOk;
    ++counters_.resets;
  }
  if (mode_ == SupervisorMode::kNormal) {
    if (in.estop) trip(Status::kEmergencyStop, in.t, in.q, in.qd);
    else if (in.tau_command.size() != n) trip(Status::kBadSize, in.t, in.q, in.qd);
    else if (!in.tau_command.allFinite()) trip(Status::kNonFiniteReference, in.t, in.q, in.qd);
    else if (((in.tau_command.cwiseAbs() - config_.peak_trip_ratio * effort_).array() > 0.0).any())
      trip(Status::kTorqueOverload, in.t, in.q, in.qd);
  }
  if (mode_ == SupervisorMode::kNormal) {
    for (int j = 0; j < n; ++j) {
      const double brake = in.qd[j] * std::fabs(in.qd[j]) / (2.0 * astop_[j]);  // signed distance
      if (in.q[j] + brake > upper_[j] || in.q[j] + brake < lower_[j]) {
        ++counters_.position_trips;
        trip(Status::kLimitViolation, in.t, in.q, in.qd);
        break;
      }
      if (std::fabs(in.qd[j]) > vmax_[j]) {
        ++counters_.velocity_trips;
        trip(Status::kLimitViolation, in.t, in.q, in.qd);
        break;
      }
      if (std::fabs(qdd_filt_[j]) > amax_[j]) {
        ++counters_.acceleration_trips;
        trip(Status::kLimitViolation, in.t, in.q, in.qd);
        break;
      }
    }
  }
  if (mode_ == SupervisorMode::kNormal) {
    out.tau = in.tau_command;
  } else {
    s = worst(s, stop_torque(in, out.tau));
  }
  s = clip(s, out.tau);

  // Sustained overload: I^2 t state of the torque actually sent.
  if (dt > 0.0) {
    const double k = dt / config_.thermal_time_constant;
    for (int j = 0; j < n; ++j) {
      const double r = out.tau[j] / (config_.rated_torque_fraction * effort_[j]);
      thermal_[j] += k * (r * r - thermal_[j]);
    }
  }
  if (mode_ == SupervisorMode::kNormal && (thermal_.array() >= 1.0).any()) {
    trip(Status::kTorqueOverload, in.t, in.q, in.qd);
    s = worst(s, stop_torque(in, out.tau));
    s = clip(s, out.tau);
  }
  out.mode = mode_;
  out.trip = trip_;
  out.thermal = thermal_;
  out.stop_time = stop_time_;
  return out.status = s;
}

}  // namespace kiloloop
