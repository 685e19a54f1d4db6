#include "kiloloop/aerial/aerial_controller.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Cholesky>
#include <kdl/frames.hpp>
#include <kdl/rigidbodyinertia.hpp>

namespace kiloloop {

namespace {

Eigen::Vector3d eig(const KDL::Vector& v) { return {v.x(), v.y(), v.z()}; }

Eigen::Matrix3d eig(const KDL::RotationalInertia& I) {
  Eigen::Matrix3d out;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) out(r, c) = I.data[3 * r + c];
  return out;
}

bool finite(double x) { return std::isfinite(x); }

// Expands a 1-or-nq gain vector to nq.
Eigen::VectorXd per_joint(const Eigen::VectorXd& g, int nq) {
  return g.size() == 1 ? Eigen::VectorXd::Constant(nq, g[0]) : g;
}

}  // namespace

Status validate(const AerialConfig& c, int nq, std::string* why) {
  auto fail = [why](const std::string& msg) {
    if (why) *why = "AerialConfig: " + msg;
    return Status::kInvalidConfig;
  };
  if (!(finite(c.dt) && c.dt > 0)) return fail("dt must be > 0");
  if (!c.gravity.allFinite() || c.gravity.norm() <= 0) return fail("gravity must be non-zero");
  for (const auto* g : {&c.arm_kp, &c.arm_kd, &c.arm_viscous, &c.arm_coulomb}) {
    if (g->size() != 1 && g->size() != nq)
      return fail("arm_kp/arm_kd/arm_viscous/arm_coulomb must have 1 or nq = " +
                  std::to_string(nq) + " entries");
    if (!g->allFinite() || (g->array() < 0).any())
      return fail("arm_kp/arm_kd/arm_viscous/arm_coulomb must be >= 0");
  }
  if (!(finite(c.arm_friction_velocity) && c.arm_friction_velocity > 0))
    return fail("arm_friction_velocity must be > 0");
  if (!(finite(c.reaction_lead) && c.reaction_lead >= 0 && c.reaction_lead <= 1.0))
    return fail("reaction_lead must be in [0, 1] s");
  if (!(finite(c.reaction_lead_filter) && c.reaction_lead_filter >= 0))
    return fail("reaction_lead_filter must be >= 0");
  if (!(finite(c.arm_friction_deadband) && c.arm_friction_deadband >= 0))
    return fail("arm_friction_deadband must be >= 0");
  if (c.arm_q_nominal.size() != 0 &&
      (c.arm_q_nominal.size() != nq || !c.arm_q_nominal.allFinite()))
    return fail("arm_q_nominal must be empty or nq finite values");
  if (!(finite(c.ik_damping) && c.ik_damping > 0)) return fail("ik_damping must be > 0");
  if (c.ik_iterations < 1 || c.ik_iterations > 50) return fail("ik_iterations must be in [1, 50]");
  if (!(finite(c.max_tilt) && c.max_tilt > 0 && c.max_tilt <= 3.14159265358979323846))
    return fail("max_tilt must be in (0, pi] rad");
  if (!(finite(c.max_measurement_age) && c.max_measurement_age > 0))
    return fail("max_measurement_age must be > 0");
  if (!(finite(c.failsafe_thrust_fraction) && c.failsafe_thrust_fraction >= 0 &&
        c.failsafe_thrust_fraction <= 1.5))
    return fail("failsafe_thrust_fraction must be in [0, 1.5]");
  Status s = validate(c.position, why);
  if (failed(s)) return s;
  s = validate(c.attitude, why);
  if (failed(s)) return s;
  return validate(c.rotors, why);
}

