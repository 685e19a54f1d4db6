#pragma once
// Ground-truth contact force on each of a set of bodies (a quadruped's feet): the force exerted on
// the body by whatever it touches, world frame [N], summed over its contacts, as the Python
// FloatingBasePlant.foot_contact_forces computes it. Valid between mj_step2 and mj_step1 (the
// contacts then match the constraint forces just solved) or after mj_forward.
#include <string>
#include <vector>

#include <mujoco/mujoco.h>

namespace kiloloop::sil {

class ContactForces {
 public:
  // bodies: MuJoCo body ids; false with why when one is out of range.
  bool configure(const mjModel* m, const std::vector<int>& bodies, std::string* why);
  // Recomputes the forces from d's contacts (needs mj_contactForce resolved).
  void update(const mjModel* m, const mjData* d) noexcept;
  const std::vector<double>& forces() const { return forces_; }  // (bodies x 3), row-major

 private:
  std::vector<int> geom_slot_;  // geom id -> index in bodies, or -1
  std::vector<double> forces_;
};

}  // namespace kiloloop::sil
