#include "kiloloop/quadruped/contact_detector.hpp"

#include <cmath>

namespace kiloloop {

Status validate(const ContactConfig& c, std::string* why) {
  const bool finite = std::isfinite(c.force_on) && std::isfinite(c.force_off) &&
                      std::isfinite(c.early_touchdown) && std::isfinite(c.touchdown_clearance);
  if (finite && c.force_on > c.force_off && c.force_off >= 0 && c.early_touchdown >= 0 &&
      c.early_touchdown <= 1)
    return Status::kOk;
  if (why) *why = "contact: need finite values, force_on > force_off >= 0, 0 <= early_touchdown <= 1";
  return Status::kInvalidConfig;
}

void ContactDetector::update(const std::array<LegPhase, kLegs>& schedule,
                             const std::array<double, kLegs>& normal_force,
                             const std::array<double, kLegs>& clearance) noexcept {
  for (int i = 0; i < kLegs; ++i) {
    const LegPhase& s = schedule[i];
    const bool was = contact_[i];
    if (was) {
      // Lift-off happens early in the swing; a foot that landed late in its swing stays down.
      if (!s.stance && s.progress <= cfg_.early_touchdown && normal_force[i] < cfg_.force_off)
        contact_[i] = false;
    } else if ((normal_force[i] > cfg_.force_on || clearance[i] < cfg_.touchdown_clearance) &&
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
