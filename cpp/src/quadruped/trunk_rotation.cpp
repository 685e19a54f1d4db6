#include "kiloloop/quadruped/trunk_rotation.hpp"

#include <cmath>

#include <Eigen/Cholesky>
#include <Eigen/LU>

#include "kiloloop/quadruped/ldlt6.hpp"

namespace kiloloop {

bool trunk_acceleration(const FreeLegInertia& inertia, const LegTorques& legs,
                        const Eigen::Vector3d& gravity, Eigen::Matrix<double, 6, 1>* accel) noexcept {
  using Matrix63 = Eigen::Matrix<double, 6, 3>;
  using Vector6 = Eigen::Matrix<double, 6, 1>;
  Matrix6d lhs = inertia.composite;
  Vector6 rhs = Vector6::Zero();
  rhs.head<3>() = inertia.composite(0, 0) * gravity;  // [m g; 0]: the weight acts at the CoM
  for (int i = 0; i < 4; ++i) {
    const Matrix63& A = inertia.momentum[i];
    const Eigen::Matrix3d& H_inv = inertia.joint_inertia_inverse[i];
    const Eigen::Vector3d& u = legs.torque[i];
    lhs -= inertia.coupling[i];  // A H^-1 A^T: a constant of the standing pose (configure)
    rhs -= A * (H_inv * u);
    if (!legs.pinned[i]) continue;
    const Eigen::Matrix3d& J = legs.jacobian[i];
    const Eigen::Matrix3d Phi = J * H_inv * J.transpose();
    if (!(std::abs(Phi.determinant()) > 1e-12)) return false;  // a straight leg: no prediction
    const Eigen::Matrix3d Phi_inv = Phi.inverse();
    Matrix63 G_T;  // G^T: a foot force's wrench about the CoM, [f; r x f]
    G_T.topRows<3>().setIdentity();
    const Eigen::Vector3d& r = legs.foot[i];
    G_T.bottomRows<3>() << 0, -r.z(), r.y(), r.z(), 0, -r.x(), -r.y(), r.x(), 0;
    const Matrix63 B_T = A * H_inv * J.transpose() - G_T;
    lhs += B_T * Phi_inv * B_T.transpose();
    rhs += B_T * (Phi_inv * (J * (H_inv * u)));
  }
  const Vector6 a = Ldlt6(lhs).solve(rhs);  // Eigen's ldlt() bit for bit (ldlt6.hpp)
  if (!a.allFinite()) return false;
  *accel = a;
  return true;
}

}  // namespace kiloloop
