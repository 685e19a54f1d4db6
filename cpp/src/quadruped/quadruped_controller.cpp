#include "kiloloop/quadruped/quadruped_controller.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/LU>

#include "kiloloop/trajectory/swing_trajectory.hpp"

namespace kiloloop {
namespace {

constexpr double kGravity = 9.81;

bool finite_input(const QuadrupedInput& in) {
  return std::isfinite(in.t) && std::isfinite(in.stamp) && in.q.allFinite() && in.qd.allFinite() &&
         in.gyro.allFinite() && in.accel.allFinite() && in.quat.allFinite() && in.quat.norm() > 0.5;
}

Eigen::Quaterniond to_quat(const Eigen::Vector4d& wxyz) {
  return Eigen::Quaterniond(wxyz[0], wxyz[1], wxyz[2], wxyz[3]).normalized();
}

Eigen::Vector4d to_wxyz(const Eigen::Quaterniond& q) { return {q.w(), q.x(), q.y(), q.z()}; }

double yaw_of(const Eigen::Quaterniond& q) {
  return std::atan2(2.0 * (q.w() * q.z() + q.x() * q.y()), 1.0 - 2.0 * (q.y() * q.y() + q.z() * q.z()));
}

double approach(double from, double to, double step) {
  return from + std::clamp(to - from, -step, step);
}

}  // namespace

Status QuadrupedController::configure(const QuadrupedConfig& config, RobotModelPtr model,
                                      QuadrupedController* out, std::string* why) {
  auto fail = [&](const std::string& msg, Status s = Status::kInvalidConfig) {
    if (why) *why = msg;
    return s;
  };
  if (!model) return fail("model is null", Status::kModelError);
  if (!(config.dt > 0) || !(config.body_height > 0) || !(config.trust_ramp >= 0) ||
      !(config.load_ramp >= 0) || !(config.max_position_lag >= 0) || !(config.swing_height >= 0) ||
      !(config.max_tilt > 0) || !(config.max_measurement_age > 0) || !(config.foot_radius >= 0))
    return fail("quadruped config: dt, body_height, max_tilt, max_measurement_age must be > 0; "
                "swing_height, foot_radius, trust_ramp, load_ramp, max_position_lag >= 0");
  QuadrupedController c;
  c.cfg_ = config;
  c.model_ = model;
  for (int i = 0; i < kLegs; ++i) {
    LegGeometry g;
    const Status s = leg_geometry_from_model(*model, config.trunk_link, config.feet[i], &g, why);
    if (failed(s)) return s;
    c.legs_[i] = LegKinematics(g);
    const Status sg = LegGravity::configure(*model, config.trunk_link, config.feet[i], &c.leg_gravity_[i], why);
    if (failed(sg)) return sg;
    KDL::Chain chain;
    model->tree().getChain(config.trunk_link, config.feet[i], chain);
    int j = 0;
    for (const auto& seg : chain.segments) {
      if (seg.getJoint().getType() == KDL::Joint::None) continue;
      const std::string& name = seg.getJoint().getName();
      c.joint_names_[3 * i + j] = name;
      const auto& names = model->joint_names();
      const auto it = std::find(names.begin(), names.end(), name);
      c.effort_[3 * i + j] = model->effort_limit()[it - names.begin()];
      ++j;
    }
  }
  // Mass and inertia for the trunk wrench: the whole robot's mass; the trunk's own inertia plus
  // each leg's mass lumped at mid-leg (legs are light, their exact distribution matters little).
  c.mass_ = config.mass > 0 ? config.mass : model->total_mass();
  const auto trunk = model->tree().getSegment(config.trunk_link);
  KDL::RigidBodyInertia I = GetTreeElementSegment(trunk->second).getInertia();
  const KDL::RotationalInertia Ic = I.RefPoint(I.getCOG()).getRotationalInertia();
  Eigen::Matrix3d inertia = Eigen::Map<const Eigen::Matrix3d>(Ic.data);
  const double leg_mass = (c.mass_ - I.getMass()) / kLegs;
  // Whole-robot CoM in the trunk frame with every leg in the standing pose (the legs' mass sits
  // behind the hips with knees pointing back: the wrench must act about this point).
  Eigen::Vector3d moment = I.getMass() * Eigen::Vector3d(I.getCOG().x(), I.getCOG().y(), I.getCOG().z());
  double mass_sum = I.getMass();
  for (int i = 0; i < kLegs; ++i) {
    KDL::Chain chain;
    model->tree().getChain(config.trunk_link, config.feet[i], chain);
    KDL::Frame T = KDL::Frame::Identity();
    int j = 0;
    for (const auto& seg : chain.segments) {
      const double qj = seg.getJoint().getType() == KDL::Joint::None ? 0.0 : config.stand_pose[j++];
      T = T * seg.pose(qj);
      const KDL::Vector cog = T * seg.getInertia().getCOG();
      moment += seg.getInertia().getMass() * Eigen::Vector3d(cog.x(), cog.y(), cog.z());
      mass_sum += seg.getInertia().getMass();
    }
  }
  c.com_ = moment / mass_sum;
  for (const auto& leg : c.legs_) {
    const LegGeometry& g = leg.geometry();
    const Eigen::Vector3d r = g.abd_origin + Eigen::Vector3d(0, g.l_abd, -0.5 * g.l_thigh);
    inertia += leg_mass * (r.squaredNorm() * Eigen::Matrix3d::Identity() - r * r.transpose());
  }
  c.inertia_ = config.inertia_diag.isZero() ? inertia : Eigen::Matrix3d(config.inertia_diag.asDiagonal());
  if (failed(c.gait_.configure(config.gait))) return fail("gait: need period > 0, 0.5 < duty < 1");
  if (!(config.contact.force_on > config.contact.force_off))
    return fail("contact: force_on must exceed force_off");
  c.contacts_.configure(config.contact);
  EstimatorConfig est = config.estimator;
  est.dt = config.dt;
  c.estimator_.configure(est);
  Status s = StanceForceQp::configure(config.force, &c.force_qp_, why);
  if (failed(s)) return s;
  for (auto& q : c.q_leg_valid_) q = config.stand_pose;
  c.configured_ = true;
  *out = std::move(c);
  return Status::kOk;
}

Status QuadrupedController::step(const QuadrupedInput& in, QuadrupedOutput& out) noexcept {
  if (!configured_) return out.status = Status::kNotConfigured;
  out.status = run(in, out);
  return out.status;
}

void QuadrupedController::safe_output(const QuadrupedInput& in, Vector12d& tau) const noexcept {
  for (int i = 0; i < kLegs; ++i) {
    const Eigen::Vector3d q = in.q.segment<3>(3 * i), qd = in.qd.segment<3>(3 * i);
    const Eigen::Vector3d t = q.allFinite() && qd.allFinite()
                                  ? Eigen::Vector3d(cfg_.safe_kp * (cfg_.crouch - q) - cfg_.safe_kd * qd)
                                  : Eigen::Vector3d::Zero();
    tau.segment<3>(3 * i) = t;
  }
}

void QuadrupedController::saturate(Vector12d& tau, Status* status) const noexcept {
  bool clipped = false;
  for (int i = 0; i < 12; ++i) {
    const double v = std::isfinite(tau[i]) ? tau[i] : 0.0;
    const double c = std::clamp(v, -effort_[i], effort_[i]);
    clipped |= c != tau[i];
    tau[i] = c;
  }
  if (clipped) *status = worst(*status, Status::kSaturated);
}

Status QuadrupedController::run(const QuadrupedInput& in, QuadrupedOutput& out) noexcept {
  // 1. Inputs. Bad sensors: hold the last command (a glitch must not drop the robot).
  const double age = in.t - in.stamp;
  if (!finite_input(in) || age > cfg_.max_measurement_age || age < -cfg_.max_measurement_age) {
    const Status why = finite_input(in) ? Status::kStaleMeasurement : Status::kNonFiniteMeasurement;
    if (have_output_) out.tau = tau_prev_;
    else safe_output(in, out.tau);
    Status ignored = why;
    saturate(out.tau, &ignored);
    return why;
  }
  Status status = Status::kOk;
  Eigen::Vector3d command = in.velocity_command;
  Gait requested = in.gait == 1 ? Gait::kTrot : Gait::kStand;
  if (!command.allFinite() || (in.gait != 0 && in.gait != 1)) {
    command.setZero();
    requested = Gait::kStand;
    status = Status::kNonFiniteReference;
  }

  // 2. Leg kinematics in the trunk frame.
  std::array<LegMeasurement, kLegs> meas;
  std::array<Eigen::Matrix3d, kLegs> J;
  std::array<Eigen::Vector3d, kLegs> tau_gravity;
  const Eigen::Quaterniond q_imu_now = to_quat(in.quat);
  const Eigen::Vector3d g_trunk = q_imu_now.conjugate() * Eigen::Vector3d(0, 0, -kGravity);
  for (int i = 0; i < kLegs; ++i) {
    const Eigen::Vector3d q = in.q.segment<3>(3 * i);
    meas[i].r = legs_[i].foot_position(q);
    J[i] = legs_[i].jacobian(q);
    meas[i].v_rel = J[i] * in.qd.segment<3>(3 * i);
    tau_gravity[i] = leg_gravity_[i].torque(q, g_trunk);
  }
  // A spherical foot rolls: its contact point (radius below the centre, along the ground normal)
  // stands still, not its centre. Add the rolling term to what the estimator takes as the
  // stance-foot velocity: v_rel = J qd + (w_shank + w_trunk) x c, c = contact point - centre.
  {
    const Eigen::Vector3d c = -cfg_.foot_radius * (q_imu_now.conjugate() * estimator_.ground_normal());
    for (int i = 0; i < kLegs; ++i) {
      const double q0 = in.q[3 * i], pitch_rate = in.qd[3 * i + 1] + in.qd[3 * i + 2];
      const Eigen::Vector3d w_shank(in.qd[3 * i], std::cos(q0) * pitch_rate, std::sin(q0) * pitch_rate);
      meas[i].v_rel += (w_shank + in.gyro).cross(c);
    }
  }
  const Eigen::Quaterniond& q_imu = q_imu_now;
  if (!estimator_.initialised()) {
    estimator_.reset(q_imu, meas, cfg_.foot_radius);
    p_des_ = estimator_.position();
    yaw_des_ = yaw_of(estimator_.orientation());
  }

  // 3. Gait schedule, then contacts from the normal force that the last command implies.
  gait_.update(in.t, requested);
  const auto& schedule = gait_.legs();
  const Eigen::Matrix3d R_prev = estimator_.rotation();
  const Eigen::Vector3d n_prev = estimator_.ground_normal();
  const Eigen::Vector3d p_prev = estimator_.position();
  std::array<double, kLegs> normal_force{}, clearance{};
  for (int i = 0; i < kLegs; ++i) {
    // Foot sphere's distance above the estimated ground plane (last tick's trunk pose).
    const Eigen::Vector3d foot = p_prev + R_prev * meas[i].r;
    clearance[i] = (foot.z() - estimator_.ground_height(foot.x(), foot.y())) * n_prev.z() - cfg_.foot_radius;
    // Static leg: tau = tau_g - J^T f  =>  f = J^-T (tau_g - tau) (trunk frame), skipped near
    // singular poses.
    const Eigen::Matrix3d Jt = J[i].transpose();
    if (std::abs(Jt.determinant()) > 1e-6) {
      const Eigen::Vector3d f = Jt.partialPivLu().solve(tau_gravity[i] - tau_prev_.segment<3>(3 * i));
      normal_force[i] = n_prev.dot(R_prev * f);
    }
  }
  contacts_.update(schedule, normal_force, clearance);
  out.foot_clearance = Eigen::Vector4d(clearance[0], clearance[1], clearance[2], clearance[3]);
  for (int i = 0; i < kLegs; ++i) {
    meas[i].contact = contacts_.contact(i);
    meas[i].touched_down = contacts_.touched_down(i);
    contact_time_[i] = meas[i].touched_down ? 0.0 : std::min(contact_time_[i] + cfg_.dt, 1e3);
    const double until_liftoff = schedule[i].stance ? schedule[i].remaining : 0.0;
    meas[i].trust = cfg_.trust_ramp > 0
                        ? std::clamp(std::min(contact_time_[i], until_liftoff) / cfg_.trust_ramp, 0.0, 1.0)
                        : 1.0;
  }

  // 4. State estimate (or ground truth when debugging).
  status = worst(status, estimator_.update(in.gyro, in.accel, q_imu, meas));
  if (in.use_ground_truth)
    estimator_.set_truth(in.true_position, in.true_velocity, to_quat(in.true_quat));
  const Eigen::Matrix3d R = estimator_.rotation();
  const Eigen::Vector3d p = estimator_.position(), v = estimator_.velocity();
  const Eigen::Vector3d w_body = estimator_.angular_velocity();
  out.tilt = std::acos(std::clamp(R(2, 2), -1.0, 1.0));
  out.position = p;
  out.velocity = v;
  out.quat = to_wxyz(estimator_.orientation());
  out.ground_normal = estimator_.ground_normal();
  for (int i = 0; i < kLegs; ++i) {
    out.contact[i] = contacts_.contact(i);
    out.scheduled[i] = schedule[i].stance;
  }

  // 5. Safety: a tilt beyond the limit latches the safe stop in this very tick.
  if (safe_stop_ || out.tilt > cfg_.max_tilt) {
    safe_stop_ = true;
    out.safe_stop = true;
    safe_output(in, out.tau);
    Status ignored = Status::kSafeStop;
    saturate(out.tau, &ignored);
    tau_prev_ = out.tau;
    have_output_ = true;
    return Status::kSafeStop;
  }
  out.safe_stop = false;

  // 6. Ramped command and the desired trunk motion (level trunk, commanded heading).
  const double dv = cfg_.max_acceleration * cfg_.dt;
  for (int k = 0; k < 3; ++k) v_cmd_[k] = approach(v_cmd_[k], command[k], dv);
  yaw_des_ += v_cmd_.z() * cfg_.dt;
  const double yaw = yaw_of(estimator_.orientation());
  const Eigen::Vector3d v_des(std::cos(yaw) * v_cmd_.x() - std::sin(yaw) * v_cmd_.y(),
                              std::sin(yaw) * v_cmd_.x() + std::cos(yaw) * v_cmd_.y(), 0.0);
  p_des_.head<2>() += v_des.head<2>() * cfg_.dt;
  // Keep the position target within reach, so a push does not wind it up.
  const Eigen::Vector2d lag = p_des_.head<2>() - p.head<2>();
  if (lag.norm() > cfg_.max_position_lag)
    p_des_.head<2>() = p.head<2>() + cfg_.max_position_lag * lag.normalized();
  p_des_.z() = estimator_.ground_height(p.x(), p.y()) + cfg_.body_height;

  // 7. Desired wrench about the CoM (world axes). Height is measured by the legs in contact
  // (trunk above the feet), which does not drift the way an integrated estimate does.
  std::array<bool, kLegs> stance{};
  std::array<double, kLegs> load{};
  int n_stance = 0;
  for (int i = 0; i < kLegs; ++i) {
    stance[i] = schedule[i].stance && contacts_.contact(i);
    n_stance += stance[i];
    // Time since the scheduled touch-down (standing counts as long ago).
    stance_time_[i] = schedule[i].stance ? std::min(stance_time_[i] + cfg_.dt, 1e3) : 0.0;
    load[i] = cfg_.load_ramp > 0
                  ? std::clamp(std::min(stance_time_[i], schedule[i].remaining) / cfg_.load_ramp, 0.0, 1.0)
                  : 1.0;
  }
  // Feedback acts on the state predicted one actuation delay ahead, when the command lands.
  const double tau_d = cfg_.actuation_delay;
  Eigen::Vector3d e_p = p_des_ - (p + tau_d * v);
  double height = tau_d * v.z();
  for (int i = 0; i < kLegs; ++i)
    if (stance[i]) height += -(R * meas[i].r).z();
  if (n_stance > 0) {
    height = height / n_stance + cfg_.foot_radius / std::max(estimator_.ground_normal().z(), 0.5);
    e_p.z() = cfg_.body_height - height;
  }
  const Eigen::Vector3d e_v = v_des - v;
  const Eigen::Quaterniond q_des(Eigen::AngleAxisd(yaw_des_, Eigen::Vector3d::UnitZ()));
  const Eigen::Vector3d half_turn = 0.5 * tau_d * w_body;
  const Eigen::Quaterniond q_pred =
      (estimator_.orientation() * Eigen::Quaterniond(1.0, half_turn.x(), half_turn.y(), half_turn.z()))
          .normalized();
  Eigen::Quaterniond q_err = q_des * q_pred.conjugate();  // world frame error
  if (q_err.w() < 0) q_err.coeffs() = -q_err.coeffs();  // shortest path
  const Eigen::Vector3d e_R_body = R.transpose() * (2.0 * q_err.vec());
  const Eigen::Vector3d w_des_body = R.transpose() * Eigen::Vector3d(0, 0, v_cmd_.z());
  Vector6d wrench;
  wrench.head<3>() = mass_ * (cfg_.kp_position.cwiseProduct(e_p) + cfg_.kd_velocity.cwiseProduct(e_v) +
                              Eigen::Vector3d(0, 0, kGravity));
  wrench.tail<3>() = R * (inertia_ * (cfg_.kp_orientation.cwiseProduct(e_R_body) +
                                      cfg_.kd_angular.cwiseProduct(w_des_body - w_body)));

  // 8. Swing legs (and stance legs still looking for the ground): foothold, swing, IK, joint PD.
  // Their motors push back on the trunk: the abduction and hip-pitch torques beyond gravity
  // compensation are a moment on the trunk that the stance feet must cancel (measured: the swing
  // legs' reaction pitched the trunk ~1.2 deg each step at 0.5 m/s).
  const double t_swing = gait_.swing_duration(), t_stance = gait_.stance_duration();
  Eigen::Vector3d swing_reaction = Eigen::Vector3d::Zero();  // trunk frame [N m]
  for (int i = 0; i < kLegs; ++i) {
    if (stance[i]) continue;
    const Eigen::Vector3d q = in.q.segment<3>(3 * i), qd = in.qd.segment<3>(3 * i);
    const LegGeometry& g = legs_[i].geometry();
    const LegPhase& ph = schedule[i];
    Eigen::Vector3d p_foot, v_foot;
    if (!ph.stance) {
      if (was_stance_[i]) swing_start_[i] = p + R * meas[i].r;  // lift-off point
      // Raibert foothold: at mid-stance under the hip moved to the CoM's x (so that the diagonal
      // support line passes through the CoM), shifted against the velocity error.
      const Eigen::Vector3d hip =
          p + R * (g.abd_origin + Eigen::Vector3d(com_.x() + cfg_.foothold_shift.x(),
                                                  g.l_abd + cfg_.foothold_shift.y(), 0));
      Eigen::Vector3d target = hip + v * ph.remaining + 0.5 * t_stance * v_des +
                               cfg_.raibert_gain * (v - v_des);
      target.z() = estimator_.ground_height(target.x(), target.y()) + cfg_.foot_radius -
                   cfg_.touchdown_depth;
      swing_target_[i] = target;
      const SwingSample s = sample_swing(swing_start_[i], target, cfg_.swing_height, ph.progress, t_swing);
      p_foot = s.p;
      v_foot = s.v;
      late_time_[i] = 0.0;
    } else {
      // Scheduled on the ground but no contact yet: keep reaching down until the foot finds it.
      if (was_stance_[i]) swing_target_[i] = p + R * meas[i].r;  // never swung: start from here
      late_time_[i] += cfg_.dt;
      p_foot = swing_target_[i] - Eigen::Vector3d(0, 0, 0.3 * late_time_[i]);
      v_foot = Eigen::Vector3d(0, 0, -0.3);
    }
    was_stance_[i] = false;
    const Eigen::Vector3d r_des = R.transpose() * (p_foot - p);
    Eigen::Vector3d q_des = q_leg_valid_[i];
    if (legs_[i].inverse(r_des, q_des) == Status::kOk) q_leg_valid_[i] = q_des;
    else status = worst(status, Status::kUnreachable);
    const Eigen::Vector3d v_rel = R.transpose() * (v_foot - v) - w_body.cross(r_des);
    const Eigen::Matrix3d Jd = legs_[i].jacobian(q_des);
    Eigen::Vector3d qd_des = Eigen::Vector3d::Zero();
    if (std::abs(Jd.determinant()) > 1e-6) qd_des = Jd.partialPivLu().solve(v_rel);
    const Eigen::Vector3d tau_pd = cfg_.swing_kp.cwiseProduct(q_des - (q + tau_d * qd)) +
                                   cfg_.swing_kd.cwiseProduct(qd_des - qd);
    out.tau.segment<3>(3 * i) = tau_gravity[i] + tau_pd;
    const double c0 = std::cos(q[0]), s0 = std::sin(q[0]);
    swing_reaction += tau_pd[0] * Eigen::Vector3d::UnitX() + tau_pd[1] * Eigen::Vector3d(0, c0, s0);
  }
  if (cfg_.swing_reaction_feedforward) wrench.tail<3>() += R * swing_reaction;

  // 9. Force distribution over the legs that are both scheduled and detected on the ground.
  out.wrench = wrench;
  std::array<Eigen::Vector3d, kLegs> feet;
  for (int i = 0; i < kLegs; ++i) feet[i] = R * (meas[i].r - com_);
  if (n_stance > 0) {
    const Status qp = force_qp_.solve(wrench, feet, stance, load, estimator_.ground_normal(), f_);
    status = worst(status, qp);
    out.qp_iterations = force_qp_.last_result().iterations;
  } else {
    f_.setZero();
    out.qp_iterations = 0;
  }
  out.foot_force = f_;

  // 10. Stance legs push with -J^T f.
  for (int i = 0; i < kLegs; ++i) {
    if (!stance[i]) continue;
    out.tau.segment<3>(3 * i) = tau_gravity[i] - J[i].transpose() * (R.transpose() * f_.segment<3>(3 * i));
    late_time_[i] = 0.0;
    was_stance_[i] = true;
  }
  saturate(out.tau, &status);
  tau_prev_ = out.tau;
  have_output_ = true;
  return status;
}

}  // namespace kiloloop
