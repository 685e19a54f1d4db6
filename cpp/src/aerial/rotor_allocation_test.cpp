// Rotor allocation: exact when unsaturated, flight-stack priorities when saturated (roll/pitch
// kept, yaw given up first), always within the limits, allocation-free.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "alloc_counter.hpp"
#include "kiloloop/aerial/rotor_allocation.hpp"

namespace kiloloop {
namespace {

RotorAllocation make(const RotorAllocationConfig& c = {}) {
  RotorAllocation a;
  std::string why;
  EXPECT_EQ(RotorAllocation::configure(c, &a, &why), Status::kOk) << why;
  return a;
}

TEST(RotorAllocation, ReproducesTheWrenchExactlyWhenUnsaturated) {
  RotorAllocation alloc = make();
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> T(12.0, 20.0), tau(-0.3, 0.3), yaw(-0.05, 0.05);
  for (int k = 0; k < 1000; ++k) {
    const Eigen::Vector4d w(T(rng), tau(rng), tau(rng), yaw(rng));
    Eigen::Vector4d f, achieved;
    ASSERT_EQ(alloc.allocate(w, &f, &achieved), Status::kOk) << w.transpose();
    EXPECT_LT((alloc.mixer() * f - w).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_LT((achieved - w).cwiseAbs().maxCoeff(), 1e-12);
  }
}

TEST(RotorAllocation, GivesUpYawBeforeRollAndPitch) {
  RotorAllocation alloc = make();
  // Near full thrust with a large yaw demand: roll/pitch must survive, yaw is cut.
  const Eigen::Vector4d w(28.0, 0.4, -0.3, 0.2);
  Eigen::Vector4d f, achieved;
  EXPECT_EQ(alloc.allocate(w, &f, &achieved), Status::kSaturated);
  EXPECT_TRUE((f.array() >= 0.0).all() && (f.array() <= 8.0).all()) << f.transpose();
  EXPECT_NEAR(achieved[1], w[1], 1e-12);
  EXPECT_NEAR(achieved[2], w[2], 1e-12);
  EXPECT_LT(std::abs(achieved[3]), std::abs(w[3]));
  EXPECT_GE(achieved[3] * w[3], 0.0);  // same sign: reduced, not reversed
  // The yaw share is the largest that fits: some rotor sits at a limit.
  EXPECT_TRUE((f.array() == 8.0).any() || (f.array() == 0.0).any());
}

TEST(RotorAllocation, ShiftsThrustToKeepRollPitchAndScalesOnlyAsLastResort) {
  RotorAllocation alloc = make();
  Eigen::Vector4d f, achieved;
  // Low thrust, strong roll: a rotor would go negative; thrust is raised, roll kept.
  const Eigen::Vector4d w(2.0, 0.6, 0.0, 0.0);
  EXPECT_EQ(alloc.allocate(w, &f, &achieved), Status::kSaturated);
  EXPECT_NEAR(achieved[1], 0.6, 1e-12);
  EXPECT_GT(achieved[0], 2.0);
  // Roll beyond what any thrust allows: scaled, still within the limits, direction kept.
  const Eigen::Vector4d huge(16.0, 10.0, 5.0, 0.0);
  EXPECT_EQ(alloc.allocate(huge, &f, &achieved), Status::kSaturated);
  EXPECT_TRUE((f.array() >= 0.0).all() && (f.array() <= 8.0).all());
  EXPECT_NEAR(achieved[1] / achieved[2], 2.0, 1e-9);
}

TEST(RotorAllocation, RandomWrenchesStayInLimits) {
  RotorAllocation alloc = make();
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> T(-5.0, 40.0), tau(-3.0, 3.0);
  for (int k = 0; k < 5000; ++k) {
    const Eigen::Vector4d w(T(rng), tau(rng), tau(rng), tau(rng));
    Eigen::Vector4d f;
    const Status s = alloc.allocate(w, &f);
    EXPECT_TRUE(s == Status::kOk || s == Status::kSaturated);
    EXPECT_TRUE(f.allFinite() && (f.array() >= 0.0).all() && (f.array() <= 8.0).all());
  }
}

TEST(RotorAllocation, LagCompensationLeadsTheCommand) {
  RotorAllocationConfig c;
  c.lag_compensation = true;
  RotorAllocation alloc = make(c);
  Eigen::Vector4d f;
  alloc.allocate(Eigen::Vector4d(16.0, 0, 0, 0), &f);
  EXPECT_NEAR(f[0], 4.0, 1e-12);
  alloc.allocate(Eigen::Vector4d(16.04, 0, 0, 0), &f);  // +0.01 N per rotor in one tick
  EXPECT_NEAR(f[0], 4.01 + 0.03 / 0.001 * 0.01, 1e-9);
}

TEST(RotorAllocation, BadInputAndConfig) {
  RotorAllocation alloc = make();
  Eigen::Vector4d f;
  EXPECT_EQ(alloc.allocate(Eigen::Vector4d(std::nan(""), 0, 0, 0), &f),
            Status::kNonFiniteReference);
  EXPECT_TRUE(f.allFinite());
  RotorAllocationConfig c;
  c.spin[0] = 0.5;
  RotorAllocation a;
  std::string why;
  EXPECT_EQ(RotorAllocation::configure(c, &a, &why), Status::kInvalidConfig);
  EXPECT_NE(why.find("spin"), std::string::npos);
  c = RotorAllocationConfig{};
  c.positions.col(1) = c.positions.col(0);  // two rotors in one place: singular
  EXPECT_EQ(RotorAllocation::configure(c, &a, &why), Status::kInvalidConfig);
}

TEST(RotorAllocation, IsAllocationFree) {
  RotorAllocation alloc = make();
  Eigen::Vector4d f;
  testing::AllocationScope scope;
  for (int k = 0; k < 10000; ++k)
    alloc.allocate(Eigen::Vector4d(10.0 + 0.002 * k, 0.3, -0.2, 0.05), &f);
  EXPECT_EQ(scope.count(), 0u);
}

}  // namespace
}  // namespace kiloloop
