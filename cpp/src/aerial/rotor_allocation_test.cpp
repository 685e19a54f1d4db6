// Rotor allocation: exact when unsaturated, flight-stack priorities when saturated (roll/pitch
// kept, yaw given up first), always within the limits, allocation-free.
#include <cmath>
#include <cstdio>
#include <random>

#include <Eigen/Geometry>

#include <gtest/gtest.h>

#include "aerial_model.hpp"
#include "alloc_counter.hpp"
#include "kiloloop/aerial/rotor_allocation.hpp"

namespace kiloloop {
namespace {

RotorAllocation make_allocation(const RotorAllocationConfig& c = {}) {
  RotorAllocation a;
  std::string why;
  EXPECT_EQ(RotorAllocation::configure(c, &a, &why), Status::kOk) << why;
  return a;
}

TEST(RotorAllocation, ReproducesTheWrenchExactlyWhenUnsaturated) {
  RotorAllocation alloc = make_allocation();
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> T(12.0, 20.0), tau(-0.3, 0.3), yaw(-0.05, 0.05);
  for (int k = 0; k < 1000; ++k) {
    const Eigen::Vector4d w(T(rng), tau(rng), tau(rng), yaw(rng));
    Eigen::VectorXd f(4);
    Eigen::Vector4d achieved;
    ASSERT_EQ(alloc.allocate(w, f, &achieved), Status::kOk) << w.transpose();
    EXPECT_LT((alloc.mixer() * f - w).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_LT((achieved - w).cwiseAbs().maxCoeff(), 1e-12);
  }
}

TEST(RotorAllocation, GivesUpYawBeforeRollAndPitch) {
  RotorAllocation alloc = make_allocation();
  // Near full thrust with a large yaw demand: roll/pitch must survive, yaw is cut.
  const Eigen::Vector4d w(28.0, 0.4, -0.3, 0.2);
  Eigen::VectorXd f(4);
  Eigen::Vector4d achieved;
  EXPECT_EQ(alloc.allocate(w, f, &achieved), Status::kSaturated);
  EXPECT_TRUE((f.array() >= 0.0).all() && (f.array() <= 8.0).all()) << f.transpose();
  EXPECT_NEAR(achieved[1], w[1], 1e-12);
  EXPECT_NEAR(achieved[2], w[2], 1e-12);
  EXPECT_LT(std::abs(achieved[3]), std::abs(w[3]));
  EXPECT_GE(achieved[3] * w[3], 0.0);  // same sign: reduced, not reversed
  // The yaw share is the largest that fits: some rotor sits at a limit.
  EXPECT_TRUE((f.array() == 8.0).any() || (f.array() == 0.0).any());
}

TEST(RotorAllocation, ShiftsThrustToKeepRollPitchAndScalesOnlyAsLastResort) {
  RotorAllocation alloc = make_allocation();
  Eigen::VectorXd f(4);
  Eigen::Vector4d achieved;
  // Low thrust, strong roll: a rotor would go negative; thrust is raised, roll kept.
  const Eigen::Vector4d w(2.0, 0.6, 0.0, 0.0);
  EXPECT_EQ(alloc.allocate(w, f, &achieved), Status::kSaturated);
  EXPECT_NEAR(achieved[1], 0.6, 1e-12);
  EXPECT_GT(achieved[0], 2.0);
  // Roll beyond what any thrust allows: scaled, still within the limits, direction kept.
  const Eigen::Vector4d huge(16.0, 10.0, 5.0, 0.0);
  EXPECT_EQ(alloc.allocate(huge, f, &achieved), Status::kSaturated);
  EXPECT_TRUE((f.array() >= 0.0).all() && (f.array() <= 8.0).all());
  EXPECT_NEAR(achieved[1] / achieved[2], 2.0, 1e-9);
}

TEST(RotorAllocation, RandomWrenchesStayInLimits) {
  RotorAllocation alloc = make_allocation();
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> T(-5.0, 40.0), tau(-3.0, 3.0);
  for (int k = 0; k < 5000; ++k) {
    const Eigen::Vector4d w(T(rng), tau(rng), tau(rng), tau(rng));
    Eigen::VectorXd f(4);
    const Status s = alloc.allocate(w, f);
    EXPECT_TRUE(s == Status::kOk || s == Status::kSaturated);
    EXPECT_TRUE(f.allFinite() && (f.array() >= 0.0).all() && (f.array() <= 8.0).all());
  }
}

TEST(RotorAllocation, LagCompensationLeadsTheCommand) {
  RotorAllocationConfig c;
  c.lag_compensation = true;
  RotorAllocation alloc = make_allocation(c);
  Eigen::VectorXd f(4);
  alloc.allocate(Eigen::Vector4d(16.0, 0, 0, 0), f);
  EXPECT_NEAR(f[0], 4.0, 1e-12);
  alloc.allocate(Eigen::Vector4d(16.04, 0, 0, 0), f);  // +0.01 N per rotor in one tick
  EXPECT_NEAR(f[0], 4.01 + 0.03 / 0.001 * 0.01, 1e-9);
}

TEST(RotorAllocation, BadInputAndConfig) {
  RotorAllocation alloc = make_allocation();
  Eigen::VectorXd f(4);
  EXPECT_EQ(alloc.allocate(Eigen::Vector4d(std::nan(""), 0, 0, 0), f),
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
  RotorAllocation alloc = make_allocation();
  Eigen::VectorXd f(4);
  testing::AllocationScope scope;
  for (int k = 0; k < 10000; ++k)
    alloc.allocate(Eigen::Vector4d(10.0 + 0.002 * k, 0.3, -0.2, 0.05), f);
  EXPECT_EQ(scope.count(), 0u);
}

RotorAllocationConfig ring(int n, double r = 0.3, double tilt = 0.0) {
  return testing::ring_rotors(n, r, tilt);
}

TEST(RotorAllocation, AnyRotorCountIsExactUnsaturatedAndInLimitsOtherwise) {
  for (int n : {4, 6, 8}) {
    for (double tilt : {0.0, 0.35}) {
      if (n == 4 && tilt > 0) continue;
      RotorAllocation alloc = make_allocation(ring(n, 0.3, tilt));
      EXPECT_EQ(alloc.n(), n);
      EXPECT_EQ(alloc.uses_lateral_rows(), tilt > 0) << n;
      std::mt19937 rng(100 + n);
      std::printf("seed %d\n", 100 + n);
      std::uniform_real_distribution<double> T(2.0 * n, 3.0 * n), tau(-0.3, 0.3),
          yaw(-0.05, 0.05), big(-5.0, 5.0);
      Eigen::VectorXd f(n);
      Eigen::Vector4d achieved;
      for (int k = 0; k < 500; ++k) {
        const Eigen::Vector4d w(T(rng), tau(rng), tau(rng), yaw(rng));
        ASSERT_EQ(alloc.allocate(w, f, &achieved), Status::kOk) << n << " " << w.transpose();
        EXPECT_LT((achieved - w).cwiseAbs().maxCoeff(), 1e-9);
        // Tilted: the lateral force the rotors' components add up to is held at zero.
        EXPECT_LT((alloc.effectiveness().topRows<2>() * f).norm(), 1e-9);
        const Eigen::Vector4d wild(T(rng) * 2.0, big(rng), big(rng), big(rng));
        const Status s = alloc.allocate(wild, f, &achieved);
        EXPECT_TRUE(s == Status::kOk || s == Status::kSaturated);
        EXPECT_TRUE(f.allFinite() && (f.array() >= 0.0).all() && (f.array() <= 8.0).all());
      }
    }
  }
}

TEST(RotorAllocation, HexarotorGivesUpYawFirst) {
  RotorAllocation alloc = make_allocation(ring(6));
  Eigen::VectorXd f(6);
  Eigen::Vector4d achieved;
  const Eigen::Vector4d w(44.0, 0.8, -0.5, 0.4);  // near full thrust, big yaw
  EXPECT_EQ(alloc.allocate(w, f, &achieved), Status::kSaturated);
  EXPECT_NEAR(achieved[1], w[1], 1e-9);
  EXPECT_NEAR(achieved[2], w[2], 1e-9);
  EXPECT_LT(std::abs(achieved[3]), std::abs(w[3]));
  EXPECT_GE(achieved[3] * w[3], 0.0);
}

TEST(RotorAllocation, NamesTheMissingAuthority) {
  RotorAllocationConfig c = ring(6);
  c.torque_coefficient.setZero();  // coplanar, vertical axes, no drag torque: no yaw
  RotorAllocation a;
  std::string why;
  EXPECT_EQ(RotorAllocation::configure(c, &a, &why), Status::kInvalidConfig);
  EXPECT_NE(why.find("yaw"), std::string::npos) << why;
  c = ring(4);
  c.positions.row(1).setZero();  // every rotor on the x axis: no roll
  EXPECT_EQ(RotorAllocation::configure(c, &a, &why), Status::kInvalidConfig);
  EXPECT_NE(why.find("roll"), std::string::npos) << why;
  c = ring(4);
  c.positions.row(0).array() += 1.0;  // rotors all ahead of the CoM
  EXPECT_EQ(RotorAllocation::configure(c, &a, &why), Status::kInvalidConfig);
  EXPECT_NE(why.find("surround"), std::string::npos) << why;
  c = ring(6);
  c.thrust_max = Eigen::VectorXd::Constant(3, 8.0);
  EXPECT_EQ(RotorAllocation::configure(c, &a, &why), Status::kInvalidConfig);
}

TEST(RotorAllocation, IsAllocationFreeForEveryRotorCount) {
  for (int n : {4, 6, 8}) {
    for (double tilt : {0.0, 0.35}) {
      if (n == 4 && tilt > 0) continue;
      RotorAllocation alloc = make_allocation(ring(n, 0.3, tilt));
      Eigen::VectorXd f(n);
      Eigen::Vector4d achieved;
      testing::AllocationScope scope;
      for (int k = 0; k < 2000; ++k)
        alloc.allocate(Eigen::Vector4d(2.0 * n + 0.02 * k, 0.3, -0.2, 0.05 * (k % 7)), f,
                       &achieved);
      EXPECT_EQ(scope.count(), 0u) << n;
    }
  }
}

}  // namespace
}  // namespace kiloloop
