// AxisCovariance against the 6x6 filter it replaced (StateEstimator before): the same P, K and
// correction bit for bit over long random sequences of predictions and corrections, from the
// start value and from blocks that make PartialPivLU exchange the rows.
#include "kiloloop/quadruped/axis_covariance.hpp"

#include <cmath>
#include <random>

#include <Eigen/LU>
#include <gtest/gtest.h>

#include "alloc_counter.hpp"

namespace kiloloop {
namespace {

using Matrix6 = Eigen::Matrix<double, 6, 6>;
using Vector6 = Eigen::Matrix<double, 6, 1>;

// The estimator's former code, verbatim.
void predict_6x6(Matrix6& P, double dt, double accel_noise) {
  Matrix6 F = Matrix6::Identity();
  F.topRightCorner<3, 3>() = Eigen::Matrix3d::Identity() * dt;
  Matrix6 Q = Matrix6::Zero();
  const double qa = accel_noise * accel_noise;
  Q.topLeftCorner<3, 3>().diagonal().setConstant(0.25 * dt * dt * dt * dt * qa);
  Q.bottomRightCorner<3, 3>().diagonal().setConstant(dt * dt * qa);
  P = F * P * F.transpose() + Q;
}

Vector6 correct_6x6(Matrix6& P, double r_p, double r_v, const Vector6& e) {
  Matrix6 Rm = Matrix6::Zero();
  Rm.topLeftCorner<3, 3>().diagonal().setConstant(r_p);
  Rm.bottomRightCorner<3, 3>().diagonal().setConstant(r_v);
  const Matrix6 S = P + Rm;
  const Matrix6 K = P * S.inverse();
  const Vector6 dx = K * e;
  P = (Matrix6::Identity() - K) * P;
  P = 0.5 * (P + P.transpose());
  return dx;
}

Vector6 correct_axes(AxisCovariance& P, double r_p, double r_v, const Vector6& e) {
  const AxisGain K = P.correct(r_p, r_v);
  Vector6 dx;
  for (int a = 0; a < 3; ++a) {
    dx[a] = K.pp * e[a] + K.pv * e[a + 3];
    dx[a + 3] = K.vp * e[a] + K.vv * e[a + 3];
  }
  return dx;
}

void expect_same(const Matrix6& ref, const AxisCovariance& P, int step) {
  const Matrix6 got = P.full();
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) ASSERT_EQ(got(i, j), ref(i, j)) << "step " << step << " (" << i << ", " << j << ")";
}

// The estimator's sequence: predict every tick, correct with the stance legs' weight (1e-3 to 4
// legs' trust) on most ticks; noises and dt spread over decades.
void run_sequence(Matrix6 P_ref, AxisCovariance P, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double dt = std::pow(10.0, -3.5 + 2.0 * u(rng));
  const double accel_noise = std::pow(10.0, -1.0 + 2.0 * u(rng));
  const double foothold = std::pow(10.0, -3.0 + 2.0 * u(rng));
  const double leg_velocity = std::pow(10.0, -2.0 + 2.0 * u(rng));
  for (int step = 0; step < 3000; ++step) {
    predict_6x6(P_ref, dt, accel_noise);
    P.predict(dt, accel_noise);
    expect_same(P_ref, P, step);
    if (u(rng) < 0.2) continue;  // no stance leg this tick
    const double weight = 1e-3 + 4.0 * u(rng);
    Vector6 e;
    for (int i = 0; i < 6; ++i) e[i] = 0.1 * (u(rng) - 0.5);
    const double r_p = foothold * foothold / weight, r_v = leg_velocity * leg_velocity / weight;
    const Vector6 dx_ref = correct_6x6(P_ref, r_p, r_v, e);
    const Vector6 dx = correct_axes(P, r_p, r_v, e);
    for (int i = 0; i < 6; ++i) ASSERT_EQ(dx[i], dx_ref[i]) << "step " << step;
    expect_same(P_ref, P, step);
  }
}

TEST(AxisCovariance, IsTheSixBySixFilterBitForBit) {
  for (unsigned seed = 0; seed < 20; ++seed) {
    AxisCovariance P;  // the estimator's start before reset: I
    run_sequence(Matrix6::Identity(), P, seed);
    P.reset(1e-4);
    run_sequence(Matrix6::Identity() * 1e-4, P, 100 + seed);
  }
}

TEST(AxisCovariance, RowExchangeOfTheInverseBitForBit) {
  // |P(v, p)| above P(p, p) + R: PartialPivLU takes the velocity row as the pivot.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int exchanged = 0;
  for (int k = 0; k < 2000; ++k) {
    Eigen::Matrix2d block;
    block << 1e-6 * u(rng), 2.0 * (u(rng) - 0.5), 2.0 * (u(rng) - 0.5), 1.0 + 4.0 * u(rng);
    AxisCovariance P(block);
    const Matrix6 ref_start = P.full();
    Matrix6 P_ref = ref_start;
    const double r_p = 1e-7 * u(rng), r_v = 1e-3 * u(rng);
    exchanged += std::abs(block(1, 0)) > std::abs(block(0, 0) + r_p);
    Vector6 e;
    for (int i = 0; i < 6; ++i) e[i] = u(rng) - 0.5;
    const Vector6 dx_ref = correct_6x6(P_ref, r_p, r_v, e);
    const Vector6 dx = correct_axes(P, r_p, r_v, e);
    for (int i = 0; i < 6; ++i) ASSERT_EQ(dx[i], dx_ref[i]) << k;
    expect_same(P_ref, P, k);
  }
  EXPECT_GT(exchanged, 1000);  // the branch was taken
}

TEST(AxisCovariance, AllocationFree) {
  AxisCovariance P;
  P.reset(1e-4);
  testing::AllocationScope scope;
  for (int k = 0; k < 100; ++k) {
    P.predict(1e-3, 0.5);
    P.correct(1e-4, 2.5e-3);
  }
  EXPECT_EQ(scope.count(), 0u);
}

}  // namespace
}  // namespace kiloloop
