#pragma once
// Contact detection with hysteresis: a leg's contact flag follows its estimated normal force,
// switching on above force_on and off below force_off (force_on > force_off), gated by the gait
// phase so that a loaded swing leg cannot be mistaken for a touch-down and a stance leg is not
// dropped by one noisy sample. The schedule proposes, the force estimate decides:
//   off -> on : force > force_on, and the leg is scheduled in stance or late in its swing;
//   on  -> off: force < force_off, and the leg is scheduled in swing.
#include <array>

#include "kiloloop/quadruped/gait_scheduler.hpp"

namespace kiloloop {

struct ContactConfig {
  double force_on = 25.0;          // [N] estimated normal force to declare touch-down
  double force_off = 10.0;         // [N] estimated normal force to declare lift-off
  double early_touchdown = 0.5;    // swing progress after which a touch-down is accepted
};

class ContactDetector {
 public:
  static constexpr int kLegs = GaitScheduler::kLegs;
  void configure(const ContactConfig& config) { cfg_ = config; contact_.fill(true); }
  // normal_force: estimated ground reaction along the ground normal [N], one per leg.
  void update(const std::array<LegPhase, kLegs>& schedule,
              const std::array<double, kLegs>& normal_force) noexcept;
  bool contact(int leg) const { return contact_[leg]; }
  bool touched_down(int leg) const { return touched_down_[leg]; }  // this tick, off -> on
  int count() const;

 private:
  ContactConfig cfg_;
  std::array<bool, kLegs> contact_{true, true, true, true};
  std::array<bool, kLegs> touched_down_{};
};

}  // namespace kiloloop
