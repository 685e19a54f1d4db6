#include "kiloloop/aerial/position_controller.hpp"

#include <algorithm>
#include <cmath>

namespace kiloloop {

Status validate(const PositionControlConfig& c, std::string* why) {
  auto fail = [why](const char* msg) {
    if (why) *why = std::string("PositionControlConfig: ") + msg;
    return Status::kInvalidConfig;
  };
  if (!c.kp.allFinite() || (c.kp.array() < 0).any()) return fail("kp must be >= 0");
  if (!c.kd.allFinite() || (c.kd.array() < 0).any()) return fail("kd must be >= 0");
  if (!c.ki.allFinite() || (c.ki.array() < 0).any()) return fail("ki must be >= 0");
  if (!c.integral_limit.allFinite() || (c.integral_limit.array() < 0).any())
    return fail("integral_limit must be >= 0");
  if (!(std::isfinite(c.max_tilt) && c.max_tilt > 0 && c.max_tilt < 1.5))
    return fail("max_tilt must be in (0, 1.5) rad");
  if (!(std::isfinite(c.dt) && c.dt > 0)) return fail("dt must be > 0");
  return Status::kOk;
}

Status PositionController::configure(const PositionControlConfig& config,
                                      PositionController* out, std::string* why) {
  const Status s = validate(config, why);
  if (failed(s)) return s;
  PositionController c;
  c.cfg_ = config;
  c.tan_max_tilt_ = std::tan(config.max_tilt);
  c.configured_ = true;
  *out = c;
  return Status::kOk;
}

Status PositionController::step(const Eigen::Vector3d& p, const Eigen::Vector3d& v,
                                const Eigen::Vector3d& p_ref, const Eigen::Vector3d& v_ref,
                                const Eigen::Vector3d& a_ref, bool saturated,
                                Eigen::Vector3d* a_des) noexcept {
  a_des->setZero();
  if (!configured_) return Status::kNotConfigured;
  if (!p.allFinite() || !v.allFinite()) return Status::kNonFiniteMeasurement;
  if (!p_ref.allFinite() || !v_ref.allFinite() || !a_ref.allFinite())
    return Status::kNonFiniteReference;
  const Eigen::Vector3d e = p_ref - p;
  if (!saturated) {
    for (int i = 0; i < 3; ++i) {
      const double ki = cfg_.ki[i];
      const double bound = ki > 0 ? cfg_.integral_limit[i] / ki : 0.0;
      integral_[i] = std::clamp(integral_[i] + cfg_.dt * e[i], -bound, bound);
    }
  }
  *a_des = a_ref + cfg_.kp.cwiseProduct(e) + cfg_.kd.cwiseProduct(v_ref - v) +
           cfg_.ki.cwiseProduct(integral_);
  return Status::kOk;
}

Eigen::Vector3d PositionController::attitude_from_thrust(const Eigen::Vector3d& F, double yaw,
                                                         Eigen::Quaterniond* q_des) const noexcept {
  // Keep a positive vertical part (a multirotor cannot pull down) and shorten the horizontal one
  // to the tilt limit.
  Eigen::Vector3d f = F;
  f.z() = std::max(f.z(), 1e-3);
  const double horizontal = std::hypot(f.x(), f.y());
  const double limit = f.z() * tan_max_tilt_;
  if (horizontal > limit) {
    f.x() *= limit / horizontal;
    f.y() *= limit / horizontal;
  }
  const Eigen::Vector3d z = f.normalized();
  const Eigen::Vector3d x_c(std::cos(yaw), std::sin(yaw), 0.0);
  // z is never horizontal (tilt < 90 deg), so z x x_c never vanishes.
  const Eigen::Vector3d y = z.cross(x_c).normalized();
  const Eigen::Vector3d x = y.cross(z);
  Eigen::Matrix3d R;
  R.col(0) = x;
  R.col(1) = y;
  R.col(2) = z;
  *q_des = Eigen::Quaterniond(R);
  return f;
}

}  // namespace kiloloop
