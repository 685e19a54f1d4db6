#include "kiloloop/control/cartesian_impedance.hpp"

#include <cmath>

namespace kiloloop {

Status validate(const CartesianImpedanceConfig& c, std::string* why) {
  const Status s = validate(c.common, why);
  if (failed(s)) return s;
  const char* msg = nullptr;
  if (!c.stiffness.allFinite() || (c.stiffness.array() < 0.0).any()) msg = "stiffness must be finite and >= 0";
  else if (!(c.damping_ratio >= 0.0) || !std::isfinite(c.damping_ratio)) msg = "damping_ratio must be finite and >= 0";
  if (msg == nullptr) return Status::kOk;
  if (why) *why = msg;
  return Status::kInvalidConfig;
}

Status CartesianImpedanceController::configure(const CartesianImpedanceConfig& config,
                                               RobotModelPtr model, CartesianImpedanceController* out,
                                               std::string* why) {
  Status s = validate(config, why);
  if (failed(s)) return s;
  CartesianImpedanceController c;
  s = c.configure_common(config.common, std::move(model), why);
  if (failed(s)) return s;
  c.config_ = config;
  *out = std::move(c);
  return Status::kOk;
}

Status CartesianImpedanceController::law(const CartesianControlInput& in, Vector6d& F) noexcept {
  const Vector6d& K = config_.stiffness;
  F.noalias() = Lambda_ * in.accel_ref;
  for (int i = 0; i < 6; ++i) {
    const double D = 2.0 * config_.damping_ratio * std::sqrt(K[i] * std::fmax(Lambda_(i, i), 0.0));
    F[i] += K[i] * e_[i] + D * (in.twist_ref[i] - xd_[i]);
  }
  return Status::kOk;
}

}  // namespace kiloloop
