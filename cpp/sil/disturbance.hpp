#pragma once
// A state-dependent disturbance of the native loop (wind drag, ...): once per control tick, before
// the physics steps, it computes a world-frame wrench on one body from the current state; the
// loop applies it through MuJoCo's xfrc_applied for that tick's physics steps, summed with any
// force events on the same body (events.hpp). Each rollout owns its own (state, random stream).
// Allocation only in configure.
#include <string>

#include <mujoco/mujoco.h>

#include "sil/log_buffer.hpp"

namespace kiloloop::sil {

class Disturbance {
 public:
  virtual ~Disturbance() = default;
  // Configure time: checks the model, declares the channels it logs; false with why.
  virtual bool configure(const mjModel* m, LogBuffer& log, std::string* why) = 0;
  virtual int body() const = 0;
  // Tick k at time t [s]: writes wrench (fx, fy, fz, tx, ty, tz) [N, N m] (world frame, about the
  // body's centre of mass, as xfrc_applied) and the log row k.
  virtual void update(double t, const mjModel* m, const mjData* d, double* wrench, LogBuffer& log,
                      int k) noexcept = 0;
};

// The torque about the body's centre of mass (xipos) of a force f [N] applied at point [m]:
// (point - xipos) x f, in the operation order of numpy.cross (sil/aerial_plant.apply_force).
inline void torque_at(const double* point, const double* xipos, const double* f, double* torque) noexcept {
  const double r[3] = {point[0] - xipos[0], point[1] - xipos[1], point[2] - xipos[2]};
  torque[0] = r[1] * f[2] - r[2] * f[1];
  torque[1] = r[2] * f[0] - r[0] * f[2];
  torque[2] = r[0] * f[1] - r[1] * f[0];
}

}  // namespace kiloloop::sil
