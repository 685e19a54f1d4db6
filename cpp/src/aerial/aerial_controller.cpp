#include "kiloloop/aerial/aerial_controller.hpp"
#include "kiloloop/model/kdl_eigen.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

#include <Eigen/Cholesky>
#include <kdl/frames.hpp>
#include <kdl/rigidbodyinertia.hpp>
#include <kdl/tree.hpp>

namespace kiloloop {

namespace {

Eigen::Matrix3d eig(const KDL::RotationalInertia& I) {
  Eigen::Matrix3d out;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) out(r, c) = I.data[3 * r + c];
  return out;
}

bool finite(double x) { return std::isfinite(x); }

// [m], [m/s], [rad/s]...: a finite value this large in a state or a reference can only be a
// fault (and would overflow the loops' products to Inf).
constexpr double kSane = 1e6;
template <typename V>
bool sane(const V& v) {
  return v.allFinite() && v.cwiseAbs().maxCoeff() <= kSane;
}
bool sane(double x) { return std::isfinite(x) && std::abs(x) <= kSane; }

// The rigid composite of the tree below `element` (its own segment included), in the frame of
// `T` (the element's tip frame expressed in the base frame); the subtree starting at the
// segment named `skip` (the arm) is left out. Joints off the arm are taken at 0.
void add_subtree(const KDL::SegmentMap::const_iterator& element, const KDL::Frame& T,
                 const std::string& skip, KDL::RigidBodyInertia* total) {
  *total = *total + T * element->second.segment.getInertia();
  for (const auto& child : GetTreeElementChildren(element->second)) {
    if (child->first == skip) continue;
    add_subtree(child, T * child->second.segment.pose(0.0), skip, total);
  }
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
  if (!model) {
    if (why) *why = "AerialController: no model";
    return Status::kModelError;
  }
  const bool has_arm = model->has_chain() && model->chain().getNrOfSegments() > 0;
  const int nq = has_arm ? model->nq() : 0;
  Status s = validate(config, nq, why);
  if (failed(s)) return s;
  AerialController c;
  c.cfg_ = config;
  // One period for every part.
  c.cfg_.position.dt = c.cfg_.attitude.dt = c.cfg_.rotors.dt = config.dt;
  c.model_ = model;
  c.nq_ = nq;
  c.has_arm_ = has_arm;
  c.gravity_norm_ = config.gravity.norm();
  if (has_arm) {
    if (nq > 0) {
      s = Dynamics::configure(model, config.gravity, &c.kin_, why);
      if (failed(s)) return s;
    }
    s = FloatingBaseRne::configure(model, &c.rne_, why);
    if (failed(s)) return s;
  }

  // The body: the base link and every link rigidly attached to it off the arm, in the base frame.
  const auto& segments = model->tree().getSegments();
  const std::string base =
      has_arm || !model->root_name().empty() ? model->root_name()
                                             : model->tree().getRootSegment()->first;
  const auto root = segments.find(base);
  if (root == segments.end()) {
    if (why) *why = "AerialController: no segment '" + base + "' in the tree";
    return Status::kModelError;
  }
  const std::string arm_first = has_arm ? model->chain().getSegment(0).getName() : std::string();
  KDL::RigidBodyInertia Ib = KDL::RigidBodyInertia::Zero();
  add_subtree(root, KDL::Frame::Identity(), arm_first, &Ib);
  c.m_body_ = Ib.getMass();
  if (!(c.m_body_ > 0)) {
    if (why) *why = "AerialController: the body link '" + base + "' has no mass";
    return Status::kModelError;
  }
  c.c_body_ = to_eigen(Ib.getCOG());
  c.J_body_ = eig(Ib.RefPoint(to_kdl(c.c_body_)).getRotationalInertia());
  // The rigid vehicle: body plus the arm frozen at its nominal pose, about the body CoM.
  KDL::RigidBodyInertia total = Ib;
  if (has_arm) {
    const KDL::Chain& chain = model->chain();
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
  }
  c.m_total_ = total.getMass();
  c.c_vehicle_ = to_eigen(total.getCOG());
  c.J_rigid_ = eig(total.RefPoint(to_kdl(c.c_body_)).getRotationalInertia());

  s = PositionController::configure(c.cfg_.position, &c.position_, why);
  if (failed(s)) return s;
  s = AttitudeController::configure(c.cfg_.attitude, c.J_body_, &c.attitude_body_, why);
  if (failed(s)) return s;
  s = AttitudeController::configure(c.cfg_.attitude, c.J_rigid_, &c.attitude_rigid_, why);
  if (failed(s)) return s;
  // The rotor geometry about the body's centre of mass.
  c.cfg_.rotors.positions = config.rotors.positions.colwise() - c.c_body_;
  s = RotorAllocation::configure(c.cfg_.rotors, &c.allocation_, why);
  if (failed(s)) return s;
  if (c.allocation_.max_collective() <= c.m_total_ * c.gravity_norm_) {
    if (why)
      *why = "AerialController: the rotors cannot lift the vehicle (largest collective thrust " +
             std::to_string(c.allocation_.max_collective()) + " N <= m g = " +
             std::to_string(c.m_total_ * c.gravity_norm_) + " N)";
    return Status::kInvalidConfig;
  }
  // Failsafe: the collective share of the failsafe fraction of the hover thrust, per rotor.
  c.failsafe_thrust_ = c.allocation_.collective_share() *
                       (config.failsafe_thrust_fraction * c.m_total_ * c.gravity_norm_);
  for (int i = 0; i < c.allocation_.n(); ++i)
    c.failsafe_thrust_[i] = std::clamp(c.failsafe_thrust_[i], c.cfg_.rotors.thrust_min,
                                       c.allocation_.thrust_max()[i]);

  // Per-joint gains (control/rules.hpp; validate() checked their sizes and signs).
  broadcast_gains(config.arm_kp, nq, &c.kp_);
  broadcast_gains(config.arm_kd, nq, &c.kd_);
  broadcast_gains(config.arm_viscous, nq, &c.viscous_);
  broadcast_gains(config.arm_coulomb, nq, &c.coulomb_);
  c.lower_ = has_arm ? model->lower() : Eigen::VectorXd();
  c.upper_ = has_arm ? model->upper() : Eigen::VectorXd();
  c.effort_ = has_arm ? model->effort_limit() : Eigen::VectorXd();
  for (auto* v : {&c.q_ref_, &c.qd_ref_, &c.qdd_ref_, &c.q_ik_, &c.qdd_cmd_, &c.tau_, &c.moment_q_})
    *v = Eigen::VectorXd::Zero(nq);
  c.J_ = Eigen::MatrixXd::Zero(6, nq);
  c.T_.setIdentity();
  c.tip_.setZero();
  c.p_ref_.setZero();
  c.v_ref_.setZero();
  c.a_ref_.setZero();
  c.ee_ref_.setZero();
  c.ee_vel_ref_.setZero();
  c.reaction_z_ = (c.m_total_ - c.m_body_) * c.gravity_norm_;  // the arm hanging at rest
  if (has_arm) {
    Eigen::Vector3d moment;
    double m_arm = 0.0;
    const Eigen::VectorXd q_nom =
        config.arm_q_nominal.size() ? config.arm_q_nominal : Eigen::VectorXd::Zero(nq);
    c.rne_.first_moment(q_nom, &moment, &m_arm);
    c.com_nominal_ = moment / c.m_total_;
  }
  c.gate_ = MeasurementGate(config.max_measurement_age);
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
  out.thrust = Eigen::VectorXd::Zero(allocation_.n());
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
  have_moment_ = false;
  allocation_.reset();
  have_ref_ = have_ik_ = false;
  saturated_prev_ = false;
  safe_stop_ = false;
  gate_.reset();
}

// Any output vector, of any size: rotors at the failsafe (or off), arm torques zero.
void AerialController::failsafe(AerialOutput& out, bool motors_off) noexcept {
  const bool sized = out.thrust.size() == allocation_.n();
  if (sized && !motors_off) {
    out.thrust = failsafe_thrust_;
  } else {
    out.thrust.setConstant(cfg_.rotors.thrust_min);
  }
  out.tau.setZero();
  out.wrench.setZero();
  if (sized) {
    out.wrench_achieved.noalias() = allocation_.mixer() * out.thrust;
  } else {
    out.wrench_achieved.setZero();
  }
  out.reaction.setZero();
  out.acceleration_des.setZero();
  out.rotors_saturated = false;
  out.safe_stop = safe_stop_;
}

Status AerialController::step(const AerialInput& in, AerialOutput& out) noexcept {
  Status s = check_measurements(in, out);
  if (!failed(s)) {
    tick_.status = Status::kOk;
    load_references(in);
    arm_reference(in, out);
    position_loop(in, out);
    thrust_and_attitude(in, out);
    s = arm_dynamics(in, out);
    if (!failed(s)) {
      allocate(out);
      const Status torques = arm_output(in, out);
      s = worst(tick_.status, guard_output(out, torques));
    }
  }
  out.status = s;
  out.safe_stop = safe_stop_;
  counters_.record(s);
  return s;
}

Status AerialController::check_measurements(const AerialInput& in, AerialOutput& out) noexcept {
  if (!configured_) {
    out.thrust.setZero();
    out.tau.setZero();
    return Status::kNotConfigured;
  }
  if (out.thrust.size() != allocation_.n() || out.tau.size() != nq_ || out.q_ref.size() != nq_) {
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
  const bool quat_usable = in.quat.allFinite() && quat_norm >= 0.5 && quat_norm <= 1.5;
  if (quat_usable) {
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
  if (!quat_usable || !sane(in.position) || !sane(in.velocity) || !sane(in.gyro) ||
      !sane(in.accel) || !in.q.allFinite() || !in.qd.allFinite() ||
      (nq_ > 0 && (in.q.cwiseAbs().maxCoeff() > kSane || in.qd.cwiseAbs().maxCoeff() > kSane)) ||
      !sane(in.t) || !sane(in.stamp)) {
    failsafe(out, false);
    return Status::kNonFiniteMeasurement;
  }
  const Status age = gate_.check(in.t, in.stamp);  // control/rules.hpp: age and order
  if (failed(age)) {
    failsafe(out, false);
    return age;
  }
  gate_.accept(in.stamp);
  tick_.q = Eigen::Quaterniond(in.quat[0], in.quat[1], in.quat[2], in.quat[3]).normalized();
  tick_.R = tick_.q.toRotationMatrix();
  return Status::kOk;
}

Status AerialController::accept_references(const AerialInput& in) noexcept {
  const bool arm_joint = in.arm_mode == ArmMode::kJoints;
  if (arm_joint && (in.q_ref.size() != nq_ || in.qd_ref.size() != nq_ || in.qdd_ref.size() != nq_))
    return Status::kBadSize;
  const bool attitude = in.flight_mode == FlightMode::kAttitude;
  bool good = sane(in.position_ref) && sane(in.velocity_ref) && sane(in.acceleration_ref) &&
              sane(in.yaw_ref) && (arm_joint || in.arm_mode == ArmMode::kEndEffector) &&
              (attitude || in.flight_mode == FlightMode::kPosition);
  if (attitude) good = good && in.quat_ref.allFinite() && in.quat_ref.norm() > 0.5 &&
                       in.quat_ref.norm() < 2.0;
  if (arm_joint) {
    good = good && (nq_ == 0 || (sane(in.q_ref) && sane(in.qd_ref) && sane(in.qdd_ref)));
  } else {
    good = good && has_arm_ && nq_ > 0 && sane(in.ee_position_ref) && sane(in.ee_velocity_ref);
  }
  if (!good) return Status::kNonFiniteReference;
  p_ref_ = in.position_ref;
  v_ref_ = in.velocity_ref;
  a_ref_ = in.acceleration_ref;
  yaw_ref_ = in.yaw_ref;
  flight_mode_ = in.flight_mode;
  if (attitude) quat_ref_ = Eigen::Quaterniond(in.quat_ref[0], in.quat_ref[1], in.quat_ref[2],
                                               in.quat_ref[3]).normalized();
  if (arm_joint) {
    if (arm_mode_ != ArmMode::kJoints) have_ik_ = false;
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

void AerialController::load_references(const AerialInput& in) noexcept {
  const Status references = accept_references(in);
  if (references == Status::kOk) return;
  tick_.status = worst(tick_.status, references);
  if (have_ref_) return;
  // Nothing valid yet: hold where we are, arm where it is.
  p_ref_ = in.position;
  v_ref_.setZero();
  a_ref_.setZero();
  const Eigen::Vector3d x = tick_.R.col(0);
  yaw_ref_ = std::atan2(x.y(), x.x());
  flight_mode_ = FlightMode::kPosition;
  arm_mode_ = ArmMode::kJoints;
  q_ref_ = in.q.cwiseMax(lower_).cwiseMin(upper_);
  qd_ref_.setZero();
  qdd_ref_.setZero();
  have_ref_ = true;
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

void AerialController::arm_reference(const AerialInput& in, AerialOutput& out) noexcept {
  if (arm_mode_ == ArmMode::kEndEffector) {
    tick_.status = worst(tick_.status, arm_target(tick_.R, in));
  } else if (nq_ > 0) {
    const bool outside = (q_ref_.array() < lower_.array()).any() ||
                         (q_ref_.array() > upper_.array()).any();
    if (outside) {
      q_ref_ = q_ref_.cwiseMax(lower_).cwiseMin(upper_);
      tick_.status = worst(tick_.status, Status::kReferenceClamped);
    }
  }
  out.q_ref = q_ref_;
}

// Position loop, on the body origin or (hold_com) on the centre of mass the arm moves.
void AerialController::position_loop(const AerialInput& in, AerialOutput& out) noexcept {
  const Eigen::Matrix3d& R = tick_.R;
  Eigen::Vector3d p_ref = p_ref_, v_ref = v_ref_;
  if (cfg_.hold_com && has_arm_) {
    const Eigen::Vector3d shift = arm_moment_at_reference() / m_total_ - com_nominal_;  // body frame
    const Eigen::Vector3d rate =
        have_com_ ? Eigen::Vector3d((shift - com_shift_prev_) / cfg_.dt) : Eigen::Vector3d::Zero();
    com_shift_prev_ = shift;
    have_com_ = true;
    p_ref -= R * shift;
    v_ref -= R * (rate + in.gyro.cross(shift));  // d/dt (R shift), gyro = body angular rate
  }
  position_.step(in.position, in.velocity, p_ref, v_ref, a_ref_, saturated_prev_, &tick_.a_des);
  out.acceleration_des = tick_.a_des;
}

// The arm's first moment (m c, body frame) at q_ref, recomputed only when q_ref changed (bit for
// bit): a held arm reference (hover, a set point) costs a compare of nq doubles a tick instead
// of a forward pass.
const Eigen::Vector3d& AerialController::arm_moment_at_reference() noexcept {
  // memcmp, not ==: -0.0 and 0.0 differ here as they may in the pass's rounding. Never with a
  // null pointer (nq 0: a rigid payload has no joints and no data).
  const size_t bytes = sizeof(double) * static_cast<size_t>(nq_);
  const bool same = have_moment_ && (bytes == 0 || std::memcmp(moment_q_.data(), q_ref_.data(), bytes) == 0);
  if (!same) {
    double m_arm = 0.0;
    rne_.first_moment(q_ref_, &moment_, &m_arm);
    moment_q_ = q_ref_;
    have_moment_ = true;
  }
  return moment_;
}

// Thrust vector (world) and desired attitude, then the attitude law. Only the vertical part of
// the arm's reaction force joins the thrust (last tick's: the pass below needs the attitude
// law's output first): the horizontal part could only be produced by tilting, which is slower
// than the arm and is the very attitude disturbance the feed-forward is meant to remove
// (measured in aerial-arm-sweep: feeding the whole vector tilted the body more than no
// feed-forward at all).
void AerialController::thrust_and_attitude(const AerialInput& in, AerialOutput& out) noexcept {
  const bool ff = cfg_.reaction_feedforward;
  const Eigen::Matrix3d& R = tick_.R;
  Eigen::Vector3d F = m_total_ * (tick_.a_des - cfg_.gravity);
  if (ff) {
    F = m_body_ * (tick_.a_des - cfg_.gravity);
    F.z() += reaction_z_;
  }
  AttitudeTarget target;
  if (flight_mode_ == FlightMode::kAttitude) {
    target.q = quat_ref_;
    // Hold the altitude whatever the tilt: the vertical part of the thrust is what counts.
    tick_.collective = std::max(F.z(), 0.0) / std::max(R(2, 2), 0.5);
  } else {
    const Eigen::Vector3d f = position_.attitude_from_thrust(F, yaw_ref_, &target.q);
    tick_.collective = std::max(f.dot(R.col(2)), 0.0);
  }
  tick_.q_des = target.q;
  out.quat_des << target.q.w(), target.q.x(), target.q.y(), target.q.z();

  // Attitude law on the body alone (feed-forward on) or on the rigid vehicle (off); alpha is the
  // angular acceleration it asks of the body.
  AttitudeController& att = ff ? attitude_body_ : attitude_rigid_;
  att.step(tick_.q, in.gyro, target, saturated_prev_, &tick_.tau_body);
  out.attitude_error = att.error();
  const Eigen::Matrix3d& J = att.inertia();
  tick_.alpha = att.inertia_ldlt().solve(tick_.tau_body - in.gyro.cross(J * in.gyro));
  if (!ff) {
    // The rigid vehicle's centre of mass is not the body's when the arm (at nominal) sits off
    // its axis: the collective, through the body CoM, would twist the vehicle about its own CoM
    // by (c_vehicle - c_body) x T z; the rotors add that moment (zero for an arm hanging on the
    // thrust axis).
    tick_.tau_body += (c_vehicle_ - c_body_).cross(Eigen::Vector3d(0.0, 0.0, tick_.collective));
  }
}

// One RNE pass of the arm on the body moving as measured (rates, accelerometer) and as just
// commanded (alpha): the arm's computed torque, and the wrench the body must apply to the arm
// for it, which the rotors add (coupled inverse dynamics: body and arm torques for the same
// accelerations).
Status AerialController::arm_dynamics(const AerialInput& in, AerialOutput& out) noexcept {
  tick_.W.setZero();
  out.reaction.setZero();
  if (!has_arm_) return Status::kOk;
  const Eigen::Matrix3d& R = tick_.R;
  qdd_cmd_ = qdd_ref_ + kd_.cwiseProduct(qd_ref_ - in.qd) + kp_.cwiseProduct(q_ref_ - in.q);
  BaseMotion base;
  base.v = R.transpose() * in.velocity;
  base.omega = in.gyro;
  base.specific_force = cfg_.measured_acceleration
                            ? in.accel
                            : Eigen::Vector3d(R.transpose() * (tick_.a_des - cfg_.gravity));
  base.alpha = tick_.alpha;
  if (failed(rne_.compute(in.q, in.qd, qdd_cmd_, base, tau_, &tick_.W, &tip_))) {
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
  out.reaction = tick_.W;
  reaction_z_ = (R * tick_.W.head<3>()).z();
  if (cfg_.reaction_feedforward) {
    // About the body CoM: the body applies W at the base origin, c_body away.
    const Eigen::Vector3d w_tau = tick_.W.tail<3>() - c_body_.cross(tick_.W.head<3>());
    if (have_reaction_) {
      const double a = cfg_.dt / (cfg_.dt + cfg_.reaction_lead_filter);
      reaction_tau_rate_ += a * ((w_tau - reaction_tau_prev_) / cfg_.dt - reaction_tau_rate_);
    }
    reaction_tau_prev_ = w_tau;
    have_reaction_ = true;
    tick_.tau_body += w_tau + cfg_.reaction_lead * reaction_tau_rate_;
  }
  return Status::kOk;
}

void AerialController::allocate(AerialOutput& out) noexcept {
  tick_.wrench << tick_.collective, tick_.tau_body;
  out.wrench = tick_.wrench;
  const Status alloc = allocation_.allocate(tick_.wrench, out.thrust, &out.wrench_achieved);
  saturated_prev_ = alloc == Status::kSaturated;
  out.rotors_saturated = saturated_prev_;
  tick_.status = worst(tick_.status, alloc);
}

// Arm torques within the effort limits; the end effector where the state puts it.
Status AerialController::arm_output(const AerialInput& in, AerialOutput& out) noexcept {
  out.tau = tau_;
  const Status torques = clip_effort(Status::kOk, out.tau, effort_);  // control/rules.hpp
  if (!failed(torques)) tick_.status = worst(tick_.status, torques);
  if (nq_ > 0) {
    out.ee_position = in.position + tick_.R * tip_;  // at in.q, from arm_dynamics' pass
  } else {
    out.ee_position = in.position;
  }
  return torques;
}

// The contract's last line: whatever happened above, the output is finite and the arm torques
// were (NaN arm torques were once possible from overflowing references; clip_effort zeroes them
// and fails); otherwise the failsafe.
Status AerialController::guard_output(AerialOutput& out, Status torques) noexcept {
  if (!failed(torques) && out.thrust.allFinite() && out.tau.allFinite() && out.wrench.allFinite())
    return Status::kOk;
  failsafe(out, false);
  return Status::kSolverFailed;
}

}  // namespace kiloloop
