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
  s.sqrt_weight_ = config.wrench_weight.cwiseSqrt();
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

double StanceForceQp::normal_force_cap(double load) const noexcept {
  const double share = std::isfinite(load) ? std::clamp(load, 0.0, 1.0) : 1.0;
  return cfg_.fz_min + share * (cfg_.fz_max - cfg_.fz_min);
}

// Without active constraints the QP is  min 1/2 x'Hx + g'x  with, over the stance legs' forces,
// B = S^1/2 A (6 x 3 count), c = alpha + beta and b = beta / c:
//   H = c I + B'B,   g = -B' S^1/2 w - beta f_prev.
// The push-through identity (c I + B'B)^-1 B' = B' (c I + BB')^-1 and Woodbury's give x = -H^-1 g
// through a 6x6 system instead of the 3 count x 3 count one:
//   x = b f_prev + B' y,   K y = S^1/2 (w - b A f_prev),   K = c I + BB'  (symmetric, >= c I).
// No cancellation is left: b <= 1 and K's eigenvalues are at least c. With m legs, R = sum r_i,
//   AA' = [m I, -[R]x; [R]x, sum (|r_i|^2 I - r_i r_i')].
// The answer is x only if it is finite and meets every constraint row exactly (no tolerance):
// then the active-set solve would stop at its unconstrained start too, with the same x up to
// rounding. Anything else, c = 0 included, goes to that solve.
bool StanceForceQp::unconstrained_optimum(const Eigen::Matrix<double, 6, 1>& wrench,
                                          const std::array<Eigen::Vector3d, kLegs>& feet,
                                          const int* legs, int count, const Eigen::Vector3d (&rows)[4],
                                          const Eigen::Vector3d& nrm,
                                          const std::array<double, kLegs>& load,
                                          Eigen::Matrix<double, 12, 1>& f) noexcept {
  const double c = cfg_.regularization + cfg_.smoothing;
  if (!(c > 0.0)) return false;
  const double b = cfg_.smoothing / c;
  // Sums over the stance legs: R = sum r, P = sum r r' (lower triangle), |r|^2, and A f_prev.
  double R[3] = {0.0, 0.0, 0.0}, P[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0}, r2 = 0.0;
  double Af[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
  for (int a = 0; a < count; ++a) {
    const int i = legs[a];
    const Eigen::Vector3d& r = feet[i];
    const Eigen::Vector3d fp = f_prev_.segment<3>(3 * i);
    const Eigen::Vector3d m = r.cross(fp);
    for (int k = 0; k < 3; ++k) {
      R[k] += r[k];
      Af[k] += fp[k];
      Af[3 + k] += m[k];
    }
    P[0] += r.x() * r.x(), P[1] += r.y() * r.x(), P[2] += r.z() * r.x();
    P[3] += r.y() * r.y(), P[4] += r.z() * r.y(), P[5] += r.z() * r.z();
    r2 += r.squaredNorm();
  }
  // K = c I + S^1/2 AA' S^1/2, lower triangle: AA' = [m I, -[R]x; [R]x, |r|^2 I - P].
  const double* s = sqrt_weight_.data();
  const double m = count;
  double K[6][6];
  K[0][0] = m, K[1][1] = m, K[2][2] = m;
  K[1][0] = 0.0, K[2][0] = 0.0, K[2][1] = 0.0;
  K[3][0] = 0.0, K[3][1] = -R[2], K[3][2] = R[1];  // [R]x
  K[4][0] = R[2], K[4][1] = 0.0, K[4][2] = -R[0];
  K[5][0] = -R[1], K[5][1] = R[0], K[5][2] = 0.0;
  K[3][3] = r2 - P[0], K[4][3] = -P[1], K[5][3] = -P[2];
  K[4][4] = r2 - P[3], K[5][4] = -P[4], K[5][5] = r2 - P[5];
  double y[6];
#pragma GCC unroll 6
  for (int i = 0; i < 6; ++i) {
#pragma GCC unroll 6
    for (int j = 0; j <= i; ++j) K[i][j] = s[i] * K[i][j] * s[j];
    K[i][i] += c;
    y[i] = s[i] * (wrench[i] - b * Af[i]);
  }
  // K = L L' in place (K >= c I: a pivot that is not positive means numbers that are not finite),
  // then L z = y and L' y = z.
  double inv_diag[6];
#pragma GCC unroll 6
  for (int j = 0; j < 6; ++j) {
    double pivot = K[j][j];
#pragma GCC unroll 6
    for (int k = 0; k < j; ++k) pivot -= K[j][k] * K[j][k];
    if (!(pivot > 0.0)) return false;
    inv_diag[j] = 1.0 / std::sqrt(pivot);
#pragma GCC unroll 6
    for (int i = j + 1; i < 6; ++i) {
      double v = K[i][j];
#pragma GCC unroll 6
      for (int k = 0; k < j; ++k) v -= K[i][k] * K[j][k];
      K[i][j] = v * inv_diag[j];
    }
  }
#pragma GCC unroll 6
  for (int i = 0; i < 6; ++i) {
    double v = y[i];
#pragma GCC unroll 6
    for (int k = 0; k < i; ++k) v -= K[i][k] * y[k];
    y[i] = v * inv_diag[i];
  }
#pragma GCC unroll 6
  for (int i = 5; i >= 0; --i) {
    double v = y[i];
#pragma GCC unroll 6
    for (int k = i + 1; k < 6; ++k) v -= K[k][i] * y[k];
    y[i] = v * inv_diag[i];
  }
  // x_i = b f_prev_i + [I [r_i]x'] S^1/2 y = b f_prev_i + y_F + y_M x r_i; each row checked.
  const Eigen::Vector3d yF(s[0] * y[0], s[1] * y[1], s[2] * y[2]), yM(s[3] * y[3], s[4] * y[4], s[5] * y[5]);
  Eigen::Matrix<double, 12, 1> x = Eigen::Matrix<double, 12, 1>::Zero();
  double Ax[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
  for (int a = 0; a < count; ++a) {
    const int i = legs[a];
    const Eigen::Vector3d& r = feet[i];
    const Eigen::Vector3d xi = b * f_prev_.segment<3>(3 * i) + yF + yM.cross(r);
    for (int k = 0; k < 4; ++k)
      if (!(rows[k].dot(xi) <= 0.0)) return false;  // NaN fails too
    const double fn = nrm.dot(xi);
    if (!(fn >= cfg_.fz_min && fn <= normal_force_cap(load[i]))) return false;
    if (!xi.allFinite()) return false;
    x.segment<3>(3 * i) = xi;
    const Eigen::Vector3d mi = r.cross(xi);
    for (int k = 0; k < 3; ++k) {
      Ax[k] += xi[k];
      Ax[3 + k] += mi[k];
    }
  }
  // 1/2 x'Hx + g'x = 1/2 (c |x|^2 + |S^1/2 A x|^2) - w' S A x - beta f_prev' x, as the solver
  // reports it.
  double quad = 0.0, lin = 0.0;
  for (int k = 0; k < 6; ++k) {
    const double wk = cfg_.wrench_weight[k];
    quad += wk * Ax[k] * Ax[k];
    lin += wrench[k] * wk * Ax[k];
  }
  const double objective = 0.5 * (c * x.squaredNorm() + quad) - lin - cfg_.smoothing * f_prev_.dot(x);
  result_ = qp::QpResult{qp::QpStatus::kOptimal, 0, objective, 0};
  f = x;
  f_prev_ = x;
  return true;
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
  closed_form_ = false;
  // Nothing on the ground: no forces and no problem to pose (the 12-variable form returned the
  // same zeros, optimal, after 12 iterations: one per variable fixed by its bounds).
  if (count == 0) {
    result_ = qp::QpResult{qp::QpStatus::kOptimal, 0, 0.0, 0};
    f.setZero();
    f_prev_.setZero();
    return Status::kOk;
  }
  // Tangents of the ground plane (any orthonormal pair perpendicular to n).
  const Eigen::Vector3d nrm = normal.normalized();
  const Eigen::Vector3d helper = std::abs(nrm.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  const Eigen::Vector3d t1 = (helper - helper.dot(nrm) * nrm).normalized(), t2 = nrm.cross(t1);
  const Eigen::Vector3d rows[4] = {t1 - cfg_.mu * nrm, -t1 - cfg_.mu * nrm, t2 - cfg_.mu * nrm,
                                   -t2 - cfg_.mu * nrm};
  closed_form_ = unconstrained_optimum(wrench, feet, legs, count, rows, nrm, load, f);
  if (closed_form_) return Status::kOk;

  for (int i = 0; i < kLegs; ++i) A_.block<3, 3>(3, 3 * i) = skew(feet[i]);  // the QP's H and g
  const auto S = cfg_.wrench_weight.asDiagonal();
  hessian_of_wrench(legs, count);
  H_.diagonal().head(n).array() += cfg_.regularization + cfg_.smoothing;
  g_.noalias() = -(A_.transpose() * (S * wrench));
  g_ -= cfg_.smoothing * f_prev_;
  for (int a = 0; a < count; ++a) gc_.segment<3>(3 * a) = g_.segment<3>(3 * legs[a]);
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
    d_[r + 5] = normal_force_cap(load[i]);
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
