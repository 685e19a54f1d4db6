#pragma once
// Lu3: a 3x3 solve A x = b by LU with partial pivoting, the numbers of Eigen's
// PartialPivLU<Matrix3d>(A).solve(b) bit for bit, without its bookkeeping.
//
// Why: the quadruped controller solves a leg Jacobian's system five times a tick (the stance
// force from the torques, the swing joints' velocity), and Eigen's decomposition also forms the
// matrix's L1 norm, a permutation matrix and its generic loops: ~600 instructions a solve
// (callgrind), several times the arithmetic. The steps here are Eigen 3.4's, in its order:
// unblocked_lu (pivot: the first largest |a_ik| of the column; the column below divided by it,
// an exactly zero pivot left undivided; the rank-1 update l_i u_j), then the row exchanges on b,
// the unit-lower and the upper substitutions as its unrolled triangular solver does them
// (a row's products summed first, then subtracted; a division by the diagonal).
// lu3_test.cpp compares it with Eigen on random, pivoting and singular matrices.
#include <cmath>
#include <utility>

#include <Eigen/Core>

namespace kiloloop {

class Lu3 {
 public:
  // Every loop unrolls completely (the pragmas), so the bounds that
  // follow k are constants: the same operations in the same order, without the loop overhead.
  explicit Lu3(const Eigen::Matrix3d& A) noexcept {
#pragma GCC unroll 3
    for (int i = 0; i < 3; ++i)
#pragma GCC unroll 3
      for (int j = 0; j < 3; ++j) m_[i][j] = A(i, j);
#pragma GCC unroll 3
    for (int k = 0; k < 2; ++k) {
      int p = k;
      double big = std::abs(m_[k][k]);
#pragma GCC unroll 3
      for (int i = k + 1; i < 3; ++i)
        if (std::abs(m_[i][k]) > big) big = std::abs(m_[i][k]), p = i;
      swap_[k] = p;
      if (big != 0.0) {
        if (p != k) std::swap(m_[k], m_[p]);
#pragma GCC unroll 3
        for (int i = k + 1; i < 3; ++i) m_[i][k] /= m_[k][k];
      }
#pragma GCC unroll 3
      for (int i = k + 1; i < 3; ++i)
#pragma GCC unroll 3
        for (int j = k + 1; j < 3; ++j) m_[i][j] -= m_[i][k] * m_[k][j];
    }
  }

  Eigen::Vector3d solve(const Eigen::Vector3d& b) const noexcept {
    double v[3] = {b[0], b[1], b[2]};
    for (int k = 0; k < 2; ++k) std::swap(v[k], v[swap_[k]]);
    // L y = P b (unit lower).
    v[1] -= m_[1][0] * v[0];
    v[2] -= m_[2][0] * v[0] + m_[2][1] * v[1];
    // U x = y, bottom up.
    v[2] /= m_[2][2];
    v[1] -= m_[1][2] * v[2];
    v[1] /= m_[1][1];
    v[0] -= m_[0][1] * v[1] + m_[0][2] * v[2];
    v[0] /= m_[0][0];
    return {v[0], v[1], v[2]};
  }

 private:
  double m_[3][3];  // L below the diagonal (unit diagonal implied), U on and above
  int swap_[2];     // row exchanged with row k at step k
};

}  // namespace kiloloop