Status AerialController::configure(const AerialConfig& config, RobotModelPtr model,
                                   AerialController* out, std::string* why) {
  if (!model || !model->has_chain()) {
    if (why) *why = "AerialController: the model needs the arm chain (load it with tip=<ee link>)";
    return Status::kModelError;
  }
  const int nq = model->nq();
  Status s = validate(config, nq, why);
  if (failed(s)) return s;
  AerialController c;
  c.cfg_ = config;
  // One period for every part.
  c.cfg_.position.dt = c.cfg_.attitude.dt = c.cfg_.rotors.dt = config.dt;
  c.model_ = model;
  c.nq_ = nq;
  c.gravity_norm_ = config.gravity.norm();
  s = Dynamics::configure(model, config.gravity, &c.kin_, why);
  if (failed(s)) return s;
  s = FloatingBaseRne::configure(model, &c.rne_, why);
  if (failed(s)) return s;

  // The body: the chain root's own segment in the tree (the URDF loader restores its inertia).
  const auto& segments = model->tree().getSegments();
  const auto body = segments.find(model->root_name());
  if (body == segments.end()) {
    if (why) *why = "AerialController: no segment '" + model->root_name() + "' in the tree";
    return Status::kModelError;
  }
  const KDL::RigidBodyInertia& Ib = body->second.segment.getInertia();
  c.m_body_ = Ib.getMass();
  if (!(c.m_body_ > 0)) {
    if (why) *why = "AerialController: the body link '" + model->root_name() + "' has no mass";
    return Status::kModelError;
  }
  const Eigen::Vector3d com = eig(Ib.getCOG());
  if (com.norm() > 1e-6) {
    if (why) *why = "AerialController: the body link's CoM must be at its origin (the body "
                    "dynamics and the rotor geometry are written about it)";
    return Status::kModelError;
  }
  c.J_body_ = eig(Ib.getRotationalInertia());
  // The rigid vehicle: body plus the arm frozen at its nominal pose, about the body origin.
  const KDL::Chain& chain = model->chain();
  KDL::RigidBodyInertia total = Ib;
  KDL::Frame T = KDL::Frame::Identity();
  int j = 0;
  for (unsigned i = 0; i < chain.getNrOfSegments(); ++i) {
    const KDL::Segment& seg = chain.getSegment(i);
    double qi = 0.0;
    if (seg.getJoint().getType() != KDL::Joint::Fixed) {
      qi = config.arm_q_nominal.size() ? config.arm_q_nominal[j] : 0.0;
      ++j;
    }
    T = T * seg.pose(qi);
    total = total + T * seg.getInertia();
  }
  c.m_total_ = total.getMass();
  c.J_rigid_ = eig(total.getRotationalInertia());

  s = PositionController::configure(c.cfg_.position, &c.position_, why);
  if (failed(s)) return s;
  s = AttitudeController::configure(c.cfg_.attitude, c.J_body_, &c.attitude_body_, why);
  if (failed(s)) return s;
  s = AttitudeController::configure(c.cfg_.attitude, c.J_rigid_, &c.attitude_rigid_, why);
  if (failed(s)) return s;
  s = RotorAllocation::configure(c.cfg_.rotors, &c.allocation_, why);
  if (failed(s)) return s;
  if (4.0 * c.cfg_.rotors.thrust_max <= c.m_total_ * c.gravity_norm_) {
    if (why) *why = "AerialController: the rotors cannot lift the vehicle (4 thrust_max <= m g)";
    return Status::kInvalidConfig;
  }

  c.kp_ = per_joint(config.arm_kp, nq);
  c.kd_ = per_joint(config.arm_kd, nq);
  c.viscous_ = per_joint(config.arm_viscous, nq);
  c.coulomb_ = per_joint(config.arm_coulomb, nq);
  c.lower_ = model->lower();
  c.upper_ = model->upper();
  c.effort_ = model->effort_limit();
  for (auto* v : {&c.q_ref_, &c.qd_ref_, &c.qdd_ref_, &c.q_ik_, &c.qdd_cmd_, &c.tau_})
    *v = Eigen::VectorXd::Zero(nq);
  c.J_ = Eigen::MatrixXd::Zero(6, nq);
  c.T_.setIdentity();
  c.p_ref_.setZero();
  c.v_ref_.setZero();
  c.a_ref_.setZero();
  c.ee_ref_.setZero();
  c.ee_vel_ref_.setZero();
  c.reaction_z_ = (c.m_total_ - c.m_body_) * c.gravity_norm_;  // the arm hanging at rest
  {
    Eigen::Vector3d moment;
    double m_arm = 0.0;
    const Eigen::VectorXd q_nom =
        config.arm_q_nominal.size() ? config.arm_q_nominal : Eigen::VectorXd::Zero(nq);
    c.rne_.first_moment(q_nom, &moment, &m_arm);
    c.com_nominal_ = moment / c.m_total_;
  }
  c.configured_ = true;
  *out = std::move(c);
  return Status::kOk;
}

