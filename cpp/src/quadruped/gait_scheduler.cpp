#include "kiloloop/quadruped/gait_scheduler.hpp"

#include <cmath>
#include <limits>

namespace kiloloop {
namespace {
// Phase offsets of FL, FR, RL, RR in a trot: diagonal pairs together.
constexpr double kTrotOffset[GaitScheduler::kLegs] = {0.0, 0.5, 0.5, 0.0};
}  // namespace

Status validate(const GaitConfig& config, std::string* why) {
  if (std::isfinite(config.period) && config.period > 0.0 && config.duty > 0.5 && config.duty < 1.0)
    return Status::kOk;
  if (why) *why = "gait: need period > 0, 0.5 < duty < 1";
  return Status::kInvalidConfig;
}

Status GaitScheduler::configure(const GaitConfig& config) {
  if (failed(validate(config, nullptr))) return Status::kInvalidConfig;
  cfg_ = config;
  gait_ = Gait::kStand;
  for (auto& leg : legs_) leg = LegPhase{true, 0.0, std::numeric_limits<double>::infinity()};
  return Status::kOk;
}

Gait GaitScheduler::update(double t, Gait requested) noexcept {
  if (gait_ == Gait::kStand && requested == Gait::kTrot) {
    gait_ = Gait::kTrot;
    t_start_ = t;
  }
  if (gait_ == Gait::kStand) {
    for (auto& leg : legs_) leg = LegPhase{true, 0.0, std::numeric_limits<double>::infinity()};
    return gait_;
  }
  const double cycle = (t - t_start_) / cfg_.period;
  bool all_stance = true;
  for (int i = 0; i < kLegs; ++i) {
    double phase = cycle + kTrotOffset[i];
    phase -= std::floor(phase);
    LegPhase& leg = legs_[i];
    leg.stance = phase < cfg_.duty;
    if (leg.stance) {
      leg.progress = phase / cfg_.duty;
      leg.remaining = (cfg_.duty - phase) * cfg_.period;
    } else {
      leg.progress = (phase - cfg_.duty) / (1.0 - cfg_.duty);
      leg.remaining = (1.0 - phase) * cfg_.period;
    }
    all_stance &= leg.stance;
  }
  if (requested == Gait::kStand && all_stance) {
    gait_ = Gait::kStand;
    for (auto& leg : legs_) leg = LegPhase{true, 0.0, std::numeric_limits<double>::infinity()};
  }
  return gait_;
}

}  // namespace kiloloop
