#include "kiloloop/quadruped/stance_force.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

namespace kiloloop {
namespace {

Eigen::Matrix3d skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d S;
  S << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return S;
}

}  // namespace

Status validate(const StanceForceConfig& config, std::string* why) {
  const bool finite = std::isfinite(config.mu) && std::isfinite(config.fz_max) &&
                      std::isfinite(config.regularization) && std::isfinite(config.smoothing) &&
                      config.wrench_weight.allFinite();
  if (finite && config.mu > 0 && config.fz_min >= 0 && config.fz_max > config.fz_min &&
      config.regularization >= 0 && config.smoothing >= 0 &&
      (config.wrench_weight.array() >= 0).all() && config.max_iterations >= 1)
    return Status::kOk;
  if (why)
    *why = "stance force: need mu > 0, 0 <= fz_min < fz_max, non-negative weights, finite values, "
           "max_iterations >= 1";
  return Status::kInvalidConfig;
}

Status StanceForceQp::configure(const StanceForceConfig& config, StanceForceQp* out, std::string* why) {
  const Status valid = validate(config, why);
  if (failed(valid)) return valid;
  qp::QpSettings settings;
  settings.max_iterations = config.max_iterations;
  StanceForceQp s;
  const Status st = qp::DenseQpSolver::configure(12, 0, 6 * kLegs, settings, &s.solver_, why);
  if (failed(st)) return st;
  s.cfg_ = config;
  s.A_.setZero();
  for (int i = 0; i < kLegs; ++i) s.A_.block<3, 3>(0, 3 * i).setIdentity();
  s.f_prev_.setZero();
  s.no_rows_ = Eigen::MatrixXd::Zero(0, 12);
  s.C_ = Eigen::MatrixXd::Zero(6 * kLegs, 12);  // zero off its diagonal blocks from here on (solve)
  s.d_ = Eigen::VectorXd::Zero(6 * kLegs);
  s.none_ = Eigen::VectorXd::Zero(0);
  *out = std::move(s);
  return Status::kOk;
}

// H = A^T S A over the stance legs (legs[0..count), their blocks at 3 a, 3 b), the numbers of
// Eigen's product A_.transpose() * S * A_ (its general matrix-matrix kernel: 3.9k instructions a
// tick) bit for bit. That product summed, for each entry, the terms (A_ki S_k) A_kj over the rows
// k = 0..5 of A in order, starting from +0; the terms left out here are exact zeros (A's identity
// blocks off their diagonal, the diagonal of each [r]x), which change no sum (the 0.0 + below
// keeps even the sign of a zero entry). With [r]x = [0 -z y; z 0 -x; -y x 0] the block of legs
// i, j is: S_c from the force rows on the diagonal, then the moment rows m != c, c' in order.
void StanceForceQp::hessian_of_wrench(const int* legs, int count) noexcept {
  const Eigen::Matrix<double, 6, 1>& w = cfg_.wrench_weight;
  const double w0 = 0.0 + w[0], w1 = 0.0 + w[1], w2 = 0.0 + w[2];
  // (A^T S)(3 i + c, 3 + m) = [r_i]x(m, c) S_{3+m}, the non-zero ones.
  double p10[kLegs], p20[kLegs], p01[kLegs], p21[kLegs], p02[kLegs], p12[kLegs];
  for (int a = 0; a < count; ++a) {
    const int i = legs[a];
    const double x = A_(5, 3 * i + 1), y = A_(3, 3 * i + 2), z = A_(4, 3 * i);  // r_i
    p10[a] = z * w[4];
    p20[a] = -y * w[5];
    p01[a] = -z * w[3];
    p21[a] = x * w[5];
    p02[a] = y * w[3];
    p12[a] = -x * w[4];
  }
  for (int b = 0; b < count; ++b) {
    const int j = legs[b];
    const double x = A_(5, 3 * j + 1), y = A_(3, 3 * j + 2), z = A_(4, 3 * j);  // r_j
    for (int a = 0; a < count; ++a) {
      auto h = H_.block<3, 3>(3 * a, 3 * b);
      h(0, 0) = (w0 + p10[a] * z) + p20[a] * -y;
      h(1, 0) = 0.0 + p21[a] * -y;
      h(2, 0) = 0.0 + p12[a] * z;
      h(0, 1) = 0.0 + p20[a] * x;
      h(1, 1) = (w1 + p01[a] * -z) + p21[a] * x;
      h(2, 1) = 0.0 + p02[a] * -z;
      h(0, 2) = 0.0 + p10[a] * -x;
      h(1, 2) = 0.0 + p01[a] * y;
      h(2, 2) = (w2 + p02[a] * y) + p12[a] * -x;
    }
  }
}

