#include "sil/signal_models.hpp"

#include <algorithm>
#include <cmath>

namespace kiloloop::sil {

namespace {
bool check_vector(const std::vector<double>& v, int n, const char* name, std::string* why) {
  if (static_cast<int>(v.size()) > n) {
    *why = std::string(name) + ": expected at most " + std::to_string(n) + " entries, got " +
           std::to_string(v.size());
    return false;
  }
  for (double x : v)
    if (!std::isfinite(x) || x < 0.0) {
      *why = std::string(name) + ": expected finite values >= 0";
      return false;
    }
  return true;
}
}  // namespace

bool SensorModel::configure(const SensorModelConfig& config, int n, std::string* why) {
  if (!check_vector(config.sigma, n, "sigma", why) || !check_vector(config.quantum, n, "quantum", why))
    return false;
  n_ = n;
  // Shorter arrays cover y's first entries; the rest are zero (and draw nothing: noisy_n_).
  sigma_ = config.sigma;
  sigma_.resize(n, 0.0);
  quantum_ = config.quantum;
  quantum_.resize(n, 0.0);
  noisy_ = false;
  for (double s : sigma_) noisy_ = noisy_ || s > 0.0;
  noisy_n_ = static_cast<int>(config.sigma.size());
  quantized_index_.clear();
  for (int i = 0; i < n; ++i)
    if (quantum_[i] > 0.0) quantized_index_.push_back(i);
  quantized_ = !quantized_index_.empty();
  rng_.reseed(config.seed);
  return true;
}

void SensorModel::apply(const double* x, double* y) noexcept {
  if (!noisy_ && !quantized_) {  // an ideal sensor (no draws either): y = x
    std::copy(x, x + n_, y);
    return;
  }
  // A zero sigma still draws its sample: the stream of every element does not depend on which
  // others are noisy.
  if (noisy_) {
    for (int i = 0; i < noisy_n_; ++i) y[i] = x[i] + sigma_[i] * rng_.normal();
    std::copy(x + noisy_n_, x + n_, y + noisy_n_);
  } else {
    std::copy(x, x + n_, y);
  }
  // nearbyint in the default rounding mode rounds half to even, as numpy.round does.
  for (int i : quantized_index_) y[i] = quantum_[i] * std::nearbyint(y[i] / quantum_[i]);
}

void MeasurementDelay::configure(int n, int ticks) {
  n_ = n;
  ticks_ = ticks < 0 ? 0 : ticks;
  head_ = count_ = 0;
  times_.assign(ticks_ + 1, 0.0);
  values_.assign(static_cast<size_t>(ticks_ + 1) * n, 0.0);
}

void MeasurementDelay::push(double t, const double* x, double* stamp, const double** y) noexcept {
  if (ticks_ == 0) {  // no delay: the sample itself (the ring would hold it one tick, unread)
    *stamp = t;
    *y = x;
    return;
  }
  const int size = ticks_ + 1;
  // The ring holds the last `size` samples; head_ is the oldest.
  const int slot = (head_ + count_) % size;
  times_[slot] = t;
  for (int i = 0; i < n_; ++i) values_[static_cast<size_t>(slot) * n_ + i] = x[i];
  ++count_;
  int use = slot;  // fewer than ticks + 1 samples so far: the newest
  if (count_ > ticks_) {
    use = head_;   // the oldest, then dropped
    head_ = (head_ + 1) % size;
    --count_;
  }
  *stamp = times_[use];
  *y = values_.data() + static_cast<size_t>(use) * n_;
}

bool MotorModel::configure(const MotorModelConfig& config, int n, std::string* why) {
  if (config.delay_ticks < 0 || !(config.dt > 0.0) || !std::isfinite(config.time_constant) ||
      config.time_constant < 0.0) {
    *why = "motor model: expected delay_ticks >= 0, dt > 0 and a finite time_constant >= 0";
    return false;
  }
  if (!config.limit.empty() && static_cast<int>(config.limit.size()) != n) {
    *why = "motor model: limit: expected 0 or " + std::to_string(n) + " entries";
    return false;
  }
  for (double l : config.limit)
    if (std::isnan(l) || l < 0.0) {  // +inf: no limit on that element
      *why = "motor model: limit: expected values >= 0";
      return false;
    }
  limit_ = config.limit;
  n_ = n;
  ticks_ = config.delay_ticks;
  head_ = 0;
  hold_first_ = config.hold_first;
  primed_ = false;
  alpha_ = config.dt / (config.time_constant + config.dt);
  fifo_.assign(static_cast<size_t>(ticks_) * n, 0.0);
  state_.assign(n, 0.0);
  return true;
}

void MotorModel::push(const double* u, double* y) noexcept {
  if (hold_first_ && !primed_)  // the queue starts full of the first command (nonideal.MotorDelay "first")
    for (int d = 0; d < ticks_; ++d) std::copy(u, u + n_, fifo_.begin() + static_cast<long>(d) * n_);
  primed_ = true;
  for (int i = 0; i < n_; ++i) {
    double arriving = u[i];
    if (ticks_ > 0) {
      double& slot = fifo_[static_cast<size_t>(head_) * n_ + i];
      arriving = slot;  // sent ticks_ ticks ago (zero before the first command arrives)
      slot = u[i];
    }
    state_[i] = alpha_ == 1.0 ? arriving : state_[i] + alpha_ * (arriving - state_[i]);
    y[i] = limit_.empty() ? state_[i] : std::clamp(state_[i], -limit_[i], limit_[i]);
  }
  if (ticks_ > 0) head_ = (head_ + 1) % ticks_;
}

}  // namespace kiloloop::sil
