#include "sil/native_loop.hpp"

#include "sil/mujoco_api.hpp"

#include <algorithm>
#include <cmath>
#include <exception>

namespace kiloloop::sil {

namespace {
int probe_width(const mjModel* m, const Probe& p, std::vector<int>* shape, std::string* why) {
  using S = Probe::Source;
  auto in_range = [&](int n) {
    for (int i : p.index)
      if (i < 0 || i >= n) return false;
    return true;
  };
  switch (p.source) {
    case S::kSensor: *shape = {static_cast<int>(p.index.size())}; if (in_range(m->nsensordata)) return shape->at(0); break;
    case S::kQpos: *shape = {static_cast<int>(p.index.size())}; if (in_range(m->nq)) return shape->at(0); break;
    case S::kQvel: *shape = {static_cast<int>(p.index.size())}; if (in_range(m->nv)) return shape->at(0); break;
    case S::kSitePos: *shape = {3}; if (p.index.size() == 1 && in_range(m->nsite)) return 3; break;
    case S::kSiteMat: *shape = {3, 3}; if (p.index.size() == 1 && in_range(m->nsite)) return 9; break;
    case S::kBodyPos: *shape = {3}; if (p.index.size() == 1 && in_range(m->nbody)) return 3; break;
    case S::kBodyQuat: *shape = {4}; if (p.index.size() == 1 && in_range(m->nbody)) return 4; break;
    case S::kBodyMat: *shape = {3, 3}; if (p.index.size() == 1 && in_range(m->nbody)) return 9; break;
    case S::kSubtreeCom: *shape = {3}; if (p.index.size() == 1 && in_range(m->nbody)) return 3; break;
    case S::kActuatorForce: *shape = {static_cast<int>(p.index.size())}; if (in_range(m->nu)) return shape->at(0); break;
    case S::kBodiesPos:
    case S::kContactForce:
      *shape = {static_cast<int>(p.index.size()), 3};
      if (!p.index.empty() && in_range(m->nbody)) return 3 * shape->at(0);
      break;
    case S::kSitesPos:
      *shape = {static_cast<int>(p.index.size()), 3};
      if (!p.index.empty() && in_range(m->nsite)) return 3 * shape->at(0);
      break;
    case S::kContactCount: *shape = {}; if (!p.index.empty() && in_range(m->ngeom)) return 1; break;
    case S::kGeomDistance: *shape = {}; if (p.index.size() >= 2 && in_range(m->ngeom)) return 1; break;
  }
  *why = "probe " + p.name + ": index out of range for this model";
  return -1;
}
// Where each logged element of probe p is read, in log order: the data's arrays (they do not
// move while the data lives), the probe's contact-force accumulator or its computed value.
void probe_sources(const mjData* d, const Probe& p, const ContactForces& contact, const double* value,
                   std::vector<const double*>* out) {
  using S = Probe::Source;
  const int i0 = p.index.empty() ? 0 : p.index[0];
  auto span = [&](const double* first, int n) {
    for (int j = 0; j < n; ++j) out->push_back(first + j);
  };
  switch (p.source) {
    case S::kSensor: for (int i : p.index) out->push_back(d->sensordata + i); break;
    case S::kQpos: for (int i : p.index) out->push_back(d->qpos + i); break;
    case S::kQvel: for (int i : p.index) out->push_back(d->qvel + i); break;
    case S::kSitePos: span(d->site_xpos + 3 * i0, 3); break;
    case S::kSiteMat: span(d->site_xmat + 9 * i0, 9); break;
    case S::kBodyPos: span(d->xpos + 3 * i0, 3); break;
    case S::kBodyQuat: span(d->xquat + 4 * i0, 4); break;
    case S::kBodyMat: span(d->xmat + 9 * i0, 9); break;
    case S::kSubtreeCom: span(d->subtree_com + 3 * i0, 3); break;
    case S::kActuatorForce: for (int i : p.index) out->push_back(d->actuator_force + i); break;
    case S::kBodiesPos: for (int b : p.index) span(d->xpos + 3 * b, 3); break;
    case S::kSitesPos: for (int s : p.index) span(d->site_xpos + 3 * s, 3); break;
    case S::kContactForce: span(contact.forces().data(), static_cast<int>(contact.forces().size())); break;
    case S::kContactCount:
    case S::kGeomDistance: out->push_back(value); break;
  }
}

// Contacts of the data (d->ncon) with geom1 or geom2 among geoms, each counted once.
int contacts_involving(const mjData* d, const std::vector<int>& geoms) noexcept {
  int n = 0;
  for (int i = 0; i < d->ncon; ++i) {
    const mjContact& c = d->contact[i];
    if (std::find(geoms.begin(), geoms.end(), c.geom[0]) != geoms.end() ||
        std::find(geoms.begin(), geoms.end(), c.geom[1]) != geoms.end())
      ++n;
  }
  return n;
}

// Smallest signed distance [m] from geoms[0] to geoms[1..] (MuJoCo's narrow phase on the data's
// current geom poses), at most distmax; the minimum taken in the order given.
double min_geom_distance(const mjModel* m, mjData* d, const std::vector<int>& geoms, double distmax) noexcept {
  const MujocoApi& mj = mujoco_api();
  double best = 0.0;
  for (size_t i = 1; i < geoms.size(); ++i) {
    double fromto[6];  // [m] unused; given as arm_scene.min_distance gives it
    const double dist = mj.geom_distance(m, d, geoms[0], geoms[i], distmax, fromto);
    best = i == 1 ? dist : std::min(best, dist);
  }
  return best;
}
}  // namespace

bool Rollout::configure(const mjModel* model, mjData* data, std::shared_ptr<Adapter> adapter,
                        RolloutConfig config, std::string* why) {
  if (!model || !data || !adapter) {
    *why = "rollout: model, data and adapter are required";
    return false;
  }
  if (!mujoco_api_loaded()) {
    *why = "rollout: libmujoco not resolved (kiloloop.sil.native loads it on import)";
    return false;
  }
  if (!(config.control_dt > 0.0) || config.ticks < 0) {
    *why = "rollout: expected control_dt > 0 and ticks >= 0";
    return false;
  }
  // Whole physics steps per control period, as sil/timing.py substeps() (which refuses others).
  const double ts = model->opt.timestep;
  const long n = std::lround(config.control_dt / ts);
  if (n < 1 || std::fabs(static_cast<double>(n) * ts - config.control_dt) > 1e-12) {
    *why = "rollout: control_dt is not a multiple of the physics timestep";
    return false;
  }
  if (static_cast<int>(config.measurement.size()) != adapter->measurement_size() ||
      static_cast<int>(config.actuators.size()) != adapter->command_size()) {
    *why = "rollout: measurement/actuator address counts do not match the adapter (" +
           std::to_string(adapter->measurement_size()) + ", " + std::to_string(adapter->command_size()) + ")";
    return false;
  }
  if (!config.measurement_source.empty() && config.measurement_source.size() != config.measurement.size()) {
    *why = "rollout: measurement_source: expected one entry per measurement address";
    return false;
  }
  std::vector<const double*> y_src;
  for (size_t i = 0; i < config.measurement.size(); ++i) {
    const int a = config.measurement[i];
    const int source = config.measurement_source.empty() ? 0 : config.measurement_source[i];
    const int size = source == 0 ? model->nsensordata : source == 1 ? model->nq : source == 2 ? model->nv : -1;
    if (size < 0) { *why = "rollout: measurement_source: expected 0 (sensordata), 1 (qpos) or 2 (qvel)"; return false; }
    if (a < 0 || a >= size) { *why = "rollout: measurement address out of range"; return false; }
    y_src.push_back((source == 0 ? data->sensordata : source == 1 ? data->qpos : data->qvel) + a);
  }
  for (int a : config.actuators)
    if (a < 0 || a >= model->nu) { *why = "rollout: actuator index out of range"; return false; }
  const int ny = adapter->measurement_size(), nu = adapter->command_size();
  if (!sensor_.configure(config.sensor, ny, why)) return false;
  for (const auto& stage : config.sensor_stages)
    if (!stage || !stage->configure(ny, why)) {
      if (!stage) *why = "rollout: null sensor stage";
      return false;
    }
  config.motor.dt = config.control_dt;
  if (!motor_.configure(config.motor, nu, why)) return false;
  delay_.configure(ny, config.delay_ticks);
  force_bodies_.clear();
  for (const auto& e : config.events) {
    if (!std::isfinite(e.time)) { *why = "event: non-finite time"; return false; }
    if (e.kind == EventKind::kForce) {
      const int body = e.payload.size() == 8 || e.payload.size() == 9 ? static_cast<int>(e.payload[0]) : -1;
      if (body < 1 || body >= model->nbody || !(e.payload[7] >= 0.0)) {
        *why = "force event: expected {body id (1..nbody-1), fx, fy, fz, tx, ty, tz, duration >= 0[, at subtree CoM]}";
        return false;
      }
      if (std::find(force_bodies_.begin(), force_bodies_.end(), body) == force_bodies_.end())
        force_bodies_.push_back(body);
    }
    if (e.kind == EventKind::kForce && e.payload.size() == 9 && e.payload[8] != 0.0 && e.payload[8] != 1.0) {
      *why = "force event: the 9th entry is 0 (at the body's CoM) or 1 (at its subtree CoM)";
      return false;
    }
    if (e.kind == EventKind::kGain) {
      const int act = e.payload.size() == 2 ? static_cast<int>(e.payload[0]) : -1;
      if (act < 0 || act >= model->nu || !std::isfinite(e.payload[1])) {
        *why = "gain event: expected {actuator id (0..nu-1), finite gain}";
        return false;
      }
    }
  }
  // Events in time order; ties keep their given order.
  std::stable_sort(config.events.begin(), config.events.end(),
                   [](const Event& a, const Event& b) { return a.time < b.time; });

  log_ = LogBuffer();
  ch_t_ = log_.declare("t", {});
  ch_probe_.clear();
  contact_forces_.assign(config.probes.size(), ContactForces());
  for (size_t i = 0; i < config.probes.size(); ++i) {
    const Probe& p = config.probes[i];
    std::vector<int> shape;
    const int width = probe_width(model, p, &shape, why);
    if (width < 0) return false;
    if (p.source == Probe::Source::kContactForce && !contact_forces_[i].configure(model, p.index, why))
      return false;
    ch_probe_.push_back(log_.declare(p.name, shape));
    if (static_cast<int>(i) == config.stop_probe && (config.stop_element < 0 || config.stop_element >= width)) {
      *why = "rollout: stop element out of range for probe " + p.name;
      return false;
    }
  }
  if (config.stop_probe >= static_cast<int>(config.probes.size())) {
    *why = "rollout: stop probe out of range";
    return false;
  }
  for (const auto& dist : config.disturbances) {
    if (!dist) { *why = "rollout: null disturbance"; return false; }
    if (!dist->configure(model, log_, why)) return false;
    if (std::find(force_bodies_.begin(), force_bodies_.end(), dist->body()) == force_bodies_.end())
      force_bodies_.push_back(dist->body());
  }
  adapter->declare(log_);
  log_.allocate(config.ticks);
  io_bytes_ = IoRecordBytes();
  io_.clear();
  probe_src_.clear();
  probe_end_.clear();
  probe_values_.assign(config.probes.size(), 0.0);  // never resized again: probe_src_ points in
  computed_probes_.clear();
  for (size_t i = 0; i < config.probes.size(); ++i) {
    const Probe::Source source = config.probes[i].source;
    if (source == Probe::Source::kContactCount || source == Probe::Source::kGeomDistance)
      computed_probes_.push_back(static_cast<int>(i));
    probe_sources(data, config.probes[i], contact_forces_[i], &probe_values_[i], &probe_src_);
    probe_end_.push_back(probe_src_.size());
  }

  m_ = model;
  d_ = data;
  adapter_ = std::move(adapter);
  config_ = std::move(config);
  substeps_ = static_cast<int>(n);
  y_src_ = std::move(y_src);
  wrenches_.assign(6 * config_.disturbances.size(), 0.0);
  y_raw_.assign(ny, 0.0);
  y_.assign(ny, 0.0);
  u_.assign(nu, 0.0);
  u_applied_.assign(nu, 0.0);
  next_event_ = 0;
  push_steps_.assign(config_.events.size(), 0);
  k_ = 0;
  result_ = RolloutResult();
  result_.ok = true;
  return true;
}

void Rollout::fire_events(double t) noexcept {
  while (next_event_ < config_.events.size() && t >= config_.events[next_event_].time) {
    const Event& e = config_.events[next_event_];
    if (e.kind == EventKind::kForce)  // whole physics steps, half up (FloatingBasePlant.apply_push)
      push_steps_[next_event_] = static_cast<int>(std::floor(e.payload[7] / m_->opt.timestep + 0.5 + 1e-9));
    else if (e.kind == EventKind::kGain)  // the caller's model: writable (a Python MjModel)
      const_cast<mjModel*>(m_)->actuator_gainprm[mjNGAIN * static_cast<int>(e.payload[0])] = e.payload[1];
    else
      adapter_->on_event(e);
    ++next_event_;
  }
}

void Rollout::physics_step(bool last) noexcept {
  if (!force_bodies_.empty()) {
    for (int b : force_bodies_) std::fill(d_->xfrc_applied + 6 * b, d_->xfrc_applied + 6 * b + 6, 0.0);
    for (size_t i = 0; i < next_event_; ++i) {
      if (push_steps_[i] <= 0) continue;
      const Event& e = config_.events[i];
      const int b = static_cast<int>(e.payload[0]);
      double* f = d_->xfrc_applied + 6 * b;
      for (int j = 0; j < 6; ++j) f[j] += e.payload[1 + j];
      if (e.payload.size() == 9 && e.payload[8] == 1.0) {  // at the subtree CoM
        double torque[3];
        torque_at(d_->subtree_com + 3 * b, d_->xipos + 3 * b, &e.payload[1], torque);
        for (int j = 0; j < 3; ++j) f[3 + j] += torque[j];
      }
      --push_steps_[i];
    }
    for (size_t i = 0; i < config_.disturbances.size(); ++i) {
      double* f = d_->xfrc_applied + 6 * config_.disturbances[i]->body();
      for (int j = 0; j < 6; ++j) f[j] += wrenches_[6 * i + j];
    }
  }
  const MujocoApi& mj = mujoco_api();
  mj.step2(m_, d_);
  // Contacts and constraint forces agree only here: mj_step1 re-detects the contacts for the new
  // positions, whose forces the next mj_step2 solves (sil/floating_plant.py).
  if (last)
    for (size_t p = 0; p < config_.probes.size(); ++p)
      if (config_.probes[p].source == Probe::Source::kContactForce) contact_forces_[p].update(m_, d_);
  mj.step1(m_, d_);
}

bool Rollout::stop_due(int k) noexcept {
  if (config_.stop_nonfinite)
    for (int i = 0; i < m_->nq; ++i)
      if (!std::isfinite(d_->qpos[i])) {
        result_.diverged = true;
        return true;
      }
  if (config_.stop_probe < 0) return false;
  return log_.row(ch_probe_[config_.stop_probe], k)[config_.stop_element] < config_.stop_below;
}

void Rollout::compute_probes() noexcept {
  // The probes that are a function of the state rather than one of its arrays, on the state the
  // tick starts from (as the other probes); only those, resolved at configure (most runs: none).
  for (int p : computed_probes_) {
    const Probe& probe = config_.probes[p];
    if (probe.source == Probe::Source::kContactCount)
      probe_values_[p] = contacts_involving(d_, probe.index);
    else if (probe.source == Probe::Source::kGeomDistance)
      probe_values_[p] = min_geom_distance(m_, d_, probe.index, Probe::kGeomDistanceMax);
  }
}

void Rollout::tick(int k) {
  const double t = k * config_.control_dt;  // no accumulated sum
  const int ny = static_cast<int>(y_raw_.size()), nu = static_cast<int>(u_.size());
  for (int i = 0; i < ny; ++i) y_raw_[i] = *y_src_[i];
  sensor_.apply(y_raw_.data(), y_.data());
  for (const auto& stage : config_.sensor_stages) stage->apply(t, y_.data());
  double stamp = t;
  const double* y = nullptr;
  delay_.push(t, y_.data(), &stamp, &y);

  *log_.row(ch_t_, k) = t;
  compute_probes();
  // Ground-truth probes: element by element from the sources configure resolved (one flat
  // pointer list rather than a switch over each probe's index vector).
  for (size_t p = 0, j = 0; p < probe_end_.size(); ++p) {
    double* row = log_.row(ch_probe_[p], k);
    for (const size_t end = probe_end_[p]; j < end; ++j) *row++ = *probe_src_[j];
  }

  fire_events(t);
  for (size_t i = 0; i < config_.disturbances.size(); ++i)
    config_.disturbances[i]->update(t, m_, d_, wrenches_.data() + 6 * i, log_, k);
  adapter_->step(t, stamp, y, u_.data(), log_, k);
  if (!io_.empty()) adapter_->write_io_record(io_bytes_, io_.data() + static_cast<size_t>(k) * io_bytes_.total());
  motor_.push(u_.data(), u_applied_.data());
  for (int i = 0; i < nu; ++i) d_->ctrl[config_.actuators[i]] = u_applied_[i];
  for (int s = 0; s < substeps_; ++s) physics_step(s == substeps_ - 1);
}

bool Rollout::record_io(std::string* why) {
  if (!adapter_ || k_ != 0) {
    *why = "rollout: record_io before the first tick of a configured rollout";
    return false;
  }
  io_bytes_ = adapter_->io_record_bytes();
  if (io_bytes_.total() == 0) {
    *why = "rollout: record_io: this adapter's controller has no back-to-back record";
    return false;
  }
  io_.assign(static_cast<size_t>(config_.ticks) * io_bytes_.total(), 0);
  return true;
}

const RolloutResult& Rollout::run() noexcept { return advance(config_.ticks); }

const RolloutResult& Rollout::advance(int n) noexcept {
  if (!m_ || !adapter_) {
    result_.ok = false;
    result_.error = "rollout: not configured";
    return result_;
  }
  if (finished()) return result_;
  int warnings0 = 0;
  for (int i = 0; i < mjNWARNING; ++i) warnings0 += d_->warning[i].number;
  try {
    if (k_ == 0)  // the state the caller set (mj_forward done): its contact forces, as the plant's reset
      for (size_t p = 0; p < config_.probes.size(); ++p)
        if (config_.probes[p].source == Probe::Source::kContactForce) contact_forces_[p].update(m_, d_);
    const int end = std::min(config_.ticks, k_ + std::max(n, 0));
    while (k_ < end) {
      tick(k_);
      result_.ticks = ++k_;
      if (stop_due(k_ - 1)) {
        result_.stopped = true;
        break;
      }
    }
  } catch (const std::exception& e) {  // MuJoCo's Python error hook throws on mju_error
    result_.ok = false;
    result_.error = e.what();
  } catch (...) {
    result_.ok = false;
    result_.error = "unknown error in the native loop";
  }
  int warnings = 0;
  for (int i = 0; i < mjNWARNING; ++i) warnings += d_->warning[i].number;
  result_.warnings += warnings - warnings0;
  return result_;
}

void step_adapter(Adapter& adapter, const double* y, int n, double dt) {
  LogBuffer log;
  adapter.declare(log);
  log.allocate(n);
  std::vector<double> u(adapter.command_size());
  for (int k = 0; k < n; ++k) adapter.step(k * dt, k * dt, y, u.data(), log, k);
}

void step_raw(const mjModel* model, mjData* data, int n, const double* ctrl, const int* actuators,
              int k) noexcept {
  const MujocoApi& mj = mujoco_api();
  if (!mj.step) return;
  for (int i = 0; i < n; ++i) {
    if (ctrl)
      for (int j = 0; j < k; ++j) data->ctrl[actuators[j]] = ctrl[static_cast<size_t>(i) * k + j];
    mj.step(model, data);
  }
}

}  // namespace kiloloop::sil