// The QP is posed on the stance legs' forces only (n = 3 per stance leg): a swing leg's force is
// zero, and passing it as a variable fixed by its bounds made the solver check and eliminate it
// every tick (the same numbers otherwise: the reduced problem it solved is this one).
Status StanceForceQp::solve(const Eigen::Matrix<double, 6, 1>& wrench,
                            const std::array<Eigen::Vector3d, kLegs>& feet,
                            const std::array<bool, kLegs>& stance,
                            const std::array<double, kLegs>& load, const Eigen::Vector3d& normal,
                            Eigen::Matrix<double, 12, 1>& f) noexcept {
  int legs[kLegs], count = 0;
  for (int i = 0; i < kLegs; ++i)
    if (stance[i]) legs[count++] = i;
  const int n = 3 * count;
  // Nothing on the ground: no forces and no problem to pose (the 12-variable form returned the
  // same zeros, optimal, after 12 iterations: one per variable fixed by its bounds).
  if (count == 0) {
    result_ = qp::QpResult{qp::QpStatus::kOptimal, 0, 0.0, 0};
    f.setZero();
    f_prev_.setZero();
    return Status::kOk;
  }
  for (int i = 0; i < kLegs; ++i) A_.block<3, 3>(3, 3 * i) = skew(feet[i]);
  const auto S = cfg_.wrench_weight.asDiagonal();
  hessian_of_wrench(legs, count);
  H_.diagonal().head(n).array() += cfg_.regularization + cfg_.smoothing;
  g_.noalias() = -(A_.transpose() * (S * wrench));
  g_ -= cfg_.smoothing * f_prev_;
  for (int a = 0; a < count; ++a) gc_.segment<3>(3 * a) = g_.segment<3>(3 * legs[a]);

  // Tangents of the ground plane (any orthonormal pair perpendicular to n).
  const Eigen::Vector3d nrm = normal.normalized();
  const Eigen::Vector3d helper = std::abs(nrm.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  const Eigen::Vector3d t1 = (helper - helper.dot(nrm) * nrm).normalized(), t2 = nrm.cross(t1);
  const Eigen::Vector3d rows[4] = {t1 - cfg_.mu * nrm, -t1 - cfg_.mu * nrm, t2 - cfg_.mu * nrm,
                                   -t2 - cfg_.mu * nrm};
  const int n_in = 6 * count;
  // C_ is block diagonal: stance leg a's six rows (6 a ..) act on its forces (3 a ..) alone. Only
  // those blocks are ever written, in full, below; every other entry keeps the zero configure()
  // set (zeroing the used corner again each tick cost 1.5k instructions).
  for (int a = 0; a < count; ++a) {
    const int i = legs[a], r = 6 * a;
    for (int k = 0; k < 4; ++k) {
      C_.block<1, 3>(r + k, 3 * a) = rows[k].transpose();
      d_[r + k] = 0.0;
    }
    C_.block<1, 3>(r + 4, 3 * a) = -nrm.transpose();
    d_[r + 4] = -cfg_.fz_min;
    C_.block<1, 3>(r + 5, 3 * a) = nrm.transpose();
    const double share = std::isfinite(load[i]) ? std::clamp(load[i], 0.0, 1.0) : 1.0;
    d_[r + 5] = cfg_.fz_min + share * (cfg_.fz_max - cfg_.fz_min);
  }
  result_ = solver_.solve(H_.topLeftCorner(n, n), gc_.head(n), no_rows_.leftCols(n), none_, C_.topLeftCorner(n_in, n),
                          d_.head(n_in), none_, none_, xc_.head(n));
  if (result_.status != qp::QpStatus::kOptimal || !xc_.head(n).allFinite()) {
    f = f_prev_;
    return Status::kSolverFailed;
  }
  f.setZero();
  for (int a = 0; a < count; ++a) f.segment<3>(3 * legs[a]) = xc_.segment<3>(3 * a);
  f_prev_ = f;
  return Status::kOk;
}

}  // namespace kiloloop
