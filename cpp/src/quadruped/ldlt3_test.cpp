// Ldlt3 against Eigen's LDLT<Matrix3d>: the same solution bit for bit on random symmetric
// matrices (definite and indefinite, every pivot order), the ground-plane normal equations the
// estimator solves, inertia-like ones, and degenerate ones (zero diagonal, singular, ties).
#include "kiloloop/quadruped/ldlt3.hpp"

#include <cmath>
#include <cstring>
#include <random>

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <gtest/gtest.h>

namespace kiloloop {
namespace {

bool same(double a, double b) {
  return std::memcmp(&a, &b, sizeof(double)) == 0 || (std::isnan(a) && std::isnan(b));
}

void expect_same_ldlt3_solution(const Eigen::Matrix3d& A, const Eigen::Vector3d& b) {
  const Eigen::Vector3d ref = A.ldlt().solve(b);
  const Eigen::Vector3d got = Ldlt3(A).solve(b);
  for (int i = 0; i < 3; ++i)
    ASSERT_TRUE(same(got[i], ref[i])) << "A =\n" << A << "\nb = " << b.transpose() << "\n"
                                      << got[i] << " vs " << ref[i];
}

TEST(Ldlt3, EqualsEigenLdltOnRandomSymmetricMatrices) {
  std::mt19937 rng(31);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int k = 0; k < 20000; ++k) {
    Eigen::Matrix3d M;
    for (int i = 0; i < 9; ++i) M(i) = u(rng) * std::pow(10.0, 2.0 * u(rng));
    const Eigen::Matrix3d A = k % 2 ? Eigen::Matrix3d(M + M.transpose()) : Eigen::Matrix3d(M * M.transpose());
    expect_same_ldlt3_solution(A, Eigen::Vector3d(u(rng), 10.0 * u(rng), 100.0 * u(rng)));
  }
}

TEST(Ldlt3, EqualsEigenLdltOnGroundPlaneAndInertiaSystems) {
  std::mt19937 rng(32);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int k = 0; k < 5000; ++k) {
    // Normal equations of z = a + b x + c y through four footholds.
    Eigen::Matrix3d AtA = Eigen::Matrix3d::Zero();
    Eigen::Vector3d Atz = Eigen::Vector3d::Zero();
    for (int f = 0; f < 4; ++f) {
      const Eigen::Vector3d row(1.0, (f < 2 ? 0.2 : -0.2) + 0.05 * u(rng), (f % 2 ? -0.15 : 0.15) + 0.05 * u(rng));
      AtA += row * row.transpose();
      Atz += row * (0.01 * u(rng));
    }
    expect_same_ldlt3_solution(AtA, Atz);
    // A rotated inertia, I_world = R I R^T.
    const Eigen::Matrix3d R =
        Eigen::Quaterniond(Eigen::Vector4d(u(rng), u(rng), u(rng), u(rng)).normalized()).toRotationMatrix();
    const Eigen::Vector3d d(0.05 + 0.05 * std::abs(u(rng)), 0.2 + 0.1 * std::abs(u(rng)), 0.25 + 0.1 * std::abs(u(rng)));
    const Eigen::Matrix3d I = R * d.asDiagonal() * R.transpose();
    expect_same_ldlt3_solution(I, Eigen::Vector3d(u(rng), u(rng), u(rng)));
  }
}

TEST(Ldlt3, DegenerateMatricesAsEigen) {
  std::mt19937 rng(33);
  std::uniform_int_distribution<int> pick(-2, 2);
  // Small integers: equal pivot candidates, zero pivots, zero diagonals, singular matrices.
  for (int k = 0; k < 20000; ++k) {
    Eigen::Matrix3d M;
    for (int i = 0; i < 9; ++i) M(i) = pick(rng);
    const Eigen::Matrix3d A = M + M.transpose();
    expect_same_ldlt3_solution(A, Eigen::Vector3d(pick(rng), pick(rng), 1.0));
  }
  expect_same_ldlt3_solution(Eigen::Matrix3d::Zero(), Eigen::Vector3d(1.0, 2.0, 3.0));
}

}  // namespace
}  // namespace kiloloop
