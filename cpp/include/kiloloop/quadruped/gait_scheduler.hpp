#pragma once
// Gait scheduler: which legs should be on the ground, and how far through swing or stance each
// is, as a pure function of time and the requested gait. Legs are ordered FL, FR, RL, RR.
//   stand: all legs in stance.
//   trot:  diagonal pairs (FL+RR, FR+RL) half a period apart; each leg is in stance for
//          duty * period and in swing for the rest.
// Transitions are smooth: a trot starts at phase 0 (both pairs on the ground, since duty > 0.5),
// and a stop request is honoured only at a moment when all four legs are in stance.
#include <array>
#include <string>

#include "kiloloop/status.hpp"

namespace kiloloop {

enum class Gait : int { kStand = 0, kTrot = 1 };

struct GaitConfig {
  double period = 0.6;  // [s] full gait cycle
  double duty = 0.6;    // stance fraction of the cycle (> 0.5 so a trot has 4-stance moments)
};

// period > 0 and 0.5 < duty < 1; the reason in *why.
Status validate(const GaitConfig& config, std::string* why);

struct LegPhase {
  bool stance = true;          // scheduled on the ground
  double progress = 0.0;       // [0, 1) through the current stance or swing
  double remaining = 0.0;      // [s] until the current stance or swing ends (inf when standing)
};

class GaitScheduler {
 public:
  static constexpr int kLegs = 4;
  Status configure(const GaitConfig& config);
  // Advances to time t [s] with the requested gait; returns the gait actually running.
  Gait update(double t, Gait requested) noexcept;
  const std::array<LegPhase, kLegs>& legs() const { return legs_; }
  Gait gait() const { return gait_; }
  double swing_duration() const { return (1.0 - cfg_.duty) * cfg_.period; }
  double stance_duration() const { return cfg_.duty * cfg_.period; }

 private:
  GaitConfig cfg_;
  Gait gait_ = Gait::kStand;
  double t_start_ = 0.0;  // [s] when the current trot began
  std::array<LegPhase, kLegs> legs_{};
};

}  // namespace kiloloop
