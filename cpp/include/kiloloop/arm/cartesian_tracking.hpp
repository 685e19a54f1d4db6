#pragma once
// CartesianTrackingController: a Cartesian reference (pose, twist, its derivative) tracked at
// 1 kHz through differential IK, then joint computed torque. Used by the `arm-line` scenario
// (a CartesianLine reference), but any Cartesian reference works.
//
// Differential IK (closed-loop inverse kinematics, Siciliano's CLIK) on an internal joint
// reference q_r, integrated once per tick:
//   e   = [p_ref - p(q_r); log(R_ref R(q_r)^T)]                          (6)  [m; rad]
//   qd_r = J^T (J J^T + lambda^2 I)^-1 (twist_ref + K e)                 (nq) [rad/s]
//   lambda^2 = lambda_max^2 (1 - w / w0)^2 if w < w0 else 0,  w = sqrt(det(J J^T))
// (damping only near singularities, Nakamura & Hanafusa / Chiaverini, so tracking is exact
// elsewhere). qd_r is scaled down as a whole to the joint velocity limits (status kSaturated),
// q_r + qd_r dt is clamped to the position limits, qdd_r is the backward difference of qd_r.
// (q_r, qd_r, qdd_r) go to the ComputedTorqueController with the measured (q, qd).
//
// The first valid tick (and the first after reset()) starts q_r at the measured q. Bad
// Cartesian reference (NaN/Inf, or pose_ref not rigid: bottom row not 0 0 0 1, rotation not
// orthonormal with det +1): q_r holds still (qd_r = qdd_r = 0), status kNonFiniteReference. Bad
// measurement: the computed torque controller's hold fallback. A q_r that overflowed (huge
// references on joints without position limits) restarts at the next valid measurement.
// step() is noexcept and allocation-free.
#include <string>

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "kiloloop/control/computed_torque.hpp"
#include "kiloloop/kinematics/chain_kinematics.hpp"

namespace kiloloop {

struct CartesianTrackingConfig {
  ComputedTorqueConfig joint;                  // inner joint loop (gains, gravity, max age)
  double dt = 0.001;                           // [s] tick period (q_r integration step)
  Vector6d task_gain = Vector6d::Constant(50.0);  // [1/s] K, CLIK error feedback per axis
  double singular_threshold = 1e-3;            // w0 [m^3] manipulability below which to damp
  double max_damping = 0.05;                   // lambda_max [m] at w = 0
};

Status validate(const CartesianTrackingConfig& config, int nq, std::string* why);

struct CartesianTrackingInput {
  double t = 0.0;                  // [s] controller time of this tick
  double stamp = 0.0;              // [s] when q, qd were sampled
  Eigen::VectorXd q;               // (nq) [rad] measured position
  Eigen::VectorXd qd;              // (nq) [rad/s] measured velocity
  Eigen::Matrix4d pose_ref = Eigen::Matrix4d::Identity();  // T_root_tip reference [m]
  Vector6d twist_ref = Vector6d::Zero();  // [m/s; rad/s] root frame
};

struct CartesianTrackingOutput {
  Eigen::VectorXd tau;     // (nq) [N m] always finite and within effort limits
  Eigen::VectorXd q_ref;   // (nq) [rad] joint reference from differential IK
  Eigen::VectorXd qd_ref;  // (nq) [rad/s]
  Eigen::VectorXd qdd_ref; // (nq) [rad/s^2]
  Vector6d task_error = Vector6d::Zero();  // [m; rad] e of q_r (before this tick's update)
  double manipulability = 0.0;             // w = sqrt(det(J J^T)) at q_r
  Status status = Status::kNotConfigured;
};

class CartesianTrackingController {
 public:
  static Status configure(const CartesianTrackingConfig& config, RobotModelPtr model,
                          CartesianTrackingController* out, std::string* why);

  Status step(const CartesianTrackingInput& in, CartesianTrackingOutput& out) noexcept;
  // Restarts q_r at the next valid measurement and forgets the measurement order.
  void reset() noexcept {
    started_ = false;
    joint_.reset();
  }

  int nq() const { return nq_; }
  CartesianTrackingInput make_input() const;
  CartesianTrackingOutput make_output() const;
  // The statuses this step returned (the inner joint controller counts its own).
  const StatusCounters& counters() const { return counters_; }

 private:
  CartesianTrackingConfig config_;
  int nq_ = 0;
  Status run(const CartesianTrackingInput& in, CartesianTrackingOutput& out) noexcept;

  ChainKinematics kin_;
  ComputedTorqueController joint_;
  JointControlInput joint_in_;
  JointControlOutput joint_out_;
  Eigen::VectorXd lower_, upper_, vmax_;
  Eigen::VectorXd q_r_, qd_r_, qd_prev_;  // (nq) integrator state
  Eigen::MatrixXd J_;                     // (6, nq)
  Eigen::Matrix<double, 6, 6> JJt_;
  Eigen::LDLT<Eigen::Matrix<double, 6, 6>> ldlt_;
  StatusCounters counters_;
  bool started_ = false;
};

}  // namespace kiloloop
