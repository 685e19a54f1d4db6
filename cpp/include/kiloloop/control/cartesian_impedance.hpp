#pragma once
// Cartesian impedance control (Hogan 1985; Ott 2008, "Cartesian Impedance Control of Redundant
// and Flexible-Joint Robots", ch. 3): the tip behaves as a mass-spring-damper about the
// reference pose,
//   F = Lambda(q) a_ref + K e + D (twist_ref - J qd),   tau = J^T F + C(q,qd) qd + g(q),
// so that without a reference acceleration, at rest, an external wrench F_ext displaces the tip
// by K^-1 F_ext (the spring), and the closed loop is Lambda x_tilde'' + D x_tilde' + K x_tilde
// = F_ext with the arm's own operational-space inertia Lambda as the mass (no force sensing
// needed). D is set per axis from a damping ratio, D_i = 2 zeta sqrt(K_i Lambda_ii), recomputed
// each tick (Lambda changes with q). The J_dot qd term is neglected (small at the speeds here).
#include <string>

#include "kiloloop/control/cartesian_controller.hpp"

namespace kiloloop {

struct CartesianImpedanceConfig {
  CartesianCommonConfig common;  // what every Cartesian controller has (gravity, limits, nullspace)
  Vector6d stiffness = (Vector6d() << 800.0, 800.0, 800.0, 60.0, 60.0, 60.0).finished();  // [N/m; N m/rad]
  double damping_ratio = 1.0;  // zeta: 1 = critically damped per axis
};

Status validate(const CartesianImpedanceConfig& config, std::string* why);

class CartesianImpedanceController : public CartesianTorqueController {
 public:
  static Status configure(const CartesianImpedanceConfig& config, RobotModelPtr model,
                          CartesianImpedanceController* out, std::string* why);

 private:
  Status law(const CartesianControlInput& in, Vector6d& F) noexcept override;

  CartesianImpedanceConfig config_;
};

}  // namespace kiloloop
