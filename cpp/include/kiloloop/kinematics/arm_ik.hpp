#pragma once
// ArmIk: the arm's position IK. Where the chain has a closed form (UR geometry, detected and
// checked at configure) the analytic solutions, nearest to the seed first, seed a short numeric
// refinement (which also absorbs small deviations from the ideal geometry, e.g. after
// calibration); otherwise the numeric solver runs from the seed with its restarts.
// solve() is noexcept and allocation-free.
#include <string>

#include "kiloloop/kinematics/numeric_ik.hpp"
#include "kiloloop/kinematics/ur_analytic_ik.hpp"

namespace kiloloop {

struct ArmIkConfig {
  NumericIkConfig numeric;     // tolerances, weights, budget of the numeric stage
  bool use_analytic = true;    // use the closed form when the chain has one
  // Largest deviation [m, rad] of the chain's FK from ideal UR geometry for which the closed
  // form is still used, as a seed (exact chains deviate by ~1e-15).
  double analytic_tolerance = 0.01;
  int refine_iterations = 10;  // numeric budget per analytic candidate
};

Status validate(const ArmIkConfig& config, std::string* why);

class ArmIk {
 public:
  ArmIk() = default;
  static Status configure(const ArmIkConfig& config, const RobotModel& model, ArmIk* out,
                          std::string* why);

  int nq() const { return numeric_.nq(); }
  bool has_analytic() const { return has_analytic_; }
  // The solver in use: "ur_analytic" (closed form, refined numerically) or "numeric".
  const char* solver() const { return has_analytic_ ? "ur_analytic" : "numeric"; }
  // Why the closed form is not used (empty when it is), e.g. "UR analytic IK: not a UR-style
  // arm: joint 3 ('elbow') axis not parallel to joint 2 ('shoulder')" or "disabled
  // (use_analytic = false)".
  const std::string& analytic_reason() const { return analytic_reason_; }
  // The closed form itself (meaningful only when has_analytic()).
  const UrAnalyticIk& analytic() const { return analytic_; }
  // FK deviation of the chain from the closed form [m, rad] (0 without one).
  double analytic_deviation() const { return has_analytic_ ? analytic_.deviation() : 0.0; }
  // Statuses as NumericIk::solve. report().iterations counts numeric iterations only.
  Status solve(const Eigen::Isometry3d& target, const Eigen::Ref<const Eigen::VectorXd>& seed,
               Eigen::Ref<Eigen::VectorXd> q) noexcept;
  const IkReport& report() const { return numeric_.report(); }
  NumericIk& numeric() { return numeric_; }

 private:
  ArmIkConfig config_;
  NumericIk numeric_;
  UrAnalyticIk analytic_;
  bool has_analytic_ = false;
  std::string analytic_reason_;
  UrAnalyticIk::Solutions candidates_;
};

}  // namespace kiloloop
