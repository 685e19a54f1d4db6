#include "kiloloop/control/cartesian_controller.hpp"

#include <cmath>

#include <Eigen/Geometry>

#include "kiloloop/kinematics/rigid_check.hpp"

namespace kiloloop {

CartesianControlInput make_cartesian_input(int nq) {
  CartesianControlInput in;
  in.q = in.qd = Eigen::VectorXd::Zero(nq);
  return in;
}

CartesianControlOutput make_cartesian_output(int nq) {
  CartesianControlOutput out;
  out.tau = Eigen::VectorXd::Zero(nq);
  return out;
}

Status validate(const CartesianCommonConfig& c, std::string* why) {
  const char* msg = nullptr;
  if (!c.gravity.allFinite()) msg = "gravity must be finite";
  else if (!(c.max_measurement_age > 0.0)) msg = "max_measurement_age must be > 0";
  else if (!(c.singular_damping >= 0.0) || !std::isfinite(c.singular_damping))
    msg = "singular_damping must be finite and >= 0";
  else if (!(c.stop_damping >= 0.0) || !std::isfinite(c.stop_damping))
    msg = "stop_damping must be finite and >= 0";
  if (msg == nullptr) return Status::kOk;
  if (why) *why = msg;
  return Status::kInvalidConfig;
}

Status CartesianTorqueController::configure_common(const CartesianCommonConfig& c,
                                                   RobotModelPtr model, std::string* why) {
  if (!model) {
    if (why) *why = "model is null";
    return Status::kModelError;
  }
  Status s = validate(c, why);
  if (failed(s)) return s;
  s = Dynamics::configure(model, c.gravity, &dyn_, why);
  if (failed(s)) return s;
  const int n = dyn_.nq();
  common_ = c;
  J_ = Eigen::MatrixXd::Zero(6, n);
  M_ = Eigen::MatrixXd::Identity(n, n);
  MinvJt_ = Eigen::MatrixXd::Zero(n, 6);
  // Eigen's LDLT leaves its info field unset until compute(): moving one that never computed
  // reads it (UBSan: invalid enum load). Computing both here also sizes M_ldlt_'s storage once.
  M_ldlt_.compute(M_);
  A_ldlt_.compute(Eigen::Matrix<double, 6, 6>::Identity());
  h_ = zero_ = last_valid_q_ = Eigen::VectorXd::Zero(n);
  has_valid_q_ = has_last_t_ = false;
  gate_ = MeasurementGate(c.max_measurement_age);
  counters_ = StatusCounters{};
  configured_ = true;
  return Status::kOk;
}

Status CartesianTorqueController::task_quantities(const CartesianControlInput& in) noexcept {
  Status s = dyn_.forward_kinematics(in.q, T_);
  if (s == Status::kOk) s = dyn_.jacobian(in.q, J_);
  if (s == Status::kOk) s = dyn_.mass_matrix(in.q, M_);
  if (s == Status::kOk) s = dyn_.inverse_dynamics(in.q, in.qd, zero_, h_);  // C qd + g
  if (s != Status::kOk) return Status::kSolverFailed;
  // Pose error: position difference and the rotation vector of R_ref R^T (root frame).
  e_.head<3>() = in.p_ref - T_.block<3, 1>(0, 3);
  const Eigen::Matrix3d R_err = in.R_ref * T_.block<3, 3>(0, 0).transpose();
  const Eigen::AngleAxisd aa(R_err);
  e_.tail<3>() = aa.angle() * aa.axis();
  xd_.noalias() = J_ * in.qd;
  // Lambda = (J M^-1 J^T + mu I)^-1, both factorizations in preallocated storage.
  M_ldlt_.compute(M_);
  if (M_ldlt_.info() != Eigen::Success) return Status::kSolverFailed;
  MinvJt_ = J_.transpose();
  M_ldlt_.solveInPlace(MinvJt_);
  Eigen::Matrix<double, 6, 6> A;
  A.noalias() = J_ * MinvJt_;
  A.diagonal().array() += common_.singular_damping;
  A_ldlt_.compute(A);
  if (A_ldlt_.info() != Eigen::Success) return Status::kSolverFailed;
  Lambda_.setIdentity();
  A_ldlt_.solveInPlace(Lambda_);
  return Lambda_.allFinite() && e_.allFinite() ? Status::kOk : Status::kSolverFailed;
}

Status CartesianTorqueController::hold(Status why, Eigen::Ref<Eigen::VectorXd> tau) noexcept {
  if (!has_valid_q_ || failed(dyn_.gravity(last_valid_q_, tau))) tau.setZero();
  saturate(why, tau);
  return why;
}

Status CartesianTorqueController::saturate(Status s, Eigen::Ref<Eigen::VectorXd> tau) const noexcept {
  return clip_effort(s, tau, dyn_.model().effort_limit());
}

Status CartesianTorqueController::step(const CartesianControlInput& in,
                                       CartesianControlOutput& out) noexcept {
  if (!configured_) return out.status = Status::kNotConfigured;
  const int n = dyn_.nq();
  Status s = Status::kOk;
  if (out.tau.size() != n) {
    s = Status::kBadSize;  // nowhere safe to write: report only
  } else if (in.q.size() != n || in.qd.size() != n) {
    s = hold(Status::kBadSize, out.tau);
  } else if (!in.q.allFinite() || !in.qd.allFinite()) {
    s = hold(Status::kNonFiniteMeasurement, out.tau);
  } else if (const Status age = gate_.check(in.t, in.stamp); failed(age)) {
    s = hold(age, out.tau);  // old, from the future, or older than one already used
  } else {
    gate_.accept(in.stamp);
    last_valid_q_ = in.q;
    has_valid_q_ = true;
    if (!in.p_ref.allFinite() || !is_rotation(in.R_ref) || !in.twist_ref.allFinite() ||
        !in.accel_ref.allFinite() || !in.wrench_ref.allFinite()) {
      // Damped stop at the measured state: g(q) - Kd qd.
      if (failed(dyn_.gravity(in.q, out.tau))) out.tau.setZero();
      out.tau.noalias() -= common_.stop_damping * in.qd;
      saturate(Status::kNonFiniteReference, out.tau);  // clip only: the status is the reason
      s = Status::kNonFiniteReference;
    } else if (const Status tq = task_quantities(in); failed(tq)) {
      s = hold(tq, out.tau);
    } else {
      dt_ = has_last_t_ ? in.t - last_t_ : 0.0;
      if (!(dt_ >= 0.0) || dt_ > 1.0) dt_ = 0.0;  // time went backwards or jumped: no integration
      Vector6d F;
      const Status l = law(in, F);
      if (failed(l) || !F.allFinite()) {
        s = hold(failed(l) ? l : Status::kSolverFailed, out.tau);
      } else {
        out.tau.noalias() = J_.transpose() * F;
        out.tau += h_;
        if (!out.tau.allFinite()) {
          s = hold(Status::kSolverFailed, out.tau);  // a finite wrench whose torque overflows
        } else {
          out.pose_error = e_;
          out.wrench_command = F;
          s = saturate(l, out.tau);
        }
      }
      last_t_ = in.t;
      has_last_t_ = true;
    }
  }
  counters_.record(s);
  return out.status = s;
}

}  // namespace kiloloop
