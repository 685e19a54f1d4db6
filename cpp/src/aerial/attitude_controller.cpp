#include "kiloloop/aerial/attitude_controller.hpp"

#include <algorithm>
#include <cmath>

namespace kiloloop {

Status validate(const AttitudeControlConfig& c, std::string* why) {
  auto fail = [why](const char* msg) {
    if (why) *why = std::string("AttitudeControlConfig: ") + msg;
    return Status::kInvalidConfig;
  };
  if (c.law != AttitudeLawType::kQuaternionPd && c.law != AttitudeLawType::kGeometricSo3)
    return fail("law must be quaternion_pd or geometric_so3");
  const auto& g = c.gains;
  if (!g.kp.allFinite() || (g.kp.array() <= 0).any()) return fail("gains.kp must be > 0");
  if (!g.kd.allFinite() || (g.kd.array() < 0).any()) return fail("gains.kd must be >= 0");
  if (!g.ki.allFinite() || (g.ki.array() < 0).any()) return fail("gains.ki must be >= 0");
  if (!c.integral_limit.allFinite() || (c.integral_limit.array() < 0).any())
    return fail("integral_limit must be >= 0");
  if (!(std::isfinite(c.hysteresis) && c.hysteresis >= 0 && c.hysteresis < 1))
    return fail("hysteresis must be in [0, 1)");
  if (!(std::isfinite(c.dt) && c.dt > 0)) return fail("dt must be > 0");
  return Status::kOk;
}

Status AttitudeController::configure(const AttitudeControlConfig& config,
                                     const Eigen::Matrix3d& inertia, AttitudeController* out,
                                     std::string* why) {
  const Status s = validate(config, why);
  if (failed(s)) return s;
  if (!inertia.allFinite() || inertia.determinant() <= 0) {
    if (why) *why = "AttitudeController: inertia must be finite and positive definite";
    return Status::kInvalidConfig;
  }
  AttitudeController c;
  c.cfg_ = config;
  c.J_ = inertia;
  c.J_ldlt_.compute(inertia);
  c.quaternion_pd_ = QuaternionPdLaw(config.hysteresis);
  c.configured_ = true;
  *out = c;
  return Status::kOk;
}

AttitudeLaw* AttitudeController::active() noexcept {
  return cfg_.law == AttitudeLawType::kGeometricSo3 ? static_cast<AttitudeLaw*>(&geometric_)
                                                     : static_cast<AttitudeLaw*>(&quaternion_pd_);
}

void AttitudeController::reset() noexcept {
  quaternion_pd_.reset();
  geometric_.reset();
  integral_.setZero();
  e_R_.setZero();
}

Status AttitudeController::step(const Eigen::Quaterniond& q, const Eigen::Vector3d& omega,
                                const AttitudeTarget& target, bool saturated,
                                Eigen::Vector3d* tau) noexcept {
  tau->setZero();
  if (!configured_) return Status::kNotConfigured;
  if (!q.coeffs().allFinite() || !omega.allFinite()) return Status::kNonFiniteMeasurement;
  if (!target.q.coeffs().allFinite() || !target.omega.allFinite() ||
      !target.omega_dot.allFinite())
    return Status::kNonFiniteReference;
  active()->compute(cfg_.gains, J_, q, omega, target, integral_, &e_R_, tau);
  // Anti-windup: integrate only what the rotors delivered, and never beyond the clamp.
  if (!saturated) {
    for (int i = 0; i < 3; ++i) {
      const double ki = cfg_.gains.ki[i];
      const double bound = ki > 0 ? cfg_.integral_limit[i] / ki : 0.0;
      integral_[i] = std::clamp(integral_[i] + cfg_.dt * e_R_[i], -bound, bound);
    }
  }
  return Status::kOk;
}

}  // namespace kiloloop
