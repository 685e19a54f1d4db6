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

Status StanceForceQp::solve(const Eigen::Matrix<double, 6, 1>& wrench,
                            const std::array<Eigen::Vector3d, kLegs>& feet,
                            const std::array<bool, kLegs>& stance,
                            const std::array<double, kLegs>& load, const Eigen::Vector3d& normal,
                            Eigen::Matrix<double, 12, 1>& f) noexcept {
  for (int i = 0; i < kLegs; ++i) A_.block<3, 3>(3, 3 * i) = skew(feet[i]);
  const auto S = cfg_.wrench_weight.asDiagonal();
  H_.noalias() = A_.transpose() * S * A_;
  H_.diagonal().array() += cfg_.regularization + cfg_.smoothing;
  g_.noalias() = -(A_.transpose() * (S * wrench));
  g_ -= cfg_.smoothing * f_prev_;

  // Tangents of the ground plane (any orthonormal pair perpendicular to n).
  const Eigen::Vector3d n = normal.normalized();
  const Eigen::Vector3d helper = std::abs(n.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  const Eigen::Vector3d t1 = (helper - helper.dot(n) * n).normalized(), t2 = n.cross(t1);
  int n_in = 0;
  C_.setZero();
  constexpr double kInf = std::numeric_limits<double>::infinity();
  for (int i = 0; i < kLegs; ++i) {
    // A foot off the ground carries nothing: fixed at zero by its bounds.
    lb_.segment<3>(3 * i).setConstant(stance[i] ? -kInf : 0.0);
    ub_.segment<3>(3 * i).setConstant(stance[i] ? kInf : 0.0);
    if (!stance[i]) continue;
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
