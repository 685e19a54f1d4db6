// The shared step rules (control/rules.hpp) and StatusCounters (status.hpp).
#include "kiloloop/control/rules.hpp"
#include "test_values.hpp"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "alloc_counter.hpp"

namespace kiloloop {
namespace {


TEST(Rules, ClipEffortClampsAndNeverPassesANonFiniteTorque) {
  const Eigen::Vector4d effort(10.0, 10.0, kInf, 5.0);
  Eigen::Vector4d tau(3.0, -12.0, 1e9, 5.0);
  EXPECT_EQ(clip_effort(Status::kOk, tau, effort), Status::kSaturated);
  EXPECT_EQ(tau, Eigen::Vector4d(3.0, -10.0, 1e9, 5.0));
  tau << 1.0, 2.0, 3.0, 4.0;
  EXPECT_EQ(clip_effort(Status::kReferenceClamped, tau, effort), Status::kReferenceClamped);
  // NaN (fmax/fmin would make it a limit) and inf beyond an infinite limit become 0: a failure.
  tau << kNaN, 2.0, kInf, -kInf;
  EXPECT_EQ(clip_effort(Status::kOk, tau, effort), Status::kSolverFailed);
  EXPECT_EQ(tau, Eigen::Vector4d(0.0, 2.0, 0.0, -5.0));
  // A failure already there stays the reason.
  tau << 1.0, 2.0, 3.0, 40.0;
  EXPECT_EQ(clip_effort(Status::kStaleMeasurement, tau, effort), Status::kStaleMeasurement);
  // Fixed-size and dynamic vectors alike, no allocation.
  Eigen::VectorXd dyn = Eigen::VectorXd::Constant(12, 100.0), lim = Eigen::VectorXd::Constant(12, 45.0);
  testing::AllocationScope scope;
  EXPECT_EQ(clip_effort(Status::kOk, dyn, lim), Status::kSaturated);
  EXPECT_EQ(scope.count(), 0u);
}

TEST(Rules, MeasurementAgeIsSymmetricAndNeedsFiniteTimes) {
  EXPECT_TRUE(measurement_fresh(1.0, 0.996, 0.005));
  EXPECT_TRUE(measurement_fresh(1.0, 1.004, 0.005));  // a little ahead: clock skew within bounds
  EXPECT_FALSE(measurement_fresh(1.0, 0.99, 0.005));
  EXPECT_FALSE(measurement_fresh(1.0, 1.01, 0.005));  // from the future
  EXPECT_FALSE(measurement_fresh(kNaN, 1.0, 0.005));
  EXPECT_FALSE(measurement_fresh(1.0, kInf, 0.005));
  EXPECT_FALSE(measurement_fresh(1e308, -1e308, 0.005));  // the gap overflows
}

TEST(Rules, MeasurementGateRejectsStaleAndOutOfOrderSamples) {
  MeasurementGate gate(0.005);
  EXPECT_EQ(gate.check(1.0, 0.999), Status::kOk);
  gate.accept(0.999);
  EXPECT_EQ(gate.check(1.001, 0.999), Status::kOk);  // the same sample again: a slow sensor
  EXPECT_EQ(gate.check(1.001, 0.998), Status::kStaleMeasurement);  // older than one acted on
  EXPECT_EQ(gate.check(0.9985, 0.9985), Status::kStaleMeasurement);  // time went backwards
  EXPECT_EQ(gate.check(1.1, 1.0), Status::kStaleMeasurement);
  EXPECT_EQ(gate.check(kNaN, 1.0), Status::kNonFiniteMeasurement);
  EXPECT_EQ(gate.check(1.0, -kInf), Status::kNonFiniteMeasurement);
  gate.reset();  // a new run: the order starts again
  EXPECT_EQ(gate.check(0.0, 0.0), Status::kOk);
}

TEST(Rules, BroadcastGains) {
  Eigen::VectorXd out;
  EXPECT_TRUE(broadcast_gains(Eigen::VectorXd::Constant(1, 3.0), 4, &out));
  EXPECT_EQ(out, Eigen::VectorXd::Constant(4, 3.0));
  EXPECT_TRUE(broadcast_gains(Eigen::Vector3d(1.0, 2.0, 3.0), 3, &out));
  EXPECT_EQ(out, Eigen::Vector3d(1.0, 2.0, 3.0));
  EXPECT_FALSE(broadcast_gains(Eigen::Vector2d(1.0, 2.0), 3, &out));
  EXPECT_FALSE(broadcast_gains(Eigen::VectorXd::Constant(1, -1.0), 3, &out));
  EXPECT_FALSE(broadcast_gains(Eigen::VectorXd::Constant(1, kNaN), 3, &out));
  Eigen::Vector3d fixed;  // into a fixed-size vector, no allocation
  EXPECT_TRUE(broadcast_gains(Eigen::VectorXd::Constant(1, 2.0), fixed));
  EXPECT_EQ(fixed, Eigen::Vector3d::Constant(2.0));
}

TEST(StatusCounters, CountsEveryStatusOfEveryStep) {
  StatusCounters c;
  c.record(Status::kOk);
  c.record(Status::kSaturated);
  c.record(Status::kEmergencyStop);
  c.record(Status::kNearSingularity);
  c.record(Status::kBadSize);
  c.record(Status::kBadSize);
  c.record(static_cast<Status>(99));  // outside the enum: a tick, no bucket
  EXPECT_EQ(c.ticks, 7u);
  EXPECT_EQ(c.count(Status::kBadSize), 2u);
  EXPECT_EQ(c.count(Status::kEmergencyStop), 1u);
  EXPECT_EQ(c.count(Status::kNearSingularity), 1u);
  EXPECT_EQ(c.failures(), 3u);
  EXPECT_EQ(c.degraded(), 2u);
  c.reset();
  EXPECT_EQ(c.ticks, 0u);
  EXPECT_EQ(c.count(Status::kBadSize), 0u);
  for (int code = kMinStatus; code <= kMaxStatus; ++code)
    EXPECT_STRNE(to_string(static_cast<Status>(code)), "unknown") << code;
}

}  // namespace
}  // namespace kiloloop
