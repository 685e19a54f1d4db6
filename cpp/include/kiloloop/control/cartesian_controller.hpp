#pragma once
// The frame shared by the Cartesian torque controllers (impedance, hybrid force/position):
// configure-time sizing, the step() contract and the task-space quantities every law needs,
// computed once per tick into preallocated storage:
//   pose error e = [p_ref - p; log(R_ref R^T)],  twist x_dot = J qd,
//   operational-space inertia Lambda = (J M^-1 J^T + mu I)^-1 (mu: damping near singularities),
//   bias h = C(q, qd) qd + g(q);   the law returns a task wrench F and tau = J^T F + h.
// Bad-input policy (as the joint controllers): bad measurement (size, NaN/Inf, stale or out of
// order: MeasurementGate) -> hold:
// gravity at the last valid position (zero if none); bad reference (NaN/Inf, R_ref not a
// rotation) -> damped stop g(q) - Kd_joint qd; torques clipped to the effort limits (kSaturated).
#include <string>

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "kiloloop/control/cartesian_io.hpp"
#include "kiloloop/control/rules.hpp"
#include "kiloloop/dynamics/dynamics.hpp"

namespace kiloloop {

// Settings every Cartesian controller has.
struct CartesianCommonConfig {
  Eigen::Vector3d gravity = Eigen::Vector3d(0.0, 0.0, -9.81);  // [m/s^2] in the chain root frame
  double max_measurement_age = 0.005;  // [s] older measurements trigger the hold fallback
  // mu added to the diagonal of J M^-1 J^T (units of an inverse mass: 1/kg linear, 1/(kg m^2)
  // angular) before inverting: bounds Lambda near singularities, negligible away from them.
  double singular_damping = 1e-4;
  double stop_damping = 5.0;           // [N m s/rad] joint damping of the damped-stop fallback
};

Status validate(const CartesianCommonConfig& c, std::string* why);

class CartesianTorqueController {
 public:
  CartesianTorqueController() = default;
  CartesianTorqueController(CartesianTorqueController&&) = default;
  CartesianTorqueController& operator=(CartesianTorqueController&&) = default;
  virtual ~CartesianTorqueController() = default;

  // out.tau must have size nq (make_output()); otherwise kBadSize and out is untouched.
  // Never allocates, throws or reads a clock.
  Status step(const CartesianControlInput& in, CartesianControlOutput& out) noexcept;

  int nq() const { return dyn_.nq(); }
  CartesianControlInput make_input() const { return make_cartesian_input(nq()); }
  CartesianControlOutput make_output() const { return make_cartesian_output(nq()); }
  const StatusCounters& counters() const { return counters_; }
  // Back to the state right after configure: no last valid position, no measurement order, no
  // previous tick time, the law's own state cleared (reset_law); counters kept.
  void reset() noexcept {
    has_valid_q_ = has_last_t_ = false;
    gate_.reset();
    reset_law();
  }
  // Tip pose of the last valid measurement (root frame): handy to initialise references.
  const Eigen::Matrix4d& tip_pose() const { return T_; }

 protected:
  Status configure_common(const CartesianCommonConfig& c, RobotModelPtr model, std::string* why);
  // The law: writes the task wrench F [N; N m] from the quantities below and the input (its
  // references and measured wrench). A failed status makes step() hold.
  virtual Status law(const CartesianControlInput& in, Vector6d& F) noexcept = 0;
  // The law's own state (an integral) back to its configure value, part of reset().
  virtual void reset_law() noexcept {}

  Dynamics dyn_;
  // Filled before law() runs.
  Eigen::Matrix4d T_ = Eigen::Matrix4d::Identity();  // tip pose
  Vector6d e_ = Vector6d::Zero();                     // pose error [m; rad]
  Vector6d xd_ = Vector6d::Zero();                    // tip twist J qd
  Eigen::Matrix<double, 6, 6> Lambda_ = Eigen::Matrix<double, 6, 6>::Identity();
  double dt_ = 0.0;  // [s] time since the previous valid tick (0 on the first)

 private:
  Status task_quantities(const CartesianControlInput& in) noexcept;
  Status hold(Status why, Eigen::Ref<Eigen::VectorXd> tau) noexcept;
  Status saturate(Status s, Eigen::Ref<Eigen::VectorXd> tau) const noexcept;

  CartesianCommonConfig common_;
  Eigen::MatrixXd J_, M_, MinvJt_;  // (6,nq), (nq,nq), (nq,6)
  Eigen::LDLT<Eigen::MatrixXd> M_ldlt_;
  Eigen::LDLT<Eigen::Matrix<double, 6, 6>> A_ldlt_;
  Eigen::VectorXd h_, zero_, last_valid_q_;
  bool has_valid_q_ = false;
  double last_t_ = 0.0;
  bool has_last_t_ = false;
  MeasurementGate gate_;
  StatusCounters counters_;
  bool configured_ = false;
};

}  // namespace kiloloop
