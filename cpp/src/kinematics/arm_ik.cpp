#include "kiloloop/kinematics/arm_ik.hpp"

namespace kiloloop {

Status validate(const ArmIkConfig& c, std::string* why) {
  if (!(c.analytic_tolerance >= 0.0)) {
    if (why) *why = "analytic_tolerance must be >= 0";
    return Status::kInvalidConfig;
  }
  if (c.refine_iterations < 0) {
    if (why) *why = "refine_iterations must be >= 0";
    return Status::kInvalidConfig;
  }
  return validate(c.numeric, why);
}

Status ArmIk::configure(const ArmIkConfig& config, const RobotModel& model, ArmIk* out,
                        std::string* why) {
  Status s = validate(config, why);
  if (failed(s)) return s;
  ArmIk ik;
  ik.config_ = config;
  s = NumericIk::configure(config.numeric, model, &ik.numeric_, why);
  if (failed(s)) return s;
  // Not UR-shaped is not an error: the numeric solver covers any chain; the reason is kept.
  if (config.use_analytic) {
    ik.has_analytic_ = UrAnalyticIk::from_model(model, &ik.analytic_, &ik.analytic_reason_,
                                                config.analytic_tolerance) == Status::kOk;
    if (ik.has_analytic_) ik.analytic_reason_.clear();
  } else {
    ik.analytic_reason_ = "disabled (use_analytic = false)";
  }
  *out = std::move(ik);
  return Status::kOk;
}

Status ArmIk::solve(const Eigen::Isometry3d& target, const Eigen::Ref<const Eigen::VectorXd>& seed,
                    Eigen::Ref<Eigen::VectorXd> q) noexcept {
  if (has_analytic_ && seed.size() == 6 && q.size() == 6 && seed.allFinite() &&
      target.matrix().allFinite()) {
    int count = 0;
    const Eigen::Matrix<double, 6, 1> s6 = seed;
    if (analytic_.solve(target, s6, candidates_, &count) == Status::kOk) {
      for (int k = 0; k < count; ++k) {
        if (numeric_.refine(target, candidates_.col(k), config_.refine_iterations, q) == Status::kOk)
          return Status::kOk;
      }
    }
  }
  return numeric_.solve(target, seed, q);
}

}  // namespace kiloloop
