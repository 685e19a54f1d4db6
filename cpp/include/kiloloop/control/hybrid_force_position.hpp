#pragma once
// Hybrid force/position control (Raibert & Craig 1981) in the operational-space form (Khatib
// 1987): a diagonal selection matrix S in a task frame R_task splits the six task axes into
// motion-controlled (S_ii = 1) and force-controlled (S_ii = 0) ones,
//   Omega   = R6 S R6^T,  Omega_bar = R6 (I - S) R6^T,   R6 = blkdiag(R_task, R_task)
//   F_m     = Omega Lambda Omega (a_ref + Kp e + Kd (twist_ref - J qd))      motion
//   F_f     = Omega_bar (f_ref + Kf (f_ref - f) + Ki int(f_ref - f) - Kv J qd)   force
//   tau     = J^T (F_m + F_f) + C(q,qd) qd + g(q).
// f_ref and f are the wrench the tip applies on the environment (CartesianControlInput); the
// integral is clamped (anti-windup) and Kv damps the free motion along the force axes, which is
// what makes the approach and contact with a stiff surface stable.
#include <string>

#include "kiloloop/control/cartesian_controller.hpp"

namespace kiloloop {

struct HybridForcePositionConfig {
  CartesianCommonConfig common;  // what every Cartesian controller has (gravity, limits, nullspace)
  Vector6d selection = (Vector6d() << 1, 1, 0, 1, 1, 1).finished();  // 1 motion, 0 force (task frame)
  Eigen::Matrix3d task_rotation = Eigen::Matrix3d::Identity();      // task frame in the root frame
  Vector6d kp = (Vector6d() << 2500, 2500, 2500, 900, 900, 900).finished();  // [1/s^2]
  Vector6d kd = (Vector6d() << 100, 100, 100, 60, 60, 60).finished();        // [1/s]
  Vector6d kf = Vector6d::Constant(0.5);     // [-] proportional force gain
  Vector6d ki = Vector6d::Constant(20.0);    // [1/s] integral force gain
  Vector6d kv = (Vector6d() << 60, 60, 60, 2, 2, 2).finished();  // [N s/m; N m s/rad] damping on force axes
  double integral_limit = 20.0;  // [N] / [N m] clamp of each force-integral term
  // true: F_m = Omega Lambda Omega a (no motion-induced force on the force axes); false: the
  // full Lambda Omega a (Khatib's dynamic decoupling, which pushes on the force axes when
  // the motion axes accelerate or carry a static error).
  bool project_motion_wrench = true;
};

Status validate(const HybridForcePositionConfig& config, std::string* why);

class HybridForcePositionController : public CartesianTorqueController {
 public:
  static Status configure(const HybridForcePositionConfig& config, RobotModelPtr model,
                          HybridForcePositionController* out, std::string* why);
  const Vector6d& force_integral() const { return integral_; }  // task frame [N; N m]

 private:
  Status law(const CartesianControlInput& in, Vector6d& F) noexcept override;
  void reset_law() noexcept override { integral_.setZero(); }  // e.g. a new contact task

  HybridForcePositionConfig config_;
  Eigen::Matrix<double, 6, 6> R6_ = Eigen::Matrix<double, 6, 6>::Identity();
  Vector6d integral_ = Vector6d::Zero();
};

}  // namespace kiloloop
