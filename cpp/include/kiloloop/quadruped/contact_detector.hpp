#pragma once
// Contact detection with hysteresis: a leg's contact flag follows its estimated normal force,
// switching on above force_on and off below force_off (force_on > force_off), gated by the gait
// phase so that a loaded swing leg cannot be mistaken for a touch-down and a stance leg is not
// dropped by one noisy sample. The schedule proposes, the force estimate decides:
//   off -> on : (force > force_on, or the foot is kinematically on the ground: its clearance above
//               the estimated ground plane is below touchdown_clearance), and the leg is
//               scheduled in stance or late in its swing;
//   on  -> off: force < force_off, and the leg is early in its scheduled swing (a foot that
//               landed late in its swing stays down: it is an early touch-down, not a lift-off).
// Why the clearance test: the force is estimated from the commanded torque, and a landing swing
// leg commands little force until its PD error builds up (measured: ~75 ms after the foot
// physically lands, with a 10 ms motor delay). Kinematics sees the landing at once.
#include <array>
#include <string>

#include "kiloloop/quadruped/gait_scheduler.hpp"

namespace kiloloop {

struct ContactConfig {
  double force_on = 25.0;          // [N] estimated normal force to declare touch-down
  double force_off = 10.0;         // [N] estimated normal force to declare lift-off
  double early_touchdown = 0.5;    // swing progress after which a touch-down is accepted
  double touchdown_clearance = 0.005;  // [m] foot clearance that counts as landed (<= 0: off)
};

// Finite; force_on > force_off >= 0; early_touchdown in [0, 1]; the reason in *why.
Status validate(const ContactConfig& config, std::string* why);

class ContactDetector {
 public:
  static constexpr int kLegs = GaitScheduler::kLegs;
  Status configure(const ContactConfig& config, std::string* why) {
    const Status s = validate(config, why);
    if (failed(s)) return s;
    cfg_ = config;
    contact_.fill(true);
    return Status::kOk;
  }
  // normal_force: estimated ground reaction along the ground normal [N], one per leg;
  // clearance: foot distance above the estimated ground plane [m], one per leg.
  void update(const std::array<LegPhase, kLegs>& schedule, const std::array<double, kLegs>& normal_force,
              const std::array<double, kLegs>& clearance) noexcept;
  bool contact(int leg) const { return contact_[leg]; }
  // Contact that can carry load: on the ground and not lifting off (early in a scheduled swing).
  bool support(int leg, const LegPhase& phase) const {
    return contact_[leg] && (phase.stance || phase.progress > cfg_.early_touchdown);
  }
  bool touched_down(int leg) const { return touched_down_[leg]; }  // this tick, off -> on
  int count() const;

 private:
  ContactConfig cfg_;
  std::array<bool, kLegs> contact_{true, true, true, true};
  std::array<bool, kLegs> touched_down_{};
};

}  // namespace kiloloop
