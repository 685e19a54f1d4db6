#pragma once
// Native SIL adapter of arm-press (python/kiloloop/scenarios/arm_press.py): a Cartesian torque
// controller (hybrid force/position or impedance) pressing down with a constant force while its
// reference slides along x on a quintic. The tool's force comes from the measurement, so the
// loop needs no Python per tick:
//   y = [q (nq); qd (nq); f_site (3); quat (4)]   plant joint order; f_site: the tool's MuJoCo
//       force sensor [N] in its site frame; quat (w, x, y, z): a framequat sensor on that site
//       (world <- site), so f = R(quat) f_site is the force the tool applies, world frame
//   u = tau (nq)
// Logs x_ref, force (3, world) [N], tau, status and q.
#include <Eigen/Core>

#include "kiloloop/control/cartesian_controller.hpp"
#include "sil/adapter.hpp"

namespace kiloloop::sil {

// The slide along x: at rest at p0.x until `settle`, then a rest-to-rest quintic of `slide` [m]
// over `slide_time` [s], held at its end.
struct PressSlide {
  Eigen::Vector3d p0 = Eigen::Vector3d::Zero();  // [m] tip start, chain root frame
  double settle = 0.0;                           // [s]
  double slide = 0.0;                            // [m] along +x
  double slide_time = 1.0;                       // [s] > 0
  // x [m], xd [m/s], xdd [m/s^2] of the reference at t [s].
  void sample(double t, double* x, double* xd, double* xdd) const noexcept;
};

// World force [N] from a site-frame force and the site's orientation quaternion (w, x, y, z),
// as arm_scene.tip_force_world does with site_xmat.
Eigen::Vector3d site_force_to_world(const double* f_site, const double* quat) noexcept;

class PressAdapter final : public Adapter {
 public:
  // controller: borrowed (the binding keeps its Python object alive); R0: orientation reference
  // (root frame); force [N]: pressed downwards (wrench_ref z = -force).
  PressAdapter(CartesianTorqueController* controller, const PressSlide& slide, const Eigen::Matrix3d& R0,
               double force);
  int measurement_size() const override { return 2 * nq_ + 7; }
  int command_size() const override { return nq_; }
  void declare(LogBuffer& log) override;
  int step(double t, double stamp, const double* y, double* u, LogBuffer& log, int k) noexcept override;

 private:
  CartesianTorqueController* c_;
  int nq_;
  PressSlide slide_;
  CartesianControlInput in_;
  CartesianControlOutput out_;
  int ch_x_ref_ = 0, ch_force_ = 0, ch_tau_ = 0, ch_status_ = 0, ch_q_ = 0;
};

}  // namespace kiloloop::sil