AerialInput AerialController::make_input() const {
  AerialInput in;
  for (auto* v : {&in.q, &in.qd, &in.q_ref, &in.qd_ref, &in.qdd_ref})
    *v = Eigen::VectorXd::Zero(nq_);
  return in;
}

AerialOutput AerialController::make_output() const {
  AerialOutput out;
  out.tau = Eigen::VectorXd::Zero(nq_);
  out.q_ref = Eigen::VectorXd::Zero(nq_);
  return out;
}

void AerialController::reset() noexcept {
  position_.reset();
  attitude_body_.reset();
  attitude_rigid_.reset();
  reaction_z_ = (m_total_ - m_body_) * gravity_norm_;
  reaction_tau_rate_.setZero();
  have_reaction_ = false;
  have_com_ = false;
  allocation_.reset();
  have_ref_ = have_ik_ = false;
  saturated_prev_ = false;
  safe_stop_ = false;
}

void AerialController::failsafe(AerialOutput& out, bool motors_off) noexcept {
  const auto& r = cfg_.rotors;
  const double f = motors_off ? r.thrust_min
                              : cfg_.failsafe_thrust_fraction * hover_thrust() / 4.0;
  out.thrust.setConstant(std::clamp(f, r.thrust_min, r.thrust_max));
  if (out.tau.size() == nq_) out.tau.setZero();
  out.wrench.setZero();
  out.wrench_achieved = allocation_.mixer() * out.thrust;
  out.reaction.setZero();
  out.acceleration_des.setZero();
  out.rotors_saturated = false;
  out.safe_stop = safe_stop_;
}

Status AerialController::step(const AerialInput& in, AerialOutput& out) noexcept {
  const Status s = run(in, out);
  out.status = s;
  out.safe_stop = safe_stop_;
  return s;
}

Status AerialController::load_references(const AerialInput& in) noexcept {
  const bool arm_joint = in.arm_mode == 0;
  if (arm_joint && (in.q_ref.size() != nq_ || in.qd_ref.size() != nq_ || in.qdd_ref.size() != nq_))
    return Status::kBadSize;
  bool good = in.position_ref.allFinite() && in.velocity_ref.allFinite() &&
              in.acceleration_ref.allFinite() && finite(in.yaw_ref) &&
              (in.arm_mode == 0 || in.arm_mode == 1);
  if (in.attitude_mode) good = good && in.quat_ref.allFinite() && in.quat_ref.norm() > 0.5;
  if (arm_joint) {
    good = good && in.q_ref.allFinite() && in.qd_ref.allFinite() && in.qdd_ref.allFinite();
  } else {
    good = good && in.ee_position_ref.allFinite() && in.ee_velocity_ref.allFinite();
  }
  if (!good) return Status::kNonFiniteReference;
  p_ref_ = in.position_ref;
  v_ref_ = in.velocity_ref;
  a_ref_ = in.acceleration_ref;
  yaw_ref_ = in.yaw_ref;
  attitude_mode_ = in.attitude_mode;
  if (attitude_mode_) quat_ref_ = Eigen::Quaterniond(in.quat_ref[0], in.quat_ref[1],
                                                     in.quat_ref[2], in.quat_ref[3]).normalized();
  if (arm_joint) {
    if (arm_mode_ != 0) have_ik_ = false;
    q_ref_ = in.q_ref;
    qd_ref_ = in.qd_ref;
    qdd_ref_ = in.qdd_ref;
  } else {
    ee_ref_ = in.ee_position_ref;
    ee_vel_ref_ = in.ee_velocity_ref;
  }
  arm_mode_ = in.arm_mode;
  have_ref_ = true;
  return Status::kOk;
}

