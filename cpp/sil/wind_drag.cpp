#include "sil/wind_drag.hpp"

#include <algorithm>
#include <cmath>

namespace kiloloop::sil {

bool WindDrag::configure(const mjModel* m, LogBuffer& log, std::string* why) {
  const WindDragConfig& c = c_;
  bool finite = std::isfinite(c.ramp) && std::isfinite(c.gust_sigma) && std::isfinite(c.gust_tau) &&
                std::isfinite(c.drag_area) && std::isfinite(c.air_density) && std::isfinite(c.vertical_scale);
  for (double s : c.steady) finite = finite && std::isfinite(s);
  if (c.body < 1 || c.body >= m->nbody || c.velocity_adr < 0 || c.velocity_adr + 3 > m->nv || !finite ||
      !(c.ramp > 0.0) || !(c.gust_tau > 0.0) || c.gust_sigma < 0.0 || c.drag_area < 0.0 || !(c.dt > 0.0)) {
    *why = "wind: expected a body id, its linear-velocity address, finite settings, ramp > 0, gust_tau > 0, "
           "gust_sigma >= 0, drag_area >= 0, dt > 0";
    return false;
  }
  a_ = std::exp(-c.dt / c.gust_tau);
  b_ = c.gust_sigma * std::sqrt(1 - a_ * a_);
  ch_wind_ = log.declare("wind", {3});
  ch_force_ = log.declare("wind_force", {3});
  return true;
}

void WindDrag::compute(double t, const mjData* d, double* wrench) noexcept {
  for (double& g : gust_) g = a_ * g + b_ * rng_.normal();
  gust_[2] *= c_.vertical_scale;
  const double ramp = std::min(t / c_.ramp, 1.0);
  const double* v = d->qvel + c_.velocity_adr;
  double rel[3];
  for (int i = 0; i < 3; ++i) {
    w_[i] = ramp * c_.steady[i] + gust_[i];
    rel[i] = w_[i] - v[i];
  }
  const double speed = std::sqrt(rel[0] * rel[0] + rel[1] * rel[1] + rel[2] * rel[2]);
  for (int i = 0; i < 3; ++i) f_[i] = 0.5 * c_.air_density * c_.drag_area * speed * rel[i];
  wrench[0] = f_[0];
  wrench[1] = f_[1];
  wrench[2] = f_[2];
  torque_at(d->subtree_com + 3 * c_.body, d->xipos + 3 * c_.body, f_, wrench + 3);
}

void WindDrag::update(double t, const mjModel* /*m*/, const mjData* d, double* wrench, LogBuffer& log,
                      int k) noexcept {
  compute(t, d, wrench);
  std::copy(w_, w_ + 3, log.row(ch_wind_, k));
  std::copy(f_, f_ + 3, log.row(ch_force_, k));
}

void WindDrag::apply(double t, const mjModel* /*m*/, mjData* d) noexcept {
  compute(t, d, d->xfrc_applied + 6 * c_.body);
}

}  // namespace kiloloop::sil
