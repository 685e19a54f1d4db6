#include "kiloloop/quadruped/stance_force.hpp"

#include <algorithm>
#include <cmath>

#include <cmath>
#include <limits>

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
  s.C_ = Eigen::MatrixXd::Zero(6 * kLegs, 12);
  s.d_ = Eigen::VectorXd::Zero(6 * kLegs);
  s.lb_ = Eigen::VectorXd::Constant(12, -std::numeric_limits<double>::infinity());
  s.ub_ = Eigen::VectorXd::Constant(12, std::numeric_limits<double>::infinity());
  s.none_ = Eigen::VectorXd::Zero(0);
  *out = std::move(s);
  return Status::kOk;
}

// H = A^T S A, the numbers of Eigen's product A_.transpose() * S * A_ (its general
// matrix-matrix kernel: 3.9k instructions a tick) bit for bit. That product summed, for each
// entry, the terms (A_ki S_k) A_kj over the rows k = 0..5 of A in order, starting from +0; the
// terms left out here are exact zeros (A's identity blocks off their diagonal, the diagonal of
// each [r]x), which change no sum (the 0.0 + below keeps even the sign of a zero entry). With
// [r]x = [0 -z y; z 0 -x; -y x 0] the block of legs i, j is: S_c from the force rows on the
// diagonal, then the moment rows m != c, c' in order.
void StanceForceQp::hessian_of_wrench() noexcept {
  const Eigen::Matrix<double, 6, 1>& w = cfg_.wrench_weight;
  const double w0 = 0.0 + w[0], w1 = 0.0 + w[1], w2 = 0.0 + w[2];
  // (A^T S)(3 i + c, 3 + m) = [r_i]x(m, c) S_{3+m}, the non-zero ones.
  double p10[kLegs], p20[kLegs], p01[kLegs], p21[kLegs], p02[kLegs], p12[kLegs];
  for (int i = 0; i < kLegs; ++i) {
    const double x = A_(5, 3 * i + 1), y = A_(3, 3 * i + 2), z = A_(4, 3 * i);  // r_i
    p10[i] = z * w[4];
    p20[i] = -y * w[5];
    p01[i] = -z * w[3];
    p21[i] = x * w[5];
    p02[i] = y * w[3];
    p12[i] = -x * w[4];
  }
  for (int j = 0; j < kLegs; ++j) {
    const double x = A_(5, 3 * j + 1), y = A_(3, 3 * j + 2), z = A_(4, 3 * j);  // r_j
    for (int i = 0; i < kLegs; ++i) {
      auto h = H_.block<3, 3>(3 * i, 3 * j);
      h(0, 0) = (w0 + p10[i] * z) + p20[i] * -y;
      h(1, 0) = 0.0 + p21[i] * -y;
      h(2, 0) = 0.0 + p12[i] * z;
      h(0, 1) = 0.0 + p20[i] * x;
      h(1, 1) = (w1 + p01[i] * -z) + p21[i] * x;
      h(2, 1) = 0.0 + p02[i] * -z;
      h(0, 2) = 0.0 + p10[i] * -x;
      h(1, 2) = 0.0 + p01[i] * y;
      h(2, 2) = (w2 + p02[i] * y) + p12[i] * -x;
    }
  }
}

Status StanceForceQp::solve(const Eigen::Matrix<double, 6, 1>& wrench,
                            const std::array<Eigen::Vector3d, kLegs>& feet,
                            const std::array<bool, kLegs>& stance,
                            const std::array<double, kLegs>& load, const Eigen::Vector3d& normal,
                            Eigen::Matrix<double, 12, 1>& f) noexcept {
  for (int i = 0; i < kLegs; ++i) A_.block<3, 3>(3, 3 * i) = skew(feet[i]);
  const auto S = cfg_.wrench_weight.asDiagonal();
  hessian_of_wrench();
  H_.diagonal().array() += cfg_.regularization + cfg_.smoothing;
  g_.noalias() = -(A_.transpose() * (S * wrench));
  g_ -= cfg_.smoothing * f_prev_;

  // Tangents of the ground plane (any orthonormal pair perpendicular to n).
  const Eigen::Vector3d n = normal.normalized();
  const Eigen::Vector3d helper = std::abs(n.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  const Eigen::Vector3d t1 = (helper - helper.dot(n) * n).normalized(), t2 = n.cross(t1);
  int n_in = 0;
  // C_ is zero but for the blocks the last solve wrote: clear only those.
  for (int i = 0; i < kLegs; ++i)
    if (block_row_[i] >= 0) C_.block<6, 3>(block_row_[i], 3 * i).setZero();
  block_row_.fill(-1);
  constexpr double kInf = std::numeric_limits<double>::infinity();
  for (int i = 0; i < kLegs; ++i) {
    // A foot off the ground carries nothing: fixed at zero by its bounds.
    lb_.segment<3>(3 * i).setConstant(stance[i] ? -kInf : 0.0);
    ub_.segment<3>(3 * i).setConstant(stance[i] ? kInf : 0.0);
    if (!stance[i]) continue;
    block_row_[i] = n_in;
    const Eigen::Vector3d rows[4] = {t1 - cfg_.mu * n, -t1 - cfg_.mu * n, t2 - cfg_.mu * n,
                                     -t2 - cfg_.mu * n};
    for (const auto& row : rows) {
      C_.block<1, 3>(n_in, 3 * i) = row.transpose();
      d_[n_in++] = 0.0;
    }
    C_.block<1, 3>(n_in, 3 * i) = -n.transpose();
    d_[n_in++] = -cfg_.fz_min;
    C_.block<1, 3>(n_in, 3 * i) = n.transpose();
    const double share = std::isfinite(load[i]) ? std::clamp(load[i], 0.0, 1.0) : 1.0;
    d_[n_in++] = cfg_.fz_min + share * (cfg_.fz_max - cfg_.fz_min);
  }
  result_ = solver_.solve(H_, g_, no_rows_, none_, C_.topRows(n_in), d_.head(n_in), lb_, ub_, x_);
  if (result_.status != qp::QpStatus::kOptimal || !x_.allFinite()) {
    f = f_prev_;
    return Status::kSolverFailed;
  }
  f = x_;
  f_prev_ = x_;
  return Status::kOk;
}

}  // namespace kiloloop
