#include "kiloloop/quadruped/trunk_rotation.hpp"

#include <cmath>

#include <Eigen/Cholesky>
#include <Eigen/LU>

#include "kiloloop/quadruped/ldlt6.hpp"

namespace kiloloop {
namespace {

using Matrix63 = Eigen::Matrix<double, 6, 3>;

// M N for a 6x3 M and a 3x3 N, each entry summed over k in order as Eigen's product of the two
// evaluates it (the first product of both written-out expressions below).
Matrix63 times_3x3(const Matrix63& M, const Eigen::Matrix3d& N) noexcept {
  Matrix63 MN;
#pragma GCC unroll 6
  for (int i = 0; i < 6; ++i)
#pragma GCC unroll 3
    for (int j = 0; j < 3; ++j)
      MN(i, j) = M(i, 0) * N(0, j) + M(i, 1) * N(1, j) + M(i, 2) * N(2, j);
  return MN;
}

// B^T = A H^-1 J^T - G^T, written out: Eigen's `A * H_inv * J.transpose() - G_T` (A H^-1 first,
// each entry summed over k in order; then the row-major product with J^T, which Eigen reduces as
// x0 + (x1 + x2)), the same operations in the same order. Out of line, as Eigen's product was
// kept in some builds (GCC's inlining of it depended on the unity unit's other sources), it cost
// a call and its stores; here it unrolls in place whatever the neighbours (bit-identity checked
// on 2M random inputs with signed zeros against Eigen's expression).
Matrix63 coupling_transposed(const Matrix63& A, const Eigen::Matrix3d& H_inv,
                             const Eigen::Matrix3d& J, const Matrix63& G_T) noexcept {
  const Matrix63 AH = times_3x3(A, H_inv);
  Matrix63 B_T;
#pragma GCC unroll 6
  for (int i = 0; i < 6; ++i)
#pragma GCC unroll 3
    for (int j = 0; j < 3; ++j)
      B_T(i, j) = (AH(i, 0) * J(j, 0) + (AH(i, 1) * J(j, 1) + AH(i, 2) * J(j, 2))) - G_T(i, j);
  return B_T;
}

// The trunk's mass matrix lhs is formed in its lower triangle and diagonal only: Ldlt6, its one
// reader, reads no entry above the diagonal (Eigen's ldlt() on the lower triangle, ldlt6.hpp), so
// the 15 entries above were work for nothing (15 subtractions a leg; 45 products and 45 sums a
// pinned leg).

// lhs -= A H^-1 A^T, entry by entry, in the lower triangle (see above).
void subtract_lower(const Matrix6d& coupling, Matrix6d* lhs) noexcept {
#pragma GCC unroll 6
  for (int j = 0; j < 6; ++j)
#pragma GCC unroll 6
    for (int i = j; i < 6; ++i) (*lhs)(i, j) -= coupling(i, j);
}

// lhs += B^T Phi^-1 B in the lower triangle (see above), each entry written out as Eigen's
// `lhs += B_T * Phi_inv * B_T.transpose()` evaluates it (B^T Phi^-1 first, summed over k in order;
// then the row-major product with B, x0 + (x1 + x2); then the sum into lhs), for the same reason
// as coupling_transposed.
void add_congruence_lower(const Matrix63& B_T, const Eigen::Matrix3d& Phi_inv,
                          Matrix6d* lhs) noexcept {
  const Matrix63 BP = times_3x3(B_T, Phi_inv);
#pragma GCC unroll 6
  for (int i = 0; i < 6; ++i)
#pragma GCC unroll 6
    for (int j = 0; j <= i; ++j)
      (*lhs)(i, j) += BP(i, 0) * B_T(j, 0) + (BP(i, 1) * B_T(j, 1) + BP(i, 2) * B_T(j, 2));
}

// One entry of a 3x3 product as Eigen's fixed-size product evaluates it (SSE2): rows 0 and 1 as
// one packet, their terms summed in order; row 2 alone, reduced as x0 + (x1 + x2).
double eigen_sum3(int row, double x0, double x1, double x2) noexcept {
  return row < 2 ? x0 + x1 + x2 : x0 + (x1 + x2);
}

// Phi = J H^-1 J^T, written out as Eigen's `J * H_inv * J.transpose()` evaluates it (J H^-1 first,
// then the product with J^T; each through eigen_sum3), inline where Eigen's two 3x3 products were
// calls (bit-identity checked on 200k random inputs against Eigen's expression).
Eigen::Matrix3d foot_mobility(const Eigen::Matrix3d& J, const Eigen::Matrix3d& H_inv) noexcept {
  Eigen::Matrix3d JH, Phi;
#pragma GCC unroll 3
  for (int i = 0; i < 3; ++i)
#pragma GCC unroll 3
    for (int j = 0; j < 3; ++j)
      JH(i, j) = eigen_sum3(i, J(i, 0) * H_inv(0, j), J(i, 1) * H_inv(1, j), J(i, 2) * H_inv(2, j));
#pragma GCC unroll 3
  for (int i = 0; i < 3; ++i)
#pragma GCC unroll 3
    for (int j = 0; j < 3; ++j)
      Phi(i, j) = eigen_sum3(i, JH(i, 0) * J(j, 0), JH(i, 1) * J(j, 1), JH(i, 2) * J(j, 2));
  return Phi;
}

}  // namespace

bool trunk_acceleration(const FreeLegInertia& inertia, const LegTorques& legs,
                        const Eigen::Vector3d& gravity, Eigen::Matrix<double, 6, 1>* accel) noexcept {
  using Vector6 = Eigen::Matrix<double, 6, 1>;
  Matrix6d lhs = inertia.composite;  // the lower triangle formed (add_congruence_lower)
  Vector6 rhs = Vector6::Zero();
  rhs.head<3>() = inertia.composite(0, 0) * gravity;  // [m g; 0]: the weight acts at the CoM
  for (int i = 0; i < 4; ++i) {
    const Matrix63& A = inertia.momentum[i];
    const Eigen::Matrix3d& H_inv = inertia.joint_inertia_inverse[i];
    const Eigen::Vector3d H_inv_u = H_inv * legs.torque[i];  // used twice for a pinned leg
    subtract_lower(inertia.coupling[i], &lhs);  // A H^-1 A^T: a constant of the standing pose
    rhs -= A * H_inv_u;
    if (!legs.pinned[i]) continue;
    const Eigen::Matrix3d& J = legs.jacobian[i];
    const Eigen::Matrix3d Phi = foot_mobility(J, H_inv);
    if (!(std::abs(Phi.determinant()) > 1e-12)) return false;  // a straight leg: no prediction
    const Eigen::Matrix3d Phi_inv = Phi.inverse();
    Matrix63 G_T;  // G^T: a foot force's wrench about the CoM, [f; r x f]
    G_T.topRows<3>().setIdentity();
    const Eigen::Vector3d& r = legs.foot[i];
    G_T.bottomRows<3>() << 0, -r.z(), r.y(), r.z(), 0, -r.x(), -r.y(), r.x(), 0;
    const Matrix63 B_T = coupling_transposed(A, H_inv, J, G_T);
    add_congruence_lower(B_T, Phi_inv, &lhs);
    rhs += B_T * (Phi_inv * (J * H_inv_u));
  }
  const Vector6 a = Ldlt6(lhs).solve(rhs);  // Eigen's ldlt() bit for bit (ldlt6.hpp)
  if (!a.allFinite()) return false;
  *accel = a;
  return true;
}

}  // namespace kiloloop
