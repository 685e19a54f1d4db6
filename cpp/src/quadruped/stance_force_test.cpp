// StanceForceQp: the ground reaction forces that realize a trunk wrench within friction pyramids,
// normal-force bounds and the per-foot load share; allocation-free solves.
#include "kiloloop/quadruped/stance_force.hpp"

#include <cmath>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "alloc_counter.hpp"

namespace kiloloop {
namespace {

using Vector12d = Eigen::Matrix<double, 12, 1>;
using Wrench = Eigen::Matrix<double, 6, 1>;

// Feet of a 0.4 m x 0.3 m stance, 0.3 m below the CoM.
const std::array<Eigen::Vector3d, 4> kFeet{Eigen::Vector3d(0.2, 0.15, -0.3), Eigen::Vector3d(0.2, -0.15, -0.3),
                                           Eigen::Vector3d(-0.2, 0.15, -0.3),
                                           Eigen::Vector3d(-0.2, -0.15, -0.3)};
constexpr double kWeight = 17.6 * 9.81;

StanceForceQp make_qp(StanceForceConfig config = {}) {
  StanceForceQp qp;
  std::string why;
  EXPECT_EQ(StanceForceQp::configure(config, &qp, &why), Status::kOk) << why;
  return qp;
}

Wrench resultant(const Vector12d& f) {
  Wrench w = Wrench::Zero();
  for (int i = 0; i < 4; ++i) {
    w.head<3>() += f.segment<3>(3 * i);
    w.tail<3>() += kFeet[i].cross(f.segment<3>(3 * i));
  }
  return w;
}

TEST(StanceForceQp, FourFeetCarryTheWeightEvenly) {
  StanceForceQp qp = make_qp();
  Wrench w;
  w << 0, 0, kWeight, 0, 0, 0;
  Vector12d f;
  ASSERT_EQ(qp.solve(w, kFeet, {true, true, true, true}, {1, 1, 1, 1}, Eigen::Vector3d::UnitZ(), f),
            Status::kOk);
  EXPECT_LT((resultant(f) - w).norm(), 0.1);
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(f[3 * i + 2], kWeight / 4, 0.5);
}

TEST(StanceForceQp, DiagonalSupportBuysTheRollMomentWithASidewaysForce) {
  // Two diagonal feet cannot produce a moment about the line through them from vertical forces;
  // with the default weights the QP still realizes the roll moment, using horizontal forces.
  StanceForceQp qp = make_qp();
  Wrench w;
  w << 0, 0, kWeight, 3.0, 0, 0;
  Vector12d f;
  ASSERT_EQ(qp.solve(w, kFeet, {true, false, false, true}, {1, 1, 1, 1}, Eigen::Vector3d::UnitZ(), f),
            Status::kOk);
  EXPECT_EQ(f.segment<3>(3).norm(), 0.0);  // swing feet carry nothing
  EXPECT_EQ(f.segment<3>(6).norm(), 0.0);
  const Wrench got = resultant(f);
  EXPECT_GT(got[3], 0.9 * 3.0);
  EXPECT_LT(got[3], 3.0 + 1e-9);
  EXPECT_GT(std::abs(got[1]), 5.0);  // the sideways force that pays for it (~ moment / height)
  // Moments weighted like forces x10 (the old default) leave most of the roll moment undone.
  StanceForceConfig light;
  light.wrench_weight << 1, 1, 1, 10, 10, 10;
  StanceForceQp qp_light = make_qp(light);
  ASSERT_EQ(qp_light.solve(w, kFeet, {true, false, false, true}, {1, 1, 1, 1}, Eigen::Vector3d::UnitZ(), f),
            Status::kOk);
  EXPECT_LT(resultant(f)[3], got[3] - 0.5);
}

TEST(StanceForceQp, LoadShareCapsTheNormalForceAndFrictionHolds) {
  StanceForceConfig config;
  StanceForceQp qp = make_qp(config);
  Wrench w;
  w << 20.0, 0, kWeight, 0, 0, 0;
  Vector12d f;
  const std::array<double, 4> load{0.1, 1.0, 1.0, 0.0};
  ASSERT_EQ(qp.solve(w, kFeet, {true, true, true, true}, load, Eigen::Vector3d::UnitZ(), f), Status::kOk);
  const double cap0 = config.fz_min + 0.1 * (config.fz_max - config.fz_min);
  EXPECT_LE(f[2], cap0 + 1e-9);
  EXPECT_LE(f[11], config.fz_min + 1e-9);  // load 0: down to the minimum normal force
  EXPECT_GE(f[11], config.fz_min - 1e-9);
  for (int i = 0; i < 4; ++i) {
    EXPECT_LE(std::abs(f[3 * i]), config.mu * f[3 * i + 2] + 1e-9);
    EXPECT_LE(std::abs(f[3 * i + 1]), config.mu * f[3 * i + 2] + 1e-9);
  }
}

TEST(StanceForceQp, SolvesAreAllocationFree) {
  StanceForceQp qp = make_qp();
  Vector12d f;
  Wrench w;
  std::size_t allocations = 0;
  for (int k = 0; k < 4000; ++k) {
    w << 5.0 * std::sin(0.01 * k), 3.0 * std::cos(0.013 * k), kWeight, 2.0 * std::sin(0.02 * k), 1.0, 0.5;
    const bool pair = (k / 300) % 2 == 0;
    const std::array<bool, 4> stance{pair || k % 300 < 30, !pair || k % 300 < 30, !pair || k % 300 < 30,
                                     pair || k % 300 < 30};
    const double ramp = std::min(1.0, (k % 300) / 30.0);
    testing::AllocationScope scope;
    const Status s = qp.solve(w, kFeet, stance, {ramp, ramp, ramp, ramp}, Eigen::Vector3d::UnitZ(), f);
    allocations += scope.count();
    ASSERT_EQ(s, Status::kOk) << "tick " << k;
    ASSERT_TRUE(f.allFinite());
  }
  EXPECT_EQ(allocations, 0u);
}

}  // namespace
}  // namespace kiloloop
