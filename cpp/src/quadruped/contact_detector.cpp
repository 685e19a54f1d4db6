#include "kiloloop/quadruped/contact_detector.hpp"

namespace kiloloop {

void ContactDetector::update(const std::array<LegPhase, kLegs>& schedule,
                             const std::array<double, kLegs>& normal_force) noexcept {
  for (int i = 0; i < kLegs; ++i) {
    const LegPhase& s = schedule[i];
    const bool was = contact_[i];
    if (was) {
      if (!s.stance && normal_force[i] < cfg_.force_off) contact_[i] = false;
    } else if (normal_force[i] > cfg_.force_on &&
               (s.stance || s.progress > cfg_.early_touchdown)) {
      contact_[i] = true;
    }
    touched_down_[i] = !was && contact_[i];
  }
}

int ContactDetector::count() const {
  int n = 0;
  for (bool c : contact_) n += c;
  return n;
}

}  // namespace kiloloop
