#include "kiloloop/safety/singularity_monitor.hpp"

#include <cmath>
#include <limits>

#include <Eigen/Eigenvalues>

namespace kiloloop {

Status validate(const SingularityMonitorConfig& c, std::string* why) {
  const char* msg = nullptr;
  if (!(c.characteristic_length > 0.0) || !std::isfinite(c.characteristic_length))
    msg = "characteristic_length must be > 0";
  else if (!(c.manipulability_warn >= 0.0) || !std::isfinite(c.manipulability_warn))
    msg = "manipulability_warn must be finite and >= 0";
  else if (!(c.condition_warn >= 1.0)) msg = "condition_warn must be >= 1";
  else if (!(c.horizon >= 0.0) || !std::isfinite(c.horizon)) msg = "horizon must be finite and >= 0";
  if (msg == nullptr) return Status::kOk;
  if (why) *why = msg;
  return Status::kInvalidConfig;
}

Status SingularityMonitor::update(const Eigen::Ref<const Eigen::MatrixXd>& J, double dt,
                                  SingularityState* state) noexcept {
  if (J.rows() != 6 || J.cols() < 1) return Status::kBadSize;
  if (!J.allFinite()) return Status::kNonFiniteMeasurement;
  Eigen::Matrix<double, 6, 6> A;
  A.noalias() = J * J.transpose();
  // Scale: rows 0-2 by 1/L, so A's blocks by 1/L^2 (vv) and 1/L (vw, wv).
  const double s = 1.0 / config_.characteristic_length;
  A.topRows<3>() *= s;
  A.leftCols<3>() *= s;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> eig(A, Eigen::EigenvaluesOnly);
  const Eigen::Matrix<double, 6, 1> lambda = eig.eigenvalues().cwiseMax(0.0);  // ascending
  // With nq < 6, J_s J_s^T has 6 - nq zero eigenvalues: use the nq largest.
  const int rank = J.cols() < 6 ? static_cast<int>(J.cols()) : 6;
  double w = 1.0;
  for (int i = 6 - rank; i < 6; ++i) w *= std::sqrt(lambda[i]);
  const double smin = std::sqrt(lambda[6 - rank]), smax = std::sqrt(lambda[5]);
  SingularityState st;
  st.manipulability = w;
  st.sigma_min = smin;
  st.condition = smin > 0.0 ? smax / smin : std::numeric_limits<double>::infinity();
  st.rate = (has_prev_ && dt > 0.0) ? (w - prev_w_) / dt : 0.0;
  prev_w_ = w;
  has_prev_ = true;
  const double predicted = w + std::fmin(st.rate, 0.0) * config_.horizon;
  st.warning = w < config_.manipulability_warn || st.condition > config_.condition_warn ||
               predicted < config_.manipulability_warn;
  *state = st;
  return st.warning ? Status::kNearSingularity : Status::kOk;
}

}  // namespace kiloloop
