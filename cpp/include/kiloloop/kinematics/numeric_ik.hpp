#pragma once
// Numeric inverse kinematics for any serial chain: Levenberg-Marquardt on the weighted pose
// error within the joint limits, with a fixed iteration budget (deterministic: no wall-clock
// stopping, restarts from a fixed quasi-random sequence).
//
//   e = [p_target - p(q); log(R_target R(q)^T)]      (6) [m; rad], W = diag(weights)
//   (J^T W J + lambda I) dq = J^T W e,   lambda = mu (E + lambda_floor),   E = e^T W e
// The damping follows the error (Sugihara 2011: large far from the target, vanishing at it, so
// convergence is quadratic) and mu adapts as in Marquardt's method: halved after a step that
// lowers E, quadrupled after one that does not. Near a singularity Gauss-Newton steps are large
// and fail, so the damping rises exactly where it is needed. Joint limits form an active set
// inside the step: a joint whose step would cross its limit is held at the limit and the others
// re-solve (clamping the full step instead is not a descent direction and stalls at limits).
// A solve succeeds when the position and the orientation errors are within their own
// tolerances (components with weight 0 are free). After `restart_after` iterations without
// success it restarts from the next point of a Halton sequence over the joint range; the best
// iterate is kept.
//
// configure() sizes every buffer; solve() is noexcept and allocation-free.
#include <string>

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "kiloloop/kinematics/chain_kinematics.hpp"

namespace kiloloop {

struct NumericIkConfig {
  int max_iterations = 500;            // budget per solve, restarts included
  int restart_after = 15;              // iterations per attempt before a restart (0: never)
  double position_tolerance = 1e-6;    // [m] on |p_target - p|
  double orientation_tolerance = 1e-6; // [rad] rotation angle of R_target R^T
  Vector6d weights = Vector6d::Ones(); // task weights [x y z rx ry rz] >= 0; 0 leaves it free
  double lambda_floor = 1e-6;          // [m^2] damping floor (relative to E, see above)
  double mu_initial = 1.0;             // initial damping multiplier
  bool joint_limits = true;            // project every iterate onto [lower, upper]
  double unbounded_range = 3.141592653589793;  // [rad] restart range where a limit is infinite
};

Status validate(const NumericIkConfig& config, std::string* why);

// What the last solve did (for logs, benchmarks and tests).
struct IkReport {
  int iterations = 0;             // LM iterations (accepted and rejected steps)
  int restarts = 0;
  double position_error = 0.0;    // [m] of the returned q
  double orientation_error = 0.0; // [rad] of the returned q
};

class NumericIk {
 public:
  NumericIk() = default;
  static Status configure(const NumericIkConfig& config, const RobotModel& model, NumericIk* out,
                          std::string* why);

  int nq() const { return kin_.nq(); }
  const NumericIkConfig& config() const { return config_; }
  const IkReport& report() const { return report_; }
  ChainKinematics& kinematics() { return kin_; }

  // q (nq) with T_root_tip(q) = target. kOk within tolerance; kIterationLimit when the budget
  // ran out (q is the best iterate found, finite and within limits); kBadSize,
  // kNonFiniteReference (target) or kNonFiniteMeasurement (seed) leave q = clamped seed or
  // untouched when the size is wrong.
  Status solve(const Eigen::Isometry3d& target, const Eigen::Ref<const Eigen::VectorXd>& seed,
               Eigen::Ref<Eigen::VectorXd> q) noexcept;
  // The same from a close initial guess (an analytic solution): `iterations` budget, no restart.
  Status refine(const Eigen::Isometry3d& target, const Eigen::Ref<const Eigen::VectorXd>& guess,
                int iterations, Eigen::Ref<Eigen::VectorXd> q) noexcept;

 private:
  Status run(const Eigen::Isometry3d& target, const Eigen::Ref<const Eigen::VectorXd>& seed,
             int budget, bool restarts, Eigen::Ref<Eigen::VectorXd> q) noexcept;
  // Weighted squared error E and whether both tolerances hold, at the pose T.
  double evaluate(const Eigen::Isometry3d& target, const Eigen::Isometry3d& T, Vector6d& e,
                  bool* converged, double* pos_err, double* rot_err) const noexcept;
  void clamp(Eigen::Ref<Eigen::VectorXd> q) const noexcept;
  // dq_ from the damped system (A_, g_) with joints that would cross a limit held at it.
  bool limited_step() noexcept;
  void restart_point(int index, Eigen::Ref<Eigen::VectorXd> q) const noexcept;

  NumericIkConfig config_;
  ChainKinematics kin_;
  Eigen::VectorXd lower_, upper_, lo_restart_, hi_restart_;  // (nq)
  Eigen::VectorXd q_, q_try_, dq_, g_, best_;                // (nq) scratch
  Eigen::MatrixXd J_, J_try_, WJ_;                           // (6, nq)
  Eigen::MatrixXd A_, A_act_;                                // (nq, nq)
  Eigen::VectorXd g_act_, active_;                           // (nq) active-set scratch
  // Computed on an empty matrix at construction (no allocation): Eigen sets an LDLT's status only
  // in compute(), and copying or moving one that never computed (a default NumericIk moved into
  // place by configure) reads that unset field (UBSan: invalid value for ComputationInfo).
  Eigen::LDLT<Eigen::MatrixXd> ldlt_{Eigen::MatrixXd(0, 0)};
  IkReport report_;
};

}  // namespace kiloloop
