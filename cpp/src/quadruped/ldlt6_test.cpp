// Ldlt6 against Eigen's LDLT<Matrix<double, 6, 6>>: the same solution bit for bit on random
// symmetric matrices (definite and indefinite, every pivot order), on floating-base-like ones
// (a trunk's mass and inertia less leg couplings plus stance-leg terms) and on degenerate ones.
#include "kiloloop/quadruped/ldlt6.hpp"

#include <cmath>
#include <random>

#include <Eigen/Cholesky>
#include <gtest/gtest.h>

namespace kiloloop {
namespace {

using Matrix6 = Eigen::Matrix<double, 6, 6>;
using Vector6 = Eigen::Matrix<double, 6, 1>;

void expect_same_ldlt6_solution(const Matrix6& A, const Vector6& b) {
  const Vector6 ref = A.ldlt().solve(b);
  const Vector6 got = Ldlt6(A).solve(b);
  for (int i = 0; i < 6; ++i)
    ASSERT_TRUE(got[i] == ref[i] || (std::isnan(got[i]) && std::isnan(ref[i])))
        << "A =\n" << A << "\nb = " << b.transpose() << "\n" << got.transpose() << "\nvs\n" << ref.transpose();
}

TEST(Ldlt6, EqualsEigenLdltOnRandomSymmetricMatrices) {
  std::mt19937 rng(41);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int k = 0; k < 20000; ++k) {
    Matrix6 M;
    for (int i = 0; i < 36; ++i) M(i) = u(rng) * std::pow(10.0, 2.0 * u(rng));
    const Matrix6 A = k % 2 ? Matrix6(M + M.transpose()) : Matrix6(M * M.transpose());
    Vector6 b;
    for (int i = 0; i < 6; ++i) b[i] = 10.0 * u(rng);
    expect_same_ldlt6_solution(A, b);
  }
}

TEST(Ldlt6, EqualsEigenLdltOnFloatingBaseSystems) {
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int k = 0; k < 5000; ++k) {
    Matrix6 A = Matrix6::Zero();
    A.topLeftCorner<3, 3>() = 15.0 * Eigen::Matrix3d::Identity();
    A.bottomRightCorner<3, 3>() = Eigen::Vector3d(0.1, 0.3, 0.35).asDiagonal();
    for (int leg = 0; leg < 4; ++leg) {
      Eigen::Matrix<double, 6, 3> B;
      for (int i = 0; i < 18; ++i) B(i) = 0.3 * u(rng);
      A += (leg % 2 ? 1.0 : -0.1) * B * B.transpose();
    }
    Vector6 b;
    for (int i = 0; i < 6; ++i) b[i] = 100.0 * u(rng);
    expect_same_ldlt6_solution(A, b);
  }
}

TEST(Ldlt6, DegenerateMatricesAsEigen) {
  std::mt19937 rng(43);
  std::uniform_int_distribution<int> pick(-2, 2);
  for (int k = 0; k < 20000; ++k) {
    Matrix6 M;
    for (int i = 0; i < 36; ++i) M(i) = pick(rng);
    Vector6 b;
    for (int i = 0; i < 6; ++i) b[i] = pick(rng);
    expect_same_ldlt6_solution(Matrix6(M + M.transpose()), b);
  }
  expect_same_ldlt6_solution(Matrix6::Zero(), Vector6::Ones());
}

}  // namespace
}  // namespace kiloloop
