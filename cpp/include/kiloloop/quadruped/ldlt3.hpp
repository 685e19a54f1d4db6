#pragma once
// Ldlt3: a symmetric 3x3 solve A x = b by LDL^T with diagonal pivoting, the numbers of Eigen's
// A.ldlt().solve(b) (Matrix3d, lower triangle) bit for bit, without its bookkeeping.
//
// Why: the quadruped controller solves such systems one to four times a tick (the ground plane's
// normal equations at each foothold latch, the trunk's rotational inertia, the swing legs'
// joint-space inertia at 35 ms), and Eigen's LDLT also forms the L1 norm and the definiteness
// sign through generic dynamic-size blocks: ~1.1k instructions a solve (callgrind), several
// times the arithmetic. The steps here are Eigen 3.4's ldlt_inplace<Lower>::unblocked in its
// order: the first largest |diagonal| entry of the trailing corner as pivot, exchanged within
// the lower triangle; the row's products with D summed, then subtracted; the column below
// divided by a non-zero pivot; an all-zero diagonal stops at once. The solve: the exchanges, the
// unit-lower substitution, D's pseudo-inverse (entries at or below DBL_MIN give 0), the
// unit-upper substitution, the exchanges back. ldlt3_test.cpp compares it with Eigen.
#include <cfloat>
#include <cmath>
#include <utility>

#include <Eigen/Core>

namespace kiloloop {

class Ldlt3 {
 public:
  // Every loop unrolls completely (the pragmas), so the bounds that
  // follow k are constants: the same operations in the same order, without the loop overhead.
  explicit Ldlt3(const Eigen::Matrix3d& A) noexcept {
#pragma GCC unroll 3
    for (int i = 0; i < 3; ++i)
#pragma GCC unroll 3
      for (int j = 0; j < 3; ++j) m_[i][j] = A(i, j);
#pragma GCC unroll 3
    for (int k = 0; k < 3; ++k) {
      int big = k;
      double big_abs = std::abs(m_[k][k]);
#pragma GCC unroll 3
      for (int i = k + 1; i < 3; ++i)
        if (std::abs(m_[i][i]) > big_abs) big_abs = std::abs(m_[i][i]), big = i;
      swap_[k] = big;
      if (big != k) {  // exchange k and big, touching the lower triangle only
#pragma GCC unroll 3
        for (int j = 0; j < k; ++j) std::swap(m_[k][j], m_[big][j]);
#pragma GCC unroll 3
        for (int i = big + 1; i < 3; ++i) std::swap(m_[i][k], m_[i][big]);
        std::swap(m_[k][k], m_[big][big]);
#pragma GCC unroll 3
        for (int i = k + 1; i < big; ++i) {
          const double t = m_[i][k];
          m_[i][k] = m_[big][i];
          m_[big][i] = t;
        }
      }
      if (k > 0) {
        double t[2];  // D L_k^T
#pragma GCC unroll 3
        for (int j = 0; j < k; ++j) t[j] = m_[j][j] * m_[k][j];
        m_[k][k] -= k == 1 ? m_[k][0] * t[0] : m_[k][0] * t[0] + m_[k][1] * t[1];
#pragma GCC unroll 3
        for (int i = k + 1; i < 3; ++i)  // k == 1 here: one term
          m_[i][k] -= m_[i][0] * t[0];
      }
      const double pivot = m_[k][k];
      if (k == 0 && !(std::abs(pivot) > 0.0)) {  // the whole diagonal is zero
        swap_[0] = 0, swap_[1] = 1, swap_[2] = 2;
        return;
      }
      if (std::abs(pivot) > 0.0) {
#pragma GCC unroll 3
        for (int i = k + 1; i < 3; ++i) m_[i][k] /= pivot;
      }
    }
  }

  Eigen::Vector3d solve(const Eigen::Vector3d& b) const noexcept {
    double v[3] = {b[0], b[1], b[2]};
    for (int k = 0; k < 3; ++k) std::swap(v[k], v[swap_[k]]);
    v[1] -= m_[1][0] * v[0];
    v[2] -= m_[2][0] * v[0] + m_[2][1] * v[1];
    for (int i = 0; i < 3; ++i) v[i] = std::abs(m_[i][i]) > DBL_MIN ? v[i] / m_[i][i] : 0.0;
    v[1] -= m_[2][1] * v[2];
    v[0] -= m_[1][0] * v[1] + m_[2][0] * v[2];
    for (int k = 2; k >= 0; --k) std::swap(v[k], v[swap_[k]]);
    return {v[0], v[1], v[2]};
  }

 private:
  double m_[3][3];  // L strictly below the diagonal (unit diagonal implied), D on it
  int swap_[3];     // row and column exchanged with k at step k
};

}  // namespace kiloloop
