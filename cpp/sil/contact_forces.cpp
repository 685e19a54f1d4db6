#include "sil/contact_forces.hpp"

#include <algorithm>

#include "sil/mujoco_api.hpp"

namespace kiloloop::sil {

bool ContactForces::configure(const mjModel* m, const std::vector<int>& bodies, std::string* why) {
  geom_slot_.assign(m->ngeom, -1);
  for (size_t k = 0; k < bodies.size(); ++k) {
    if (bodies[k] < 0 || bodies[k] >= m->nbody) {
      *why = "contact force probe: body id out of range";
      return false;
    }
    for (int g = 0; g < m->ngeom; ++g)
      if (m->geom_bodyid[g] == bodies[k]) geom_slot_[g] = static_cast<int>(k);
  }
  forces_.assign(3 * bodies.size(), 0.0);
  return true;
}

void ContactForces::update(const mjModel* m, const mjData* d) noexcept {
  std::fill(forces_.begin(), forces_.end(), 0.0);
  const auto contact_force = mujoco_api().contact_force;
  for (int i = 0; i < d->ncon; ++i) {
    const mjContact& c = d->contact[i];
    const int k1 = c.geom[0] >= 0 ? geom_slot_[c.geom[0]] : -1;
    const int k2 = c.geom[1] >= 0 ? geom_slot_[c.geom[1]] : -1;
    if (k1 < 0 && k2 < 0) continue;
    mjtNum f6[6];
    contact_force(m, d, i, f6);
    // f6[:3]: force of geom 0 on geom 1 in the contact frame, whose rows are its axes; world =
    // frame^T f, summed in the order numpy's frame.reshape(3, 3).T @ f6[:3] does.
    double f[3];
    for (int r = 0; r < 3; ++r) f[r] = c.frame[r] * f6[0] + c.frame[3 + r] * f6[1] + c.frame[6 + r] * f6[2];
    for (int r = 0; r < 3; ++r) {
      if (k2 >= 0) forces_[3 * k2 + r] += f[r];
      if (k1 >= 0) forces_[3 * k1 + r] -= f[r];
    }
  }
}

}  // namespace kiloloop::sil