// End-effector mode: damped least-squares IK on the position, in the body frame, warm-started;
// the reference velocity maps the world EE velocity relative to the moving body to the joints.
Status AerialController::arm_target(const Eigen::Matrix3d& R, const AerialInput& in) noexcept {
  const Eigen::Vector3d target = R.transpose() * (ee_ref_ - in.position);
  if (!have_ik_) {
    q_ik_ = in.q.cwiseMax(lower_).cwiseMin(upper_);
    have_ik_ = true;
  }
  const double lambda2 = cfg_.ik_damping * cfg_.ik_damping;
  Eigen::Matrix3d JJt;
  Eigen::Vector3d e = Eigen::Vector3d::Zero();
  for (int it = 0; it < cfg_.ik_iterations; ++it) {
    kin_.forward_kinematics(q_ik_, T_);
    kin_.jacobian(q_ik_, J_);
    e = target - T_.block<3, 1>(0, 3);
    JJt.noalias() = J_.topRows<3>().lazyProduct(J_.topRows<3>().transpose());
    JJt.diagonal().array() += lambda2;
    const Eigen::Vector3d y = JJt.ldlt().solve(e);
    q_ik_.noalias() += J_.topRows<3>().transpose().lazyProduct(y);
    q_ik_ = q_ik_.cwiseMax(lower_).cwiseMin(upper_);
  }
  kin_.forward_kinematics(q_ik_, T_);
  kin_.jacobian(q_ik_, J_);
  const Eigen::Vector3d p_ee = T_.block<3, 1>(0, 3);
  const Eigen::Vector3d omega = in.gyro;
  // EE velocity wanted relative to the body frame: remove the body's own motion at the EE.
  const Eigen::Vector3d v_rel =
      R.transpose() * (ee_vel_ref_ - in.velocity) - omega.cross(p_ee);
  JJt.noalias() = J_.topRows<3>().lazyProduct(J_.topRows<3>().transpose());
  JJt.diagonal().array() += lambda2;
  const Eigen::Vector3d y = JJt.ldlt().solve(v_rel);
  q_ref_ = q_ik_;
  qd_ref_.noalias() = J_.topRows<3>().transpose().lazyProduct(y);
  qdd_ref_.setZero();
  e = target - p_ee;
  return e.norm() > 10.0 * cfg_.ik_damping ? Status::kUnreachable : Status::kOk;
}

