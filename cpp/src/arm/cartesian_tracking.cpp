#include "kiloloop/arm/cartesian_tracking.hpp"

#include <cmath>

#include <Eigen/LU>

#include "kiloloop/kinematics/rigid_check.hpp"

namespace kiloloop {

Status validate(const CartesianTrackingConfig& c, int nq, std::string* why) {
  auto fail = [why](const char* msg) {
    if (why) *why = msg;
    return Status::kInvalidConfig;
  };
  if (!(c.dt > 0.0) || !std::isfinite(c.dt)) return fail("dt must be finite and > 0");
  if (!c.task_gain.allFinite() || (c.task_gain.array() < 0.0).any())
    return fail("task_gain must be finite and >= 0");
  if (c.task_gain.maxCoeff() * c.dt >= 1.0)
    return fail("task_gain * dt must be < 1 (the discrete CLIK loop is unstable otherwise)");
  if (!(c.singular_threshold > 0.0) || !std::isfinite(c.singular_threshold))
    return fail("singular_threshold must be finite and > 0");
  if (!(c.max_damping >= 0.0) || !std::isfinite(c.max_damping))
    return fail("max_damping must be finite and >= 0");
  return validate(c.joint, nq, why);
}

Status CartesianTrackingController::configure(const CartesianTrackingConfig& config,
                                              RobotModelPtr model,
                                              CartesianTrackingController* out, std::string* why) {
  if (!model) {
    if (why) *why = "model is null";
    return Status::kModelError;
  }
  Status s = validate(config, model->nq(), why);
  if (failed(s)) return s;
  CartesianTrackingController c;
  c.config_ = config;
  s = ChainKinematics::configure(*model, &c.kin_, why);
  if (failed(s)) return s;
  s = ComputedTorqueController::configure(config.joint, model, &c.joint_, why);
  if (failed(s)) return s;
  c.nq_ = model->nq();
  c.lower_ = model->lower();
  c.upper_ = model->upper();
  c.vmax_ = model->velocity_limit();
  c.joint_in_ = make_joint_input(c.nq_);
  c.joint_out_ = make_joint_output(c.nq_);
  c.q_r_ = c.qd_r_ = c.qd_prev_ = Eigen::VectorXd::Zero(c.nq_);
  c.J_ = Eigen::MatrixXd::Zero(6, c.nq_);
  // An LDLT that never computed has no info value: moving it is undefined (UBSan).
  c.ldlt_.compute(Eigen::Matrix<double, 6, 6>::Identity());
  *out = std::move(c);
  return Status::kOk;
}

CartesianTrackingInput CartesianTrackingController::make_input() const {
  CartesianTrackingInput in;
  in.q = in.qd = Eigen::VectorXd::Zero(nq_);
  return in;
}

CartesianTrackingOutput CartesianTrackingController::make_output() const {
  CartesianTrackingOutput out;
  out.tau = out.q_ref = out.qd_ref = out.qdd_ref = Eigen::VectorXd::Zero(nq_);
  return out;
}

Status CartesianTrackingController::step(const CartesianTrackingInput& in,
                                         CartesianTrackingOutput& out) noexcept {
  if (nq_ == 0) return out.status = Status::kNotConfigured;
  const Status s = run(in, out);
  counters_.record(s);
  return s;
}

Status CartesianTrackingController::run(const CartesianTrackingInput& in,
                                        CartesianTrackingOutput& out) noexcept {
  if (out.tau.size() != nq_ || out.q_ref.size() != nq_ || out.qd_ref.size() != nq_ ||
      out.qdd_ref.size() != nq_)
    return out.status = Status::kBadSize;  // nowhere safe to write
  JointControlInput& j = joint_in_;
  j.t = in.t;
  j.stamp = in.stamp;
  Status ik = Status::kOk;
  const bool measured = in.q.size() == nq_ && in.qd.size() == nq_ && in.q.allFinite() &&
                        in.qd.allFinite();
  if (measured) {
    j.q = in.q;
    j.qd = in.qd;
  } else {
    // The joint controller sees the bad measurement and applies its hold fallback.
    if (in.q.size() == nq_ && in.qd.size() == nq_) {
      j.q = in.q;
      j.qd = in.qd;
    } else {
      j.q.setConstant(std::numeric_limits<double>::quiet_NaN());
    }
  }
  if (!started_ && measured) {
    q_r_ = in.q.cwiseMax(lower_).cwiseMin(upper_);
    qd_prev_.setZero();
    started_ = true;
  }
  // A non-rigid pose_ref (bottom row, non-orthonormal R) is as unusable as a NaN one.
  const bool reference_ok = is_rigid_transform(in.pose_ref) && in.twist_ref.allFinite();
  Eigen::Isometry3d T;
  kin_.forward_jacobian(q_r_, T, J_);
  JJt_.noalias() = J_ * J_.transpose();
  const double det = JJt_.determinant();
  out.manipulability = det > 0.0 ? std::sqrt(det) : 0.0;
  if (!started_ || !reference_ok) {
    qd_r_.setZero();
    ik = reference_ok ? Status::kOk : Status::kNonFiniteReference;
    out.task_error.setZero();
  } else {
    Eigen::Isometry3d T_ref;
    T_ref.matrix() = in.pose_ref;
    out.task_error = pose_error(T_ref, T);
    const Vector6d v = in.twist_ref + config_.task_gain.cwiseProduct(out.task_error);
    // Damped least squares, damping only near a singularity.
    const double w = out.manipulability, w0 = config_.singular_threshold;
    const double l2 = w < w0 ? std::pow(config_.max_damping * (1.0 - w / w0), 2) : 0.0;
    JJt_.diagonal().array() += l2 + 1e-12;
    ldlt_.compute(JJt_);
    const Vector6d y = ldlt_.solve(v);
    qd_r_.noalias() = J_.transpose() * y;
    // Uniform scaling keeps the Cartesian direction when a joint would exceed its speed.
    double scale = 1.0;
    for (int i = 0; i < nq_; ++i) {
      const double a = std::abs(qd_r_[i]);
      if (a > vmax_[i]) scale = std::min(scale, vmax_[i] / a);
    }
    if (scale < 1.0) {
      qd_r_ *= scale;
      ik = Status::kSaturated;
    }
    if (!qd_r_.allFinite()) {
      qd_r_.setZero();
      ik = Status::kNonFiniteReference;
    }
  }
  j.q_ref = q_r_;
  j.qd_ref = qd_r_;
  // Backward difference while tracking; a held reference is at rest.
  if (started_ && reference_ok) {
    j.qdd_ref = (qd_r_ - qd_prev_) / config_.dt;
  } else {
    j.qdd_ref.setZero();
  }
  out.q_ref = j.q_ref;
  out.qd_ref = j.qd_ref;
  out.qdd_ref = j.qdd_ref;
  Status js = joint_.step(j, joint_out_);
  // A wrong-size measurement reached the joint controller as NaN (its q cannot be resized here).
  if (js == Status::kNonFiniteMeasurement && (in.q.size() != nq_ || in.qd.size() != nq_))
    js = Status::kBadSize;
  out.tau = joint_out_.tau;
  // Integrate the reference for the next tick (only while tracking a valid reference).
  if (started_) {
    q_r_ = (q_r_ + qd_r_ * config_.dt).cwiseMax(lower_).cwiseMin(upper_);
    qd_prev_ = qd_r_;
    if (!q_r_.allFinite()) {  // restart from the next valid measurement; finite until then
      q_r_ = Eigen::VectorXd::Zero(nq_).cwiseMax(lower_).cwiseMin(upper_);
      started_ = false;
    }
  }
  return out.status = worst(ik, js);
}

}  // namespace kiloloop
