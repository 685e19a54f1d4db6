#pragma once
// Wind on a flying body (the aerial-wind scenario's model, seeded in C++): quadratic drag
//   F = 1/2 rho CdA |w - v| (w - v)   [N], world frame, at the vehicle's centre of mass
// (the body's subtree CoM), v the body's free-joint linear velocity (world), and the wind
//   w = min(t / ramp, 1) steady + g,  g_k = a g_k-1 + sigma sqrt(1 - a^2) N(0, 1) per axis,
//   a = exp(-dt / tau)  (exact discretization of a first-order, Dryden-like gust), then
//   g_z scaled by vertical_scale each tick (weaker vertical gusts near the ground).
// Logs "wind" (3) [m/s] and "wind_force" (3) [N].
#include <string>

#include "sil/disturbance.hpp"
#include "sil/rng.hpp"

namespace kiloloop::sil {

struct WindDragConfig {
  int body = -1;                 // MuJoCo body id (with a free joint)
  int velocity_adr = -1;         // qvel address of its linear velocity (world frame)
  double steady[3] = {0, 0, 0};  // [m/s] steady wind, world
  double ramp = 1.0;             // [s] the steady part ramps in linearly over this
  double gust_sigma = 0.0;       // [m/s] gust standard deviation per axis
  double gust_tau = 0.5;         // [s] gust correlation time
  double vertical_scale = 0.5;   // applied to the vertical gust every tick
  double drag_area = 0.05;       // [m^2] CdA
  double air_density = 1.225;    // [kg/m^3]
  double dt = 0.001;             // [s] control period
  unsigned long long seed = 0;   // gust stream
};

class WindDrag final : public Disturbance {
 public:
  explicit WindDrag(const WindDragConfig& config) : c_(config), rng_(config.seed) {}
  bool configure(const mjModel* m, LogBuffer& log, std::string* why) override;
  int body() const override { return c_.body; }
  void update(double t, const mjModel* m, const mjData* d, double* wrench, LogBuffer& log, int k) noexcept override;
  // The last update's wind [m/s] and force [N] (update() logs them).
  const double* wind() const { return w_; }
  const double* force() const { return f_; }
  // Computes the tick's wind and force and writes them into d->xfrc_applied of the body (a
  // test's entry; the native loop goes through update()).
  void apply(double t, const mjModel* m, mjData* d) noexcept;

 private:
  void compute(double t, const mjData* d, double* wrench) noexcept;

  WindDragConfig c_;
  Rng rng_;
  double gust_[3] = {0, 0, 0}, w_[3] = {0, 0, 0}, f_[3] = {0, 0, 0};
  double a_ = 0.0, b_ = 0.0;  // gust recursion coefficients
  int ch_wind_ = -1, ch_force_ = -1;
};

}  // namespace kiloloop::sil