Status AerialController::run(const AerialInput& in, AerialOutput& out) noexcept {
  if (!configured_) {
    out.thrust.setZero();
    if (out.tau.size()) out.tau.setZero();
    return Status::kNotConfigured;
  }
  if (out.tau.size() != nq_ || out.q_ref.size() != nq_) {
    failsafe(out, false);
    return Status::kBadSize;
  }
  if (safe_stop_) {
    failsafe(out, true);
    return Status::kSafeStop;
  }
  // Tilt first, from any usable orientation: a vehicle past the limit stops its motors even when
  // another signal is bad at the same time (a NaN gyro must not keep it flying upside down).
  const double quat_norm = in.quat.norm();
  if (in.quat.allFinite() && quat_norm >= 0.5 && quat_norm <= 1.5) {
    const double c = (in.quat[0] * in.quat[0] - in.quat[1] * in.quat[1] - in.quat[2] * in.quat[2] +
                      in.quat[3] * in.quat[3]) / (quat_norm * quat_norm);  // R(2, 2)
    out.tilt = std::acos(std::clamp(c, -1.0, 1.0));
    if (out.tilt > cfg_.max_tilt) {
      safe_stop_ = true;
      failsafe(out, true);
      return Status::kSafeStop;
    }
  }
  if (in.q.size() != nq_ || in.qd.size() != nq_) {
    failsafe(out, false);
    return Status::kBadSize;
  }
  if (!in.position.allFinite() || !in.velocity.allFinite() || !in.quat.allFinite() ||
      !in.gyro.allFinite() || !in.accel.allFinite() || !in.q.allFinite() ||
      !in.qd.allFinite() || !finite(in.t) || !finite(in.stamp) || in.quat.norm() < 0.5 ||
      in.quat.norm() > 1.5) {
    failsafe(out, false);
    return Status::kNonFiniteMeasurement;
  }
  const double age = in.t - in.stamp;
  if (age > cfg_.max_measurement_age || age < -1e-9) {
    failsafe(out, false);
    return Status::kStaleMeasurement;
  }
  const Eigen::Quaterniond q =
      Eigen::Quaterniond(in.quat[0], in.quat[1], in.quat[2], in.quat[3]).normalized();
  const Eigen::Matrix3d R = q.toRotationMatrix();  // (the tilt was checked above)

  Status status = Status::kOk;
  const Status references = load_references(in);
  if (references != Status::kOk) {
    status = references;
    if (!have_ref_) {
      // Nothing valid yet: hold where we are, arm where it is.
      p_ref_ = in.position;
      v_ref_.setZero();
      a_ref_.setZero();
      const Eigen::Vector3d x = R.col(0);
      yaw_ref_ = std::atan2(x.y(), x.x());
      attitude_mode_ = false;
      arm_mode_ = 0;
      q_ref_ = in.q.cwiseMax(lower_).cwiseMin(upper_);
      qd_ref_.setZero();
      qdd_ref_.setZero();
      have_ref_ = true;
    }
  }

  // Arm target.
  if (arm_mode_ == 1) {
    status = worst(status, arm_target(R, in));
  } else {
    const bool outside = (q_ref_.array() < lower_.array()).any() ||
                         (q_ref_.array() > upper_.array()).any();
    if (outside) {
      q_ref_ = q_ref_.cwiseMax(lower_).cwiseMin(upper_);
      status = worst(status, Status::kReferenceClamped);
    }
  }
  out.q_ref = q_ref_;

  const bool ff = cfg_.reaction_feedforward;

  // Position loop, on the body origin or (hold_com) on the centre of mass the arm moves.
  Eigen::Vector3d p_ref = p_ref_, v_ref = v_ref_;
  if (cfg_.hold_com) {
    Eigen::Vector3d moment;
    double m_arm = 0.0;
    rne_.first_moment(q_ref_, &moment, &m_arm);
    const Eigen::Vector3d shift = moment / m_total_ - com_nominal_;  // body frame
    const Eigen::Vector3d rate =
        have_com_ ? Eigen::Vector3d((shift - com_shift_prev_) / cfg_.dt) : Eigen::Vector3d::Zero();
    com_shift_prev_ = shift;
    have_com_ = true;
    p_ref -= R * shift;
    v_ref -= R * (rate + in.gyro.cross(shift));  // d/dt (R shift), gyro = body angular rate
  }
  Eigen::Vector3d a_des;
  position_.step(in.position, in.velocity, p_ref, v_ref, a_ref_, saturated_prev_, &a_des);
  out.acceleration_des = a_des;

  // Thrust vector (world) and desired attitude. Only the vertical part of the arm's reaction
  // force joins it (last tick's: the pass below needs the attitude law's output first): the
  // horizontal part could only be produced by tilting, which is slower than the arm and is the
  // very attitude disturbance the feed-forward is meant to remove (measured in aerial-arm-sweep:
  // feeding the whole vector tilted the body more than no feed-forward at all).
  Eigen::Vector3d F = m_total_ * (a_des - cfg_.gravity);
  if (ff) {
    F = m_body_ * (a_des - cfg_.gravity);
    F.z() += reaction_z_;
  }
  AttitudeTarget target;
  double collective = 0.0;
  if (attitude_mode_) {
    target.q = quat_ref_;
    // Hold the altitude whatever the tilt: the vertical part of the thrust is what counts.
    collective = std::max(F.z(), 0.0) / std::max(R(2, 2), 0.5);
  } else {
    const Eigen::Vector3d f = position_.attitude_from_thrust(F, yaw_ref_, &target.q);
    collective = std::max(f.dot(R.col(2)), 0.0);
  }
  out.quat_des << target.q.w(), target.q.x(), target.q.y(), target.q.z();

  // Attitude law on the body alone (feed-forward on) or on the rigid vehicle (off); alpha is the
  // angular acceleration it asks of the body.
  AttitudeController& att = ff ? attitude_body_ : attitude_rigid_;
  Eigen::Vector3d tau_body;
  att.step(q, in.gyro, target, saturated_prev_, &tau_body);
  out.attitude_error = att.error();
  const Eigen::Matrix3d& J = att.inertia();
  const Eigen::Vector3d alpha = J.ldlt().solve(tau_body - in.gyro.cross(J * in.gyro));

  // One RNE pass of the arm on the body moving as measured (rates, accelerometer) and as just
  // commanded (alpha): the arm's computed torque, and the wrench the body must apply to the arm
  // for it, which the rotors add (coupled inverse dynamics: body and arm torques for the same
  // accelerations).
  qdd_cmd_ = qdd_ref_ + kd_.cwiseProduct(qd_ref_ - in.qd) + kp_.cwiseProduct(q_ref_ - in.q);
  BaseMotion base;
  base.v = R.transpose() * in.velocity;
  base.omega = in.gyro;
  base.specific_force = cfg_.measured_acceleration ? in.accel
                                                    : Eigen::Vector3d(R.transpose() *
                                                                      (a_des - cfg_.gravity));
  base.alpha = alpha;
  Vector6d W = Vector6d::Zero();
  if (failed(rne_.compute(in.q, in.qd, qdd_cmd_, base, tau_, &W))) {
    failsafe(out, false);
    return Status::kSolverFailed;
  }
  // Friction compensation (acts between arm and body: not part of the reaction).
  for (int i = 0; i < nq_; ++i) {
    const double e = q_ref_[i] - in.q[i];
    const double e_out =
        std::copysign(std::max(std::abs(e) - cfg_.arm_friction_deadband, 0.0), e);
    const double v_c = qd_ref_[i] + (kd_[i] > 0 ? kp_[i] / kd_[i] : 0.0) * e_out;
    tau_[i] += viscous_[i] * in.qd[i] +
               coulomb_[i] * std::tanh(v_c / cfg_.arm_friction_velocity);
  }
  out.reaction = W;
  reaction_z_ = (R * W.head<3>()).z();
  if (ff) {
    const Eigen::Vector3d w_tau = W.tail<3>();
    if (have_reaction_) {
      const double a = cfg_.dt / (cfg_.dt + cfg_.reaction_lead_filter);
      reaction_tau_rate_ += a * ((w_tau - reaction_tau_prev_) / cfg_.dt - reaction_tau_rate_);
    }
    reaction_tau_prev_ = w_tau;
    have_reaction_ = true;
    tau_body += w_tau + cfg_.reaction_lead * reaction_tau_rate_;
  }

  Eigen::Vector4d wrench;
  wrench << collective, tau_body;
  out.wrench = wrench;
  const Status alloc = allocation_.allocate(wrench, &out.thrust, &out.wrench_achieved);
  saturated_prev_ = alloc == Status::kSaturated;
  out.rotors_saturated = saturated_prev_;
  status = worst(status, alloc);

  // Arm torques within the effort limits.
  bool clipped = false;
  for (int i = 0; i < nq_; ++i) {
    const double t = std::clamp(tau_[i], -effort_[i], effort_[i]);
    clipped = clipped || t != tau_[i];
    out.tau[i] = t;
  }
  if (clipped) status = worst(status, Status::kSaturated);
  kin_.forward_kinematics(in.q, T_);
  out.ee_position = in.position + R * T_.block<3, 1>(0, 3);
  return status;
}

}  // namespace kiloloop
