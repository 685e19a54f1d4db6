// Gait scheduler, swing trajectory and contact hysteresis.
#include <gtest/gtest.h>

#include "kiloloop/quadruped/contact_detector.hpp"
#include "kiloloop/quadruped/gait_scheduler.hpp"
#include "kiloloop/trajectory/swing_trajectory.hpp"

namespace kiloloop {
namespace {

TEST(GaitScheduler, TrotMovesDiagonalPairsTogetherWithTheDutyFactor) {
  GaitScheduler gait;
  ASSERT_EQ(gait.configure(GaitConfig{}), Status::kOk);
  int stance_ticks[4] = {0, 0, 0, 0};
  const int ticks = 6000;  // 10 periods of 0.6 s at 1 kHz
  for (int k = 0; k < ticks; ++k) {
    gait.update(k * 0.001, Gait::kTrot);
    const auto& legs = gait.legs();
    EXPECT_EQ(legs[0].stance, legs[3].stance);  // FL with RR
    EXPECT_EQ(legs[1].stance, legs[2].stance);  // FR with RL
    for (int i = 0; i < 4; ++i) stance_ticks[i] += legs[i].stance;
  }
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(stance_ticks[i] / double(ticks), 0.6, 0.002);
}

TEST(GaitScheduler, StartsWithAllFeetDownAndStopsOnlyWhenAllAreDown) {
  GaitScheduler gait;
  ASSERT_EQ(gait.configure(GaitConfig{}), Status::kOk);
  gait.update(1.0, Gait::kTrot);
  for (const auto& leg : gait.legs()) EXPECT_TRUE(leg.stance);
  // 0.5 s into the trot FL/RR swing (phase 0.83) while FR/RL stand: no stop yet.
  EXPECT_EQ(gait.update(1.2 + 0.3, Gait::kStand), Gait::kTrot);
  bool stopped = false;
  for (int k = 0; k < 600 && !stopped; ++k) stopped = gait.update(1.5 + k * 0.001, Gait::kStand) == Gait::kStand;
  EXPECT_TRUE(stopped);
  EXPECT_EQ(gait.configure(GaitConfig{0.6, 0.4}), Status::kInvalidConfig);
}

TEST(SwingTrajectory, SmoothAtBothEndsAndReachesTheApex) {
  const Eigen::Vector3d p0(0, 0, 0.02), p1(0.1, 0.02, 0.0);
  const double T = 0.24, h = 0.08;
  for (double s : {0.0, 1.0}) {
    const SwingSample x = sample_swing(p0, p1, h, s, T);
    EXPECT_LT((x.p - (s == 0.0 ? p0 : p1)).norm(), 1e-15);
    EXPECT_LT(x.v.norm() + x.a.norm(), 1e-12);
  }
  const SwingSample mid = sample_swing(p0, p1, h, 0.5, T);
  EXPECT_NEAR(mid.p.z(), 0.5 * (p0.z() + p1.z()) + h, 1e-12);
  // Jerk also vanishes at lift-off: S7'''(0) = 0.
  double f, df, ddf, dddf;
  smoothstep7(0.0, &f, &df, &ddf, &dddf);
  EXPECT_EQ(dddf, 0.0);
  smoothstep7(1.0, &f, &df, &ddf, &dddf);
  EXPECT_NEAR(dddf, 0.0, 1e-9);
  // Velocity is the derivative of position.
  const double s = 0.3, ds = 1e-6;
  const SwingSample a = sample_swing(p0, p1, h, s, T), b = sample_swing(p0, p1, h, s + ds, T);
  EXPECT_LT(((b.p - a.p) / (ds * T) - a.v).norm(), 1e-4);
}

TEST(ContactDetector, HysteresisAndPhaseGating) {
  ContactDetector det;
  ASSERT_EQ(det.configure(ContactConfig{}, nullptr), Status::kOk);
  std::array<LegPhase, 4> sched{};
  std::array<double, 4> force{};
  std::array<double, 4> clearance{};
  clearance.fill(0.05);  // feet well above the ground: only the force decides here
  for (auto& s : sched) s.stance = false, s.progress = 0.2;
  // Loaded leg in early swing stays in contact until the force drops below force_off.
  force.fill(20.0);
  det.update(sched, force, clearance);
  EXPECT_TRUE(det.contact(0));
  force.fill(5.0);
  det.update(sched, force, clearance);
  EXPECT_FALSE(det.contact(0));
  // Early in swing a force spike is not a touch-down; late in swing it is.
  force.fill(40.0);
  det.update(sched, force, clearance);
  EXPECT_FALSE(det.contact(0));
  for (auto& s : sched) s.progress = 0.8;
  det.update(sched, force, clearance);
  EXPECT_TRUE(det.contact(0));
  EXPECT_TRUE(det.touched_down(0));
  // Between the thresholds nothing changes (hysteresis), even when the schedule says swing.
  force.fill(15.0);
  det.update(sched, force, clearance);
  EXPECT_TRUE(det.contact(0));
  EXPECT_FALSE(det.touched_down(0));
}

TEST(ContactDetector, LandedFootCountsBeforeItsForceBuildsUp) {
  ContactDetector det;
  ASSERT_EQ(det.configure(ContactConfig{}, nullptr), Status::kOk);
  std::array<LegPhase, 4> sched{};
  std::array<double, 4> force{}, clearance{};
  for (auto& s : sched) s.stance = false, s.progress = 0.2;
  clearance.fill(0.05);
  det.update(sched, force, clearance);  // unloaded swing legs: lift-off
  ASSERT_FALSE(det.contact(0));
  // A foot at the ground early in its swing (scuffing) is not a touch-down...
  clearance.fill(0.0);
  det.update(sched, force, clearance);
  EXPECT_FALSE(det.contact(0));
  // ...late in the swing it is, with no force yet; just above the threshold it is not.
  for (auto& s : sched) s.progress = 0.9;
  clearance = {0.001, 0.0049, 0.0051, 0.02};
  det.update(sched, force, clearance);
  EXPECT_TRUE(det.contact(0));
  EXPECT_TRUE(det.contact(1));
  EXPECT_FALSE(det.contact(2));
  EXPECT_FALSE(det.contact(3));
  // A foot that landed late in its swing stays down (no chattering while unloaded)...
  clearance.fill(0.05);
  det.update(sched, force, clearance);
  EXPECT_TRUE(det.contact(0));
  EXPECT_TRUE(det.contact(1));
  // ...and leaves contact by force early in its next swing, not while in stance.
  sched[0].stance = true;
  sched[1].progress = 0.1;
  det.update(sched, force, clearance);
  EXPECT_TRUE(det.contact(0));
  EXPECT_FALSE(det.contact(1));
}

}  // namespace
}  // namespace kiloloop
