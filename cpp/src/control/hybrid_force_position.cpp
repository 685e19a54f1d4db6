#include "kiloloop/control/hybrid_force_position.hpp"

#include <cmath>

#include <Eigen/LU>

namespace kiloloop {

Status validate(const HybridForcePositionConfig& c, std::string* why) {
  const Status s = validate(c.common, why);
  if (failed(s)) return s;
  auto non_negative = [](const Vector6d& v) { return v.allFinite() && (v.array() >= 0.0).all(); };
  const char* msg = nullptr;
  if (!((c.selection.array() == 0.0) || (c.selection.array() == 1.0)).all())
    msg = "selection entries must be 0 (force) or 1 (motion)";
  else if (!c.task_rotation.allFinite() ||
           (c.task_rotation.transpose() * c.task_rotation - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-9 ||
           c.task_rotation.determinant() < 0.0)
    msg = "task_rotation must be a rotation matrix";
  else if (!non_negative(c.kp) || !non_negative(c.kd)) msg = "kp and kd must be finite and >= 0";
  else if (!non_negative(c.kf) || !non_negative(c.ki) || !non_negative(c.kv))
    msg = "kf, ki and kv must be finite and >= 0";
  else if (!(c.integral_limit >= 0.0) || !std::isfinite(c.integral_limit))
    msg = "integral_limit must be finite and >= 0";
  if (msg == nullptr) return Status::kOk;
  if (why) *why = msg;
  return Status::kInvalidConfig;
}

Status HybridForcePositionController::configure(const HybridForcePositionConfig& config,
                                                RobotModelPtr model,
                                                HybridForcePositionController* out, std::string* why) {
  Status s = validate(config, why);
  if (failed(s)) return s;
  HybridForcePositionController c;
  s = c.configure_common(config.common, std::move(model), why);
  if (failed(s)) return s;
  c.config_ = config;
  c.R6_.setZero();
  c.R6_.topLeftCorner<3, 3>() = config.task_rotation;
  c.R6_.bottomRightCorner<3, 3>() = config.task_rotation;
  *out = std::move(c);
  return Status::kOk;
}

Status HybridForcePositionController::law(const CartesianControlInput& in, Vector6d& F) noexcept {
  if (!in.wrench_measured.allFinite()) return Status::kNonFiniteMeasurement;
  const HybridForcePositionConfig& c = config_;
  // Everything into the task frame, per-axis laws there, the wrench back to the root frame.
  const Vector6d e = R6_.transpose() * e_;
  const Vector6d ed = R6_.transpose() * (in.twist_ref - xd_);
  const Vector6d a_ref = R6_.transpose() * in.accel_ref;
  const Vector6d f_ref = R6_.transpose() * in.wrench_ref;
  const Vector6d f = R6_.transpose() * in.wrench_measured;
  const Vector6d v = R6_.transpose() * xd_;
  Vector6d a_m, f_cmd;
  for (int i = 0; i < 6; ++i) {
    if (c.selection[i] == 1.0) {
      a_m[i] = a_ref[i] + c.kp[i] * e[i] + c.kd[i] * ed[i];
      f_cmd[i] = 0.0;
      integral_[i] = 0.0;
    } else {
      a_m[i] = 0.0;
      const double err = f_ref[i] - f[i];
      // An increment that overflows (huge forces) is skipped: clamping a NaN would pick a limit.
      const double increment = c.ki[i] * err * dt_;
      if (std::isfinite(increment))
        integral_[i] = std::fmin(std::fmax(integral_[i] + increment, -c.integral_limit),
                                 c.integral_limit);
      f_cmd[i] = f_ref[i] + c.kf[i] * err + integral_[i] - c.kv[i] * v[i];
    }
  }
  // Motion part Omega Lambda Omega a_m: Lambda's off-diagonal terms would otherwise turn a motion
  // command into a force along the force-controlled axes (a static disturbance of the force).
  const Eigen::Matrix<double, 6, 6> Lambda_task = R6_.transpose() * Lambda_ * R6_;
  Vector6d f_m = Lambda_task * a_m;
  if (c.project_motion_wrench)
    for (int i = 0; i < 6; ++i)
      if (c.selection[i] != 1.0) f_m[i] = 0.0;
  F.noalias() = R6_ * (f_m + f_cmd);
  return Status::kOk;
}

}  // namespace kiloloop
