#pragma once
// Ldlt6: a symmetric 6x6 solve A x = b by LDL^T with diagonal pivoting (the floating base's
// trunk acceleration, trunk_rotation.cpp), the numbers of Eigen's A.ldlt().solve(b) (Matrix6d,
// lower triangle) bit for bit.
//
// Why: Eigen's factorization runs on dynamic-size blocks (1.6k instructions a tick, callgrind, a
// fifth of trunk_acceleration) and forms the L1 norm and the definiteness sign besides. The
// factorization here is Eigen 3.4's ldlt_inplace<Lower>::unblocked, step for step (pivot: the
// first largest |diagonal| entry of the trailing corner, exchanged within the lower triangle;
// the row's products with D summed in order and subtracted from the diagonal entry; each entry
// below it less the sum, in order from zero, of its row's products; the column divided by a
// non-zero pivot; an all-zero diagonal stops at once). The solve is Eigen's own code: the same
// exchanges, triangular views and pseudo-inverse of D as LDLT::solve. ldlt6_test.cpp compares
// it with Eigen.
#include <cfloat>
#include <cmath>
#include <utility>

#include <Eigen/Core>

namespace kiloloop {

class Ldlt6 {
 public:
  using Matrix6 = Eigen::Matrix<double, 6, 6>;
  using Vector6 = Eigen::Matrix<double, 6, 1>;

  // Every loop unrolls completely (the pragmas), so the bounds that
  // follow k are constants: the same operations in the same order, without the loop overhead.
  explicit Ldlt6(const Matrix6& A) noexcept : m_(A) {
    constexpr int n = 6;
#pragma GCC unroll 6
    for (int k = 0; k < n; ++k) {
      int big = k;
      double big_abs = std::abs(m_(k, k));
#pragma GCC unroll 6
      for (int i = k + 1; i < n; ++i)
        if (std::abs(m_(i, i)) > big_abs) big_abs = std::abs(m_(i, i)), big = i;
      swaps_.indices()[k] = big;
      if (big != k) {  // exchange k and big, touching the lower triangle only
#pragma GCC unroll 6
        for (int j = 0; j < k; ++j) std::swap(m_(k, j), m_(big, j));
#pragma GCC unroll 6
        for (int i = big + 1; i < n; ++i) std::swap(m_(i, k), m_(i, big));
        std::swap(m_(k, k), m_(big, big));
#pragma GCC unroll 6
        for (int i = k + 1; i < big; ++i) {
          const double t = m_(i, k);
          m_(i, k) = m_(big, i);
          m_(big, i) = t;
        }
      }
      if (k > 0) {
        double t[n];  // D L_k^T
#pragma GCC unroll 6
        for (int j = 0; j < k; ++j) t[j] = m_(j, j) * m_(k, j);
        double s = m_(k, 0) * t[0];
#pragma GCC unroll 6
        for (int j = 1; j < k; ++j) s += m_(k, j) * t[j];
        m_(k, k) -= s;
#pragma GCC unroll 6
        for (int i = k + 1; i < n; ++i) {
          double r = 0.0;
#pragma GCC unroll 6
          for (int j = 0; j < k; ++j) r += m_(i, j) * t[j];
          m_(i, k) -= r;
        }
      }
      const double pivot = m_(k, k);
      if (k == 0 && !(std::abs(pivot) > 0.0)) {  // the whole diagonal is zero
        swaps_.setIdentity();
        return;
      }
      if (std::abs(pivot) > 0.0) {
#pragma GCC unroll 6
        for (int i = k + 1; i < n; ++i) m_(i, k) /= pivot;
      }
    }
  }

  Vector6 solve(const Vector6& b) const noexcept {
    Vector6 x = swaps_ * b;
    const Matrix6& m = m_;
    m.triangularView<Eigen::UnitLower>().solveInPlace(x);
    for (int i = 0; i < 6; ++i) {
      if (std::abs(m(i, i)) > DBL_MIN) x[i] /= m(i, i);
      else x[i] = 0.0;
    }
    m.transpose().triangularView<Eigen::UnitUpper>().solveInPlace(x);
    return swaps_.transpose() * x;
  }

 private:
  Matrix6 m_;                          // L strictly below the diagonal, D on it
  Eigen::Transpositions<6, 6, int> swaps_;  // row and column exchanged with k at step k
};

}  // namespace kiloloop
