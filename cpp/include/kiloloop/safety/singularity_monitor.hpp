#pragma once
// Singularity monitor from the Jacobian's singular values. The linear rows are divided by a
// characteristic length L so that all six rows are in the same unit (rad/s per rad/s):
//   J_s = [J_v / L; J_w],  sigma_i = sqrt(eig(J_s J_s^T)),
//   manipulability w = prod sigma_i = sqrt(det(J_s J_s^T))  (Yoshikawa),
//   condition number kappa = sigma_max / sigma_min.
// It warns BEFORE the arm gets there: when w falls below w_warn, kappa rises above kappa_warn,
// or w extrapolated `horizon` seconds ahead at its current rate would fall below w_warn.
// Allocation-free for any nq (J_s J_s^T is always 6x6).
#include <string>

#include <Eigen/Core>

#include "kiloloop/status.hpp"

namespace kiloloop {

struct SingularityMonitorConfig {
  double characteristic_length = 0.5;   // [m] L (about the arm's reach)
  double manipulability_warn = 0.005;   // w below this warns (UR5 at its default pose: ~0.06)
  double condition_warn = 40.0;         // kappa above this warns
  double horizon = 0.3;                 // [s] look-ahead of the rate test (0 disables it)
};

Status validate(const SingularityMonitorConfig& c, std::string* why);

struct SingularityState {
  double manipulability = 0.0;  // w
  double condition = 0.0;       // kappa (inf when singular)
  double sigma_min = 0.0;
  double rate = 0.0;            // [1/s] dw/dt (finite difference)
  bool warning = false;
};

class SingularityMonitor {
 public:
  void configure(const SingularityMonitorConfig& c) { config_ = c, has_prev_ = false; }
  // J: (6, nq) tip Jacobian [linear; angular]; dt [s] since the previous update (<= 0: no rate).
  // Returns kNearSingularity when warning, kOk otherwise, kBadSize / kNonFiniteMeasurement on
  // bad input (state untouched).
  Status update(const Eigen::Ref<const Eigen::MatrixXd>& J, double dt, SingularityState* state) noexcept;
  const SingularityMonitorConfig& config() const { return config_; }

 private:
  SingularityMonitorConfig config_;
  double prev_w_ = 0.0;
  bool has_prev_ = false;
};

}  // namespace kiloloop
