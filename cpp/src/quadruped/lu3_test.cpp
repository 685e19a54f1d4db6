// Lu3 against Eigen's PartialPivLU<Matrix3d>: the same solution bit for bit on random matrices
// (every pivot order), leg-Jacobian-like ones, ones with exactly equal pivot candidates, and
// singular ones (where both give the same non-finite numbers).
#include "kiloloop/quadruped/lu3.hpp"

#include <cstring>
#include <random>

#include <Eigen/LU>
#include <gtest/gtest.h>

namespace kiloloop {
namespace {

// Bit patterns equal (NaN payloads included), so that "the same numbers" holds for inf and NaN.
bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof(double)) == 0; }

void expect_same_lu3_solution(const Eigen::Matrix3d& A, const Eigen::Vector3d& b) {
  const Eigen::Vector3d ref = A.partialPivLu().solve(b);
  const Eigen::Vector3d got = Lu3(A).solve(b);
  for (int i = 0; i < 3; ++i)
    ASSERT_TRUE(same_bits(got[i], ref[i]) || (std::isnan(got[i]) && std::isnan(ref[i])))
        << "A =\n" << A << "\nb = " << b.transpose() << "\n" << got[i] << " vs " << ref[i];
}

TEST(Lu3, EqualsEigenPartialPivLuBitForBit) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int k = 0; k < 20000; ++k) {
    Eigen::Matrix3d A;
    for (int i = 0; i < 9; ++i) A(i) = u(rng) * std::pow(10.0, 3.0 * u(rng));
    const Eigen::Vector3d b(u(rng), 10.0 * u(rng), 100.0 * u(rng));
    expect_same_lu3_solution(A, b);
  }
}

TEST(Lu3, TiesZerosAndSingularMatricesAsEigen) {
  std::mt19937 rng(12);
  std::uniform_int_distribution<int> pick(-2, 2);
  // Small integers: many exactly equal candidates, zero pivots, singular matrices.
  for (int k = 0; k < 20000; ++k) {
    Eigen::Matrix3d A;
    for (int i = 0; i < 9; ++i) A(i) = pick(rng);
    const Eigen::Vector3d b(pick(rng), pick(rng), 1.0);
    expect_same_lu3_solution(A, b);
  }
}

TEST(Lu3, LegJacobianShapesAsEigen) {
  // J^T of a leg: a zero in the corner, the abduction column coupling y and z.
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int k = 0; k < 5000; ++k) {
    Eigen::Matrix3d J;
    J << 0.0, -0.2 + 0.05 * u(rng), -0.1 * u(rng), 0.08 * u(rng), 0.1 * u(rng), 0.05 * u(rng),
        -0.3 + 0.05 * u(rng), 0.02 * u(rng), 0.2 * u(rng);
    const Eigen::Vector3d b(10.0 * u(rng), 10.0 * u(rng), 10.0 * u(rng));
    expect_same_lu3_solution(J, b);
    expect_same_lu3_solution(J.transpose(), b);
  }
}

}  // namespace
}  // namespace kiloloop
