#include "kiloloop/quadruped/quadruped_controller.hpp"
#include "kiloloop/model/gravity.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <kdl/chaindynparam.hpp>
#include <kdl/jntspaceinertiamatrix.hpp>
#include <utility>
#include <vector>

#include "kiloloop/control/rules.hpp"
#include "kiloloop/control/sane_range.hpp"
#include "kiloloop/quadruped/ldlt3.hpp"
#include "kiloloop/quadruped/lu3.hpp"
#include "kiloloop/trajectory/swing_trajectory.hpp"

namespace kiloloop {
namespace {

// The measured signals the controller uses finite and within_sane_range (control/sane_range.hpp:
// a finite value beyond it, such as 1e308, can only be a fault and would overflow the estimate
// and the wrench); the clock within kSaneTime (t = 1e308 overflowed the gait phase); the
// simulator's state only where it replaces the estimate (use_ground_truth); the AHRS quaternion
// only where it is used (estimator.external_attitude).
bool measurement_usable(const QuadrupedInput& in, bool external_attitude) {
  const bool truth_ok = !in.use_ground_truth ||
                        (within_sane_range(in.true_position) && within_sane_range(in.true_velocity) &&
                         within_sane_range(in.true_quat) && in.true_quat.norm() > 0.5);
  const bool quat_ok = !external_attitude || (within_sane_range(in.quat) && in.quat.norm() > 0.5);
  return std::abs(in.t) <= kSaneTime && within_sane_range(in.q) && within_sane_range(in.qd) &&
         within_sane_range(in.gyro) && within_sane_range(in.accel) && quat_ok &&
         within_sane_range(in.foothold_offset) && truth_ok;
}

Eigen::Quaterniond to_quat(const Eigen::Vector4d& wxyz) {
  return Eigen::Quaterniond(wxyz[0], wxyz[1], wxyz[2], wxyz[3]).normalized();
}

Eigen::Vector4d to_wxyz(const Eigen::Quaterniond& q) { return {q.w(), q.x(), q.y(), q.z()}; }

double yaw_of(const Eigen::Quaterniond& q) {
  return std::atan2(2.0 * (q.w() * q.z() + q.x() * q.y()), 1.0 - 2.0 * (q.y() * q.y() + q.z() * q.z()));
}

// [m/s] a foot scheduled on the ground that has not found it yet reaches on down at this speed
// (swing_legs: the late foot).
constexpr double kLateReachSpeed = 0.3;

double approach(double from, double to, double step) {
  return from + std::clamp(to - from, -step, step);
}

// The legs in a set of legs (bit i for leg i).
std::array<bool, QuadrupedController::kLegs> legs_in(int set) {
  std::array<bool, QuadrupedController::kLegs> legs{};
  for (int i = 0; i < QuadrupedController::kLegs; ++i) legs[i] = (set >> i) & 1;
  return legs;
}

// Whether the leg's inverse kinematics put the foot at the point within its joint limits:
// kOk only (kUnreachable is a degradation, not a failure: ok() and failed() both let it through,
// with q left untouched).
bool reached(const LegKinematics& leg, const Eigen::Vector3d& foot, Eigen::Vector3d* q) {
  return leg.inverse(foot, *q) == Status::kOk;
}

// Whether a leg holds its foot at a trunk-frame point with a knee bend `knee` allows (kAuto:
// either bend its joint limits allow).
bool reaches(const LegGeometry& g, KneeDirection knee, const Eigen::Vector3d& foot) {
  const KneeBends bends = allowed_bends(g);
  for (const KneeDirection k : {KneeDirection::kBackward, KneeDirection::kForward}) {
    const bool allowed = knee == KneeDirection::kAuto
                             ? (k == KneeDirection::kBackward ? bends.backward : bends.forward)
                             : knee == k;
    if (!allowed) continue;
    LegGeometry bent = g;
    bent.knee = k;
    Eigen::Vector3d q = Eigen::Vector3d::Zero();
    if (reached(LegKinematics(bent), foot, &q)) return true;
  }
  return false;
}

// [-] the range of stand extensions (hip -> foot / leg length) the derivation may move to where
// the joint limits forbid QuadrupedConfig::stand_extension: a straighter leg has no room left to
// lift its foot, a more bent one stands too low for its swing.
constexpr double kMinStandExtension = 0.40, kMaxStandExtension = 0.90;
constexpr double kStandExtensionStep = 0.01;

// x to 3 significant digits (configure-time messages).
std::string short_text(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", x);
  return buf;
}

std::string limits_text(const LegGeometry& g) {
  auto range = [](double lo, double hi) { return "[" + short_text(lo) + ", " + short_text(hi) + "]"; };
  return "hip pitch limits " + range(g.lower[1], g.upper[1]) + " rad and knee limits " +
         range(g.lower[2], g.upper[2]) + " rad";
}

}  // namespace

Status validate(const QuadrupedConfig& c, std::string* why) {
  auto fail = [&](const char* msg) {
    if (why) *why = std::string("quadruped config: ") + msg;
    return Status::kInvalidConfig;
  };
  if (!(c.dt > 0) || !(c.max_tilt > 0) || !(c.max_measurement_age > 0))
    return fail("dt, max_tilt, max_measurement_age must be > 0");
  if (!(c.body_height >= 0) || !(c.foot_radius >= 0) || !(c.swing_height >= 0) ||
      !(c.touchdown_depth >= 0) || !(c.raibert_gain >= 0) || !(c.mass >= 0) ||
      !(c.inertia_diag.array() >= 0).all() || !c.inertia_diag.allFinite())
    return fail("body_height, foot_radius, swing_height, touchdown_depth, raibert_gain, mass, "
                "inertia_diag must be >= 0 (0: derived)");
  if (!(c.stand_extension > 0 && c.stand_extension < 1) ||
      !(c.crouch_extension > 0 && c.crouch_extension <= c.stand_extension))
    return fail("need 0 < crouch_extension <= stand_extension < 1");
  if (!(c.gait.period >= 0)) return fail("gait.period must be >= 0 (0: derived)");
  if (!(c.trust_ramp >= 0) || !(c.load_ramp >= 0) || !(c.max_position_lag >= 0) ||
      !(c.actuation_delay >= 0) || !(c.max_acceleration > 0))
    return fail("trust_ramp, load_ramp, max_position_lag, actuation_delay >= 0; max_acceleration > 0");
  if (!(c.contact_force_on > c.contact_force_off) || !(c.contact_force_off >= 0) ||
      !(c.fz_min >= 0) || !(c.fz_max > c.fz_min))
    return fail("weight fractions: need contact_force_on > contact_force_off >= 0, fz_max > fz_min >= 0");
  if (!(c.trunk_delay_margin > 0)) return fail("trunk_delay_margin must be > 0");
  if (!(c.swing_prediction_residual >= 0 && c.swing_prediction_residual <= 1))
    return fail("swing_prediction_residual must be in [0, 1]");
  if (!(c.swing_frequency > 0) || !(c.swing_damping >= 0) || !(c.swing_damping_predicted >= 0) || !(c.swing_delay_margin > 0) ||
      !(c.swing_predict_from > 0) ||
      !(c.swing_kp.array() >= 0).all() || !(c.swing_kd.array() >= 0).all())
    return fail("swing_frequency, swing_delay_margin, swing_predict_from > 0; swing_damping, "
                "swing_damping_predicted, swing_kp, swing_kd >= 0");
  if (!(c.safe_stiffness > 0) || !(c.safe_time_constant >= 0) || !(c.safe_kp >= 0) || !(c.safe_kd >= 0))
    return fail("safe_stiffness > 0; safe_time_constant, safe_kp, safe_kd >= 0");
  if (!c.kp_position.allFinite() || !c.kd_velocity.allFinite() || !c.kp_orientation.allFinite() ||
      !c.kd_angular.allFinite() || !(c.kp_position.array() >= 0).all() ||
      !(c.kd_velocity.array() >= 0).all() || !(c.kp_orientation.array() >= 0).all() ||
      !(c.kd_angular.array() >= 0).all())
    return fail("trunk gains must be finite and >= 0");
  // Its length is checked against each shank at configure (leg_geometry_from_model).
  if (!c.foot_offset.allFinite()) return fail("foot_offset must be finite [m, foot link frame]");
  EstimatorConfig est = c.estimator;
  est.dt = c.dt;  // the controller's period is the estimator's
  if (const Status s = validate(est, why); failed(s)) {
    if (why) *why = "quadruped config: " + *why;
    return s;
  }
  return Status::kOk;
}

// The knee bend of a leg whose joint limits allow both (kAuto, resolved backward by
// leg_geometry_from_model): the one whose knee angle standing (the foot body_height below, under
// its hip) lies nearer the URDF's zero pose, the leg as its designers drew it; backward on a tie
// (a straight shank: the same angle either way, Solo12). ANYmal's shank carries its foot 0.1 m
// off the shank's axis, forward on the front legs and backward on the hind ones: backward knees
// everywhere bent the hind knees 2.25 rad against the front's 1.60, tilted the hind shanks 64 deg
// from vertical and put their adapter cylinders on the ground; forward hind knees mirror the
// front legs (ANYmal's own stance).
LegGeometry QuadrupedController::knee_nearer_zero(const LegGeometry& g, const QuadrupedConfig& cfg) {
  const KneeBends bends = allowed_bends(g);
  if (!(bends.backward && bends.forward)) return g;  // one bend only
  const Eigen::Vector3d stand(g.abd_origin.x(), g.abd_origin.y() + g.l_abd,
                              -(cfg.body_height - cfg.foot_radius));
  LegGeometry forward = g, backward = g;
  forward.knee = KneeDirection::kForward;
  backward.knee = KneeDirection::kBackward;
  Eigen::Vector3d q_forward = Eigen::Vector3d::Zero(), q_backward = Eigen::Vector3d::Zero();
  const bool f_ok = reached(LegKinematics(forward), stand, &q_forward);
  const bool b_ok = reached(LegKinematics(backward), stand, &q_backward);
  if (f_ok && (!b_ok || std::abs(q_forward[2]) < std::abs(q_backward[2]) - 1e-9)) return forward;
  return b_ok ? backward : g;
}

// [rad/s] the swing PD's highest natural frequency on the legs' full joint-space mass matrices
// (the joints coupled, not each on its own diagonal inertia): the largest sqrt(eig(H^-1 Kp)) over
// the legs, each at its standing pose and at its swing's apex (the foot swing_height straight
// above its standing place; skipped where the leg cannot reach it). Kp = diag(swing_kp) > 0, so
// eig(H^-1 Kp) = eig(Kp^1/2 H^-1 Kp^1/2), a symmetric one. Configure-time (allocates).
double QuadrupedController::coupled_swing_frequency(const QuadrupedController& c,
                                                    const QuadrupedConfig& cfg) {
  if (!(cfg.swing_kp.array() > 0).all()) return 0.0;
  const Eigen::Matrix3d root_kp = cfg.swing_kp.cwiseSqrt().asDiagonal();
  double largest = 0.0;  // [1/s^2]
  for (int i = 0; i < kLegs; ++i) {
    const Eigen::Vector3d q_stand = c.stand_q_.segment<3>(3 * i);
    Eigen::Vector3d q_apex = q_stand;
    const Eigen::Vector3d apex =
        c.legs_[i].foot_position(q_stand) + Eigen::Vector3d(0, 0, cfg.swing_height);
    const int poses = reached(c.legs_[i], apex, &q_apex) ? 2 : 1;
    for (int k = 0; k < poses; ++k) {
      const Eigen::Matrix3d H = c.leg_inertia_[i].at(k == 0 ? q_stand : q_apex);
      const Eigen::LLT<Eigen::Matrix3d> llt(H);
      if (llt.info() != Eigen::Success) continue;
      const Eigen::Matrix3d A = root_kp * llt.solve(root_kp);
      const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(0.5 * (A + A.transpose()),
                                                              Eigen::EigenvaluesOnly);
      largest = std::max(largest, eig.eigenvalues().maxCoeff());
    }
  }
  return std::sqrt(largest);
}

Status QuadrupedController::configure(const QuadrupedConfig& config, RobotModelPtr model,
                                      QuadrupedController* out, std::string* why) {
  auto fail = [&](const std::string& msg, Status s = Status::kInvalidConfig) {
    if (why) *why = msg;
    return s;
  };
  if (!model) return fail("model is null", Status::kModelError);
  if (const Status s = validate(config, why); failed(s)) return s;
  if (model->tree().getSegments().count(config.trunk_link) == 0)
    return fail("trunk_link: no link named '" + config.trunk_link + "' in the model", Status::kModelError);
  QuadrupedController c;
  c.cfg_ = config;
  QuadrupedConfig& cfg = c.cfg_;  // resolved in place below
  c.model_ = model;
  for (int i = 0; i < kLegs; ++i) {
    LegGeometry g;
    Status s = leg_geometry_from_model(*model, config.trunk_link, config.feet[i], &g, why,
                                       config.knees[i], config.foot_offset);
    if (failed(s)) return s;
    c.legs_[i] = LegKinematics(g);
    cfg.knees[i] = g.knee;
    s = LegGravity::configure(*model, config.trunk_link, config.feet[i], c.legs_[i], &c.leg_gravity_[i], why);
    if (failed(s)) return s;
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
  // Feet order FL, FR, RL, RR checked against the geometry: a swapped pair would turn the trot
  // into a pace (or worse) without any other symptom.
  {
    const char* names[kLegs] = {"front-left", "front-right", "rear-left", "rear-right"};
    const double sx[kLegs] = {1, 1, -1, -1}, sy[kLegs] = {1, -1, 1, -1};
    Eigen::Vector2d centre = Eigen::Vector2d::Zero();
    for (const auto& leg : c.legs_) centre += 0.25 * leg.geometry().abd_origin.head<2>();
    for (int i = 0; i < kLegs; ++i) {
      const LegGeometry& g = c.legs_[i].geometry();
      const Eigen::Vector2d hip = Eigen::Vector2d(g.abd_origin.x(), g.abd_origin.y() + g.l_abd) - centre;
      if (hip.x() * sx[i] <= 0 || hip.y() * sy[i] <= 0)
        return fail("feet: '" + config.feet[i] + "' is listed as " + names[i] +
                        " but its hip lies at x = " + std::to_string(hip.x()) + " m, y = " +
                        std::to_string(hip.y()) + " m from the hips' centre (trunk frame: x forward, "
                        "y left); list the feet as front-left, front-right, rear-left, rear-right",
                    Status::kModelError);
    }
  }
  // Standing height: each foot stand_extension of its leg's length straight below its hip pitch
  // axis (mean over the legs), unless given. Where a leg's joint limits forbid it (the foot
  // under the hip there, or swing_height above that, out of reach with every knee bend the leg
  // may take), the nearest extension in [0.40, 0.90] where every leg reaches both (resolved into
  // stand_extension). Measured: a 25 kg quadruped (Laikago) with its knees flipped to bend
  // forward, limits [0, pi], cannot put its feet under its hips at 0.58 with its hip pitch's
  // lower limit (-0.52 rad); unchecked, its stand pose came out all zeros (legs straight) and it
  // fell in every scenario.
  auto hip_z = [](const LegGeometry& g) { return g.abd_origin.z() + g.h_abd; };
  if (cfg.body_height == 0) {
    double mean_length = 0;
    for (const auto& leg : c.legs_) mean_length += 0.25 * leg.geometry().length();
    const double lift = cfg.swing_height > 0 ? cfg.swing_height : 0.16 * mean_length;  // as below
    auto height_at = [&](double extension) {
      double h = 0;
      for (const auto& leg : c.legs_)
        h += 0.25 * (extension * leg.geometry().length() - hip_z(leg.geometry()));
      return h + cfg.foot_radius;
    };
    // The first leg that cannot stand at height h (or lift its foot from there), -1: none.
    auto first_short_leg = [&](double h) {
      for (int i = 0; i < kLegs; ++i) {
        const LegGeometry& g = c.legs_[i].geometry();
        const Eigen::Vector3d foot(g.abd_origin.x(), g.abd_origin.y() + g.l_abd, -(h - cfg.foot_radius));
        if (!reaches(g, config.knees[i], foot) ||
            !reaches(g, config.knees[i], foot + Eigen::Vector3d(0, 0, lift)))
          return i;
      }
      return -1;
    };
    double extension = cfg.stand_extension;
    int short_leg = first_short_leg(height_at(extension));
    const int wanted_short_leg = short_leg;
    for (int k = 1; short_leg >= 0 && k <= 100; ++k)
      for (const double e : {cfg.stand_extension - k * kStandExtensionStep,
                             cfg.stand_extension + k * kStandExtensionStep}) {
        if (e < kMinStandExtension - 1e-9 || e > kMaxStandExtension + 1e-9 || short_leg < 0) continue;
        if (first_short_leg(height_at(e)) < 0) extension = e, short_leg = -1;
      }
    if (short_leg >= 0) {
      const LegGeometry& g = c.legs_[wanted_short_leg].geometry();
      return fail("no standing height within the joint limits: leg '" + config.feet[wanted_short_leg] +
                      "' (" + short_text(g.length()) + " m) cannot hold its foot under its hip at " +
                      short_text(kMinStandExtension) + " to " + short_text(kMaxStandExtension) +
                      " of its length and lift it " + short_text(lift) + " m from there with its " +
                      limits_text(g) + "; set body_height, knees or the limits ([limits.<joint>])",
                  Status::kInvalidConfig);
    }
    cfg.stand_extension = extension;
    cfg.body_height = height_at(extension);
  }
  for (int i = 0; i < kLegs; ++i)
    if (config.knees[i] == KneeDirection::kAuto) {
      c.legs_[i] = LegKinematics(knee_nearer_zero(c.legs_[i].geometry(), cfg));
      cfg.knees[i] = c.legs_[i].geometry().knee;
    }
  // Standing and crouch poses: IK of the feet below the hips (crouch raised until the limits allow).
  for (int i = 0; i < kLegs; ++i) {
    const LegGeometry& g = c.legs_[i].geometry();
    const Eigen::Vector3d under_hip(g.abd_origin.x(), g.abd_origin.y() + g.l_abd, 0.0);
    Eigen::Vector3d q = Eigen::Vector3d::Zero();
    const Eigen::Vector3d stand = under_hip - Eigen::Vector3d(0, 0, cfg.body_height - cfg.foot_radius);
    if (!reached(c.legs_[i], stand, &q))
      return fail("body_height " + std::to_string(cfg.body_height) + " m: leg '" + config.feet[i] +
                      "' cannot stand there (out of reach or joint limits)",
                  Status::kInvalidConfig);
    c.stand_q_.segment<3>(3 * i) = q;
    c.crouch_q_.segment<3>(3 * i) = q;
    for (double e = cfg.crouch_extension; e < cfg.stand_extension; e += 0.02) {
      Eigen::Vector3d qc = q;
      const Eigen::Vector3d p = under_hip + Eigen::Vector3d(0, 0, hip_z(g) - e * g.length());
      if (reached(c.legs_[i], p, &qc)) {
        c.crouch_q_.segment<3>(3 * i) = qc;
        break;
      }
    }
  }
  c.mass_ = cfg.mass > 0 ? cfg.mass : model->total_mass();
  cfg.mass = c.mass_;
  // Composite rigid-body inertia of the whole tree in the standing pose (dummy links above the
  // trunk included): each link's own inertia moved by the parallel-axis theorem (KDL's
  // frame * inertia), summed in the root frame, then expressed in the trunk frame.
  {
    KDL::RigidBodyInertia total = KDL::RigidBodyInertia::Zero();
    KDL::Frame T_root_trunk = KDL::Frame::Identity();
    std::vector<std::pair<KDL::SegmentMap::const_iterator, KDL::Frame>> stack;
    stack.emplace_back(model->tree().getRootSegment(), KDL::Frame::Identity());
    while (!stack.empty()) {
      const auto [el, T] = stack.back();
      stack.pop_back();
      total = total + T * GetTreeElementSegment(el->second).getInertia();
      if (el->first == config.trunk_link) T_root_trunk = T;
      for (const auto& child : GetTreeElementChildren(el->second)) {
        const KDL::Segment& seg = GetTreeElementSegment(child->second);
        double q = 0.0;
        const std::string& jn = seg.getJoint().getName();
        for (int k = 0; k < 12; ++k)
          if (seg.getJoint().getType() != KDL::Joint::None && c.joint_names_[k] == jn) q = c.stand_q_[k];
        stack.emplace_back(child, T * seg.pose(q));
      }
    }
    total = T_root_trunk.Inverse() * total;
    const KDL::Vector cog = total.getCOG();
    c.com_ = Eigen::Vector3d(cog.x(), cog.y(), cog.z());
    const KDL::RotationalInertia Ic = total.RefPoint(cog).getRotationalInertia();
    c.inertia_ = Eigen::Map<const Eigen::Matrix3d>(Ic.data);
    c.inertia_free_ = free_leg_inertia(*model, config.trunk_link, config.feet, c.stand_q_, c.mass_,
                                       c.com_, c.inertia_);
    if (!cfg.inertia_diag.isZero()) {
      // An override scales the legs' couplings with it (axis by axis).
      const Eigen::Vector3d s = cfg.inertia_diag.cwiseQuotient(c.inertia_.diagonal()).cwiseSqrt();
      Matrix6d scale = Matrix6d::Identity();
      scale.bottomRightCorner<3, 3>() = s.asDiagonal();
      c.inertia_ = cfg.inertia_diag.asDiagonal();
      c.inertia_free_.composite.bottomRightCorner<3, 3>() = c.inertia_;
      for (auto& a : c.inertia_free_.coupling) a = scale * a * scale;
      for (auto& a : c.inertia_free_.momentum) a = scale * a;
    }
    cfg.inertia_diag = c.inertia_.diagonal();
    // distribute_forces' trunk inertia for each set of swinging legs: a constant of the standing
    // pose, so its 3x3 inverse and products are done here once, not every tick.
    for (int set = 0; set < (1 << kLegs); ++set)
      c.inertia_by_swing_set_[set] = c.inertia_free_.rotational(legs_in(set));
  }
  // Stance-force QP: a moment error weighs as the trunk acceleration it causes at the feet
  // against the CoM acceleration of a force error (QuadrupedConfig::force), unless given.
  {
    const double lever = cfg.body_height + c.com_.z();  // [m] CoM above the ground, standing
    for (int j = 0; j < 3; ++j)
      if (cfg.force.wrench_weight[3 + j] == 0) {
        const double a = c.mass_ * lever / c.inertia_(j, j);  // [1/m]
        cfg.force.wrench_weight[3 + j] = a * a;
      }
  }
  // Sizes that scale with the leg.
  double leg_length = 0;
  for (const auto& leg : c.legs_) leg_length += 0.25 * leg.geometry().length();
  if (cfg.swing_height == 0) cfg.swing_height = 0.16 * leg_length;
  if (cfg.touchdown_depth == 0) cfg.touchdown_depth = 0.02 * leg_length;
  if (cfg.raibert_gain == 0) cfg.raibert_gain = 0.75 * std::sqrt(cfg.body_height / kGravity);
  if (cfg.gait.period == 0) cfg.gait.period = 2.4 * std::sqrt(leg_length / kGravity);
  // Delay bounds every loop's bandwidth: a natural frequency above margin / (delay + dt) is
  // lowered to it, its damping ratio kept (kp scales with w^2, kd with w).
  const double t_loop = cfg.actuation_delay + cfg.dt;
  auto cap = [](double& kp, double& kd, double inertia, double w_max) {
    const double w = std::sqrt(kp / inertia);
    if (w > w_max) {
      kp *= (w_max / w) * (w_max / w);
      kd *= w_max / w;
    }
  };
  const double kp_roll = cfg.kp_orientation[0];
  for (int j = 0; j < 3; ++j) {
    cap(cfg.kp_position[j], cfg.kd_velocity[j], 1.0, cfg.trunk_delay_margin / t_loop);
    cap(cfg.kp_orientation[j], cfg.kd_angular[j], 1.0, cfg.trunk_delay_margin / t_loop);
  }
  if (cfg.kp_orientation[0] < kp_roll) cfg.kp_position[1] = 0.0;  // no hold across the heading
  // Swing PD: kp = I w^2, kd = 2 zeta I w per joint, I the leg's joint-space inertia diagonal at
  // the standing pose (mean over the legs).
  {
    Eigen::Vector3d inertia = Eigen::Vector3d::Zero();
    for (int i = 0; i < kLegs; ++i) {
      const KDL::Chain chain = leg_chain(*model, config.trunk_link, config.feet[i]);
      KDL::ChainDynParam dyn(chain, KDL::Vector::Zero());
      KDL::JntArray q(3);
      KDL::JntSpaceInertiaMatrix H(3);
      for (int k = 0; k < 3; ++k) q(k) = c.stand_q_[3 * i + k];
      dyn.JntToMass(q, H);
      for (int k = 0; k < 3; ++k) inertia[k] += 0.25 * H(k, k);
      c.leg_mass_inverse_[i] = Eigen::Matrix3d(H.data).inverse();
      // The same H at any pose, allocation-free (the check: it must match KDL's here).
      const Eigen::Matrix3d H_own = c.leg_inertia_[i].configure(chain)
                                        ? c.leg_inertia_[i].at(c.stand_q_.segment<3>(3 * i))
                                        : Eigen::Matrix3d::Zero();
      if ((H_own - Eigen::Matrix3d(H.data)).norm() > 1e-9 * (1.0 + Eigen::Matrix3d(H.data).norm())) {
        if (why) *why = "leg " + config.feet[i] + ": its chain is not 3 joints in at most " +
                        std::to_string(LegJointInertia::kMaxSegments) + " segments";
        return Status::kInvalidConfig;
      }
    }
    c.swing_inertia_ = inertia;
    // The joint predictor only where the delay takes a large phase at the swing frequency
    // (omega (delay + dt) above swing_predict_from): it models a free leg, so a foot touching early (stones, soft ground)
    // makes its prediction wrong. Measured with it always on: our model fell on stones and
    // compliant ground at 10 ms (it passes both without); at 35 ms it is what makes the trot pass.
    if (cfg.swing_frequency * (cfg.actuation_delay + cfg.dt) <= cfg.swing_predict_from)
      cfg.predict_swing = false;
    const double w = cfg.swing_frequency;
    const double zeta = cfg.predict_swing ? cfg.swing_damping_predicted : cfg.swing_damping;
    if (cfg.swing_kp.isZero()) cfg.swing_kp = inertia * w * w;
    if (cfg.swing_kd.isZero()) cfg.swing_kd = 2.0 * zeta * w * inertia;
    // With the joint predictor only its error is left of the delay inside the loop.
    const double unpredicted = cfg.predict_swing ? cfg.swing_prediction_residual : 1.0;
    const double t_swing_loop = unpredicted * cfg.actuation_delay + cfg.dt;
    const double w_swing_max = cfg.swing_delay_margin / t_swing_loop;
    for (int j = 0; j < 3; ++j)
      if (inertia[j] > 0)
        cap(cfg.swing_kp[j], cfg.swing_kd[j], inertia[j], w_swing_max);
    const double w_coupled = coupled_swing_frequency(c, cfg);
    if (w_coupled > w_swing_max) {
      const double s = w_swing_max / w_coupled;  // every joint's gains alike: the mode shapes kept
      cfg.swing_kp *= s * s;
      cfg.swing_kd *= s;
    }
  }
  // Safe stop from the effort limits, the derived gains at most those of a swing leg without the
  // joint predictor (a leg lifted off a tipping trunk is a leg in the air, and the safe stop
  // predicts nothing): the swing gains at the natural frequency a free leg takes over the whole
  // delay, swing_predict_from / (actuation_delay + dt) if below swing_frequency, and the damping
  // ratio swing_damping. Measured: Solo12's URDF gives every joint 1000 N m, so 400 N m/rad and
  // 40 N m s/rad on joints of 5e-4 to 2e-3 kg m^2; in quadruped-tilt-stop the safe stop rang its
  // legs until MuJoCo's accelerations were not finite, 0.8 s in on seeds 0-4 (MuJoCo then resets
  // the simulation). At 35 ms the swing gains as the predictor has them (critically damped, 30
  // rad/s) still rang it.
  const double w_safe = std::min(cfg.swing_frequency, cfg.swing_predict_from / t_loop);
  const double r = w_safe / cfg.swing_frequency;  // of the swing gains' design frequency
  const double zeta_ratio =
      cfg.predict_swing && cfg.swing_damping_predicted > 0 ? cfg.swing_damping / cfg.swing_damping_predicted : 1.0;
  for (int k = 0; k < 12; ++k) {
    const double kp_effort = cfg.safe_stiffness * c.effort_[k];
    c.safe_kp_[k] = cfg.safe_kp > 0 ? cfg.safe_kp : std::min(kp_effort, r * r * cfg.swing_kp[k % 3]);
    c.safe_kd_[k] = cfg.safe_kd > 0 ? cfg.safe_kd
                                    : std::min(cfg.safe_time_constant * kp_effort,
                                               r * zeta_ratio * cfg.swing_kd[k % 3]);
  }
  // Forces from weight fractions.
  const double weight = c.mass_ * kGravity;
  cfg.contact.force_on = cfg.contact_force_on * weight;
  cfg.contact.force_off = cfg.contact_force_off * weight;
  cfg.force.fz_min = cfg.fz_min * weight;
  cfg.force.fz_max = cfg.fz_max * weight;
  if (failed(c.gait_.configure(cfg.gait))) return fail("gait: need period > 0, 0.5 < duty < 1");
  if (failed(c.contacts_.configure(cfg.contact, why))) return Status::kInvalidConfig;
  EstimatorConfig est = cfg.estimator;
  est.dt = cfg.dt;
  if (failed(c.estimator_.configure(est, why))) return Status::kInvalidConfig;
  cfg.estimator = c.estimator_.config();  // the attitude crossover resolved
  cfg.estimator.dt = config.estimator.dt;
  Status s = StanceForceQp::configure(cfg.force, &c.force_qp_, why);
  if (failed(s)) return s;
  for (int i = 0; i < kLegs; ++i) c.q_leg_valid_[i] = c.stand_q_.segment<3>(3 * i);
  const int n_flight = static_cast<int>(std::floor(cfg.actuation_delay / cfg.dt + 0.5 + 1e-9));
  c.tau_in_flight_.configure(n_flight, Vector12d::Zero());
  c.accel_in_flight_.configure(n_flight, Vector6d::Zero());
  c.qdd_in_flight_.configure(n_flight, Vector12d::Zero());
  c.schedule_in_flight_.configure(n_flight, c.gait_.legs());
  c.acting_schedule_ = c.gait_.legs();
  c.gate_ = MeasurementGate(c.cfg_.max_measurement_age);
  c.configured_ = true;
  *out = std::move(c);
  return Status::kOk;
}

Status QuadrupedController::step(const QuadrupedInput& in, QuadrupedOutput& out) noexcept {
  if (!configured_) return out.status = Status::kNotConfigured;
  tick_.accel.setZero();
  tick_.qdd.setZero();
  out.status = run(in, out);
  counters_.record(out.status);
  // Whatever was sent is now in flight (held and safe outputs included).
  tau_in_flight_.push(out.tau);
  accel_in_flight_.push(tick_.accel);
  qdd_in_flight_.push(tick_.qdd);
  schedule_in_flight_.push(gait_.legs());
  return out.status;
}

void QuadrupedController::safe_output(const QuadrupedInput& in, Vector12d& tau) const noexcept {
  for (int i = 0; i < kLegs; ++i) {
    const Eigen::Vector3d q = in.q.segment<3>(3 * i), qd = in.qd.segment<3>(3 * i);
    const Eigen::Vector3d t =
        q.allFinite() && qd.allFinite()
            ? Eigen::Vector3d(safe_kp_.segment<3>(3 * i).cwiseProduct(crouch_q_.segment<3>(3 * i) - q) -
                              safe_kd_.segment<3>(3 * i).cwiseProduct(qd))
            : Eigen::Vector3d::Zero();
    tau.segment<3>(3 * i) = t;
  }
}

// The shared rule (control/rules.hpp): clamp to +-effort; a non-finite torque becomes 0 and the
// step fails.
void QuadrupedController::saturate(Vector12d& tau, Status* status) const noexcept {
  *status = clip_effort(*status, tau, effort_);
}

// The 1 kHz tick as a short list of stages over the per-tick scratch `tick_` (each stage reads
// what the earlier ones wrote there; nothing allocates).
Status QuadrupedController::run(const QuadrupedInput& in, QuadrupedOutput& out) noexcept {
  if (!read_inputs(in, out)) return tick_.status;  // bad sensors: last command held
  leg_kinematics(in);
  detect_contacts(in, out);
  estimate_state(in, out);
  if (safety_stop(in, out)) return Status::kSafeStop;
  trunk_reference();
  trunk_wrench(out);
  swing_legs(in, out);
  distribute_forces(out);
  stance_legs(out);
  saturate(out.tau, &tick_.status);
  // Only the joint predictor reads them (swing_legs): without it (short delays) the per-leg
  // H(q) solves would be work for nothing; qdd stays the zero set at the tick's start.
  if (cfg_.predict_swing) swing_joint_accelerations(in, out.tau);
  trunk_rotation_from_torques(out.tau);
  tau_prev_ = out.tau;
  have_output_ = true;
  return tick_.status;
}

// 1. Inputs. Bad sensors: hold the last command (a glitch must not drop the robot).
bool QuadrupedController::read_inputs(const QuadrupedInput& in, QuadrupedOutput& out) noexcept {
  Tick& k = tick_;
  // Stamp finite, fresh and not older than one already used (control/rules.hpp), then the
  // signals usable; only a tick that goes on to use its measurement counts for the order.
  k.status = gate_.check(in.t, in.stamp);
  if (k.status == Status::kOk && !measurement_usable(in, cfg_.estimator.external_attitude)) k.status = Status::kNonFiniteMeasurement;
  if (failed(k.status)) {
    if (have_output_) out.tau = tau_prev_;
    else safe_output(in, out.tau);
    Status ignored = k.status;
    saturate(out.tau, &ignored);
    return false;
  }
  gate_.accept(in.stamp);
  k.command = in.velocity_command;
  k.requested = in.gait == Gait::kTrot ? Gait::kTrot : Gait::kStand;
  if (!k.command.allFinite() || (in.gait != Gait::kStand && in.gait != Gait::kTrot)) {
    k.command.setZero();
    k.requested = Gait::kStand;
    k.status = Status::kNonFiniteReference;
  }
  return true;
}

// 2. Leg kinematics in the trunk frame.
void QuadrupedController::leg_kinematics(const QuadrupedInput& in) noexcept {
  Tick& k = tick_;
  // The orientation this stage works with: the AHRS's, or the estimate of the last tick (the
  // estimator runs after the contacts it needs), or on the first tick the accelerometer's tilt.
  k.q_imu = cfg_.estimator.external_attitude ? to_quat(in.quat) : Eigen::Quaterniond::Identity();
  if (cfg_.estimator.external_attitude) k.q_prior = k.q_imu;
  else if (estimator_.initialised()) k.q_prior = estimator_.orientation();
  else k.q_prior = estimator_.initial_orientation(in.accel, k.q_imu);
  const Eigen::Vector3d g_trunk = k.q_prior.conjugate() * Eigen::Vector3d(0, 0, -kGravity);
  std::array<LegKinematics::Trig, kLegs> trig;  // the joints' sines and cosines, once
  for (int i = 0; i < kLegs; ++i) {
    const Eigen::Vector3d q = in.q.segment<3>(3 * i);
    legs_[i].foot_and_jacobian(q, &k.meas[i].r, &k.J[i], &trig[i]);
    k.meas[i].v_rel = k.J[i] * in.qd.segment<3>(3 * i);
    k.tau_gravity[i] = leg_gravity_[i].torque(trig[i], g_trunk);
  }
  // A spherical foot rolls: its contact point (radius below the centre, along the ground normal)
  // stands still, not its centre. Add the rolling term to what the estimator takes as the
  // stance-foot velocity: v_rel = J qd + (w_shank + w_trunk) x c, c = contact point - centre.
  const Eigen::Vector3d c = -cfg_.foot_radius * (k.q_prior.conjugate() * estimator_.ground_normal());
  for (int i = 0; i < kLegs; ++i) {
    const Eigen::Vector3d& sg = legs_[i].geometry().sign;
    const double pitch_rate = sg[1] * in.qd[3 * i + 1] + sg[2] * in.qd[3 * i + 2];
    const Eigen::Vector3d& axis = trig[i].pitch_axis;  // the shank turns about it
    const Eigen::Vector3d w_shank(sg[0] * in.qd[3 * i], axis.y() * pitch_rate, axis.z() * pitch_rate);
    k.meas[i].v_rel += (w_shank + in.gyro - estimator_.gyro_bias()).cross(c);
  }
  if (!estimator_.initialised()) {
    estimator_.reset(k.q_prior, k.meas, cfg_.foot_radius);
    p_des_ = estimator_.position();
    yaw_des_ = yaw_of(estimator_.orientation());
  }
}

// 3. Gait schedule, then contacts from the normal force that the last command implies.
void QuadrupedController::detect_contacts(const QuadrupedInput& in, QuadrupedOutput& out) noexcept {
  Tick& k = tick_;
  gait_.update(in.t, k.requested);
  // The robot moves as the commands acting now say: those sent a delay ago, with their schedule.
  acting_schedule_ = schedule_in_flight_.size() > 0 ? schedule_in_flight_.oldest(0) : gait_.legs();
  const auto& schedule = acting_schedule_;
  const Eigen::Matrix3d R_prev = estimator_.rotation();
  const Eigen::Vector3d n_prev = estimator_.ground_normal();
  const Eigen::Vector3d p_prev = estimator_.position();
  for (int i = 0; i < kLegs; ++i) {
    // Foot sphere's distance above the estimated ground plane (last tick's trunk pose).
    const Eigen::Vector3d foot = p_prev + R_prev * k.meas[i].r;
    k.clearance[i] = (foot.z() - estimator_.ground_height(foot.x(), foot.y())) * n_prev.z() - cfg_.foot_radius;
    // Static leg: tau = tau_g - J^T f  =>  f = J^-T (tau_g - tau) (trunk frame), skipped near
    // singular poses.
    const Eigen::Matrix3d Jt = k.J[i].transpose();
    k.normal_force[i] = 0.0;
    // The torque acting now is the one sent a delay ago.
    const Vector12d& tau_acting =
        cfg_.predict_in_flight && tau_in_flight_.size() > 0 ? tau_in_flight_.oldest(0) : tau_prev_;
    if (std::abs(Jt.determinant()) > 1e-6) {
      const Eigen::Vector3d f = Lu3(Jt).solve(k.tau_gravity[i] - tau_acting.segment<3>(3 * i));
      k.normal_force[i] = n_prev.dot(R_prev * f);
    }
  }
  // A late foot (the commands acting now have it on the ground, no contact yet) reaches on down
  // at kLateReachSpeed: by the reference acting now, a delay old, it should be that far below
  // where it stands. Counted off its clearance for the detector, a foot held up by ground
  // higher than estimated lands after (clearance - touchdown_clearance) / kLateReachSpeed, a
  // free foot follows its reference down and lands as before. Measured at 10 ms with the
  // clearance alone (touchdown_clearance 5 mm, force_on 0.145 m g, which a late foot's weak
  // swing PD does not reach): on stones a rear foot standing on a stone 9-11 mm above the plane
  // fitted through the footholds read 16-18 mm of clearance for 50 ms (both robots); on soft
  // ground (1e3 N/m) the stance feet sink on after their footholds latch and a Go1 foot on the
  // surface read 12-16 mm. Neither was loaded, the other diagonal lifted off, one leg carried
  // the trunk, and it rolled over.
  std::array<double, kLegs> reach_clearance = k.clearance;
  for (int i = 0; i < kLegs; ++i)
    if (late_time_[i] > 0)
      reach_clearance[i] -= kLateReachSpeed * std::max(late_time_[i] - cfg_.actuation_delay, 0.0);
  contacts_.update(schedule, k.normal_force, reach_clearance);
  out.foot_clearance = Eigen::Vector4d(k.clearance[0], k.clearance[1], k.clearance[2], k.clearance[3]);
  for (int i = 0; i < kLegs; ++i) {
    k.meas[i].contact = contacts_.contact(i);
    k.meas[i].touched_down = contacts_.touched_down(i);
    contact_time_[i] = k.meas[i].touched_down ? 0.0 : std::min(contact_time_[i] + cfg_.dt, 1e3);
    const double until_liftoff = schedule[i].stance ? schedule[i].remaining : 0.0;
    k.meas[i].trust = cfg_.trust_ramp > 0
                          ? std::clamp(std::min(contact_time_[i], until_liftoff) / cfg_.trust_ramp, 0.0, 1.0)
                          : 1.0;
  }
}

// 4. State estimate (or ground truth when debugging).
void QuadrupedController::estimate_state(const QuadrupedInput& in, QuadrupedOutput& out) noexcept {
  Tick& k = tick_;
  k.status = worst(k.status, estimator_.update(in.gyro, in.accel, k.q_imu, k.meas));
  if (in.use_ground_truth)
    estimator_.set_truth(in.true_position, in.true_velocity, to_quat(in.true_quat));
  k.R = estimator_.rotation();
  k.p = estimator_.position();
  k.v = estimator_.velocity();
  k.w_body = estimator_.angular_velocity();
  out.tilt = std::acos(std::clamp(k.R(2, 2), -1.0, 1.0));
  out.position = k.p;
  out.velocity = k.v;
  out.quat = to_wxyz(estimator_.orientation());
  out.ground_normal = estimator_.ground_normal();
  for (int i = 0; i < kLegs; ++i) {
    out.contact[i] = contacts_.contact(i);
    out.scheduled[i] = acting_schedule_[i].stance;
  }
}

// 5. Safety: a tilt beyond the limit latches the safe stop in this very tick.
bool QuadrupedController::safety_stop(const QuadrupedInput& in, QuadrupedOutput& out) noexcept {
  if (!safe_stop_ && !(out.tilt > cfg_.max_tilt)) {
    out.safe_stop = false;
    return false;
  }
  safe_stop_ = true;
  out.safe_stop = true;
  safe_output(in, out.tau);
  Status ignored = Status::kSafeStop;
  saturate(out.tau, &ignored);
  tau_prev_ = out.tau;
  have_output_ = true;
  return true;
}

// 6. Ramped command and the desired trunk motion (level trunk, commanded heading).
void QuadrupedController::trunk_reference() noexcept {
  Tick& k = tick_;
  const double dv = cfg_.max_acceleration * cfg_.dt;
  for (int j = 0; j < 3; ++j) v_cmd_[j] = approach(v_cmd_[j], k.command[j], dv);
  yaw_des_ += v_cmd_.z() * cfg_.dt;
  const double yaw = yaw_of(estimator_.orientation());
  k.v_des = Eigen::Vector3d(std::cos(yaw) * v_cmd_.x() - std::sin(yaw) * v_cmd_.y(),
                            std::sin(yaw) * v_cmd_.x() + std::cos(yaw) * v_cmd_.y(), 0.0);
  p_des_.head<2>() += k.v_des.head<2>() * cfg_.dt;
  // Keep the position target within reach, so a push does not wind it up.
  const Eigen::Vector2d lag = p_des_.head<2>() - k.p.head<2>();
  if (lag.norm() > cfg_.max_position_lag)
    p_des_.head<2>() = k.p.head<2>() + cfg_.max_position_lag * lag.normalized();
  p_des_.z() = estimator_.ground_height(k.p.x(), k.p.y()) + cfg_.body_height;
}

// kp_position's x and y act along and across the commanded heading (world z as is).
Eigen::Vector3d QuadrupedController::heading_frame_position_feedback(const Eigen::Vector3d& e_p) const noexcept {
  const double c = std::cos(yaw_des_), s = std::sin(yaw_des_);
  const double along = cfg_.kp_position.x() * (c * e_p.x() + s * e_p.y());
  const double across = cfg_.kp_position.y() * (-s * e_p.x() + c * e_p.y());
  return Eigen::Vector3d(c * along - s * across, s * along + c * across, cfg_.kp_position.z() * e_p.z());
}

// 7. Desired wrench about the CoM (world axes). Height is measured by the legs in contact
// (trunk above the feet), which does not drift the way an integrated estimate does.
void QuadrupedController::trunk_wrench(QuadrupedOutput& out) noexcept {
  Tick& k = tick_;
  const auto& schedule = gait_.legs();
  k.n_stance = 0;
  for (int i = 0; i < kLegs; ++i) {
    k.stance[i] = commanded_stance(i);
    k.n_stance += k.stance[i];
    // Time since the scheduled touch-down (standing counts as long ago).
    stance_time_[i] = schedule[i].stance ? std::min(stance_time_[i] + cfg_.dt, 1e3) : 0.0;
    k.load[i] = cfg_.load_ramp > 0
                    ? std::clamp(std::min(stance_time_[i], schedule[i].remaining) / cfg_.load_ramp, 0.0, 1.0)
                    : 1.0;
  }
  // Feedback acts on the state predicted one actuation delay ahead, when the command lands:
  // first order, plus (predict_in_flight) what the commands still in flight will do to it.
  const double tau_d = cfg_.actuation_delay;
  const Eigen::Matrix3d& R = k.R;
  InFlightEffect<Vector6d> e{Vector6d::Zero(), Vector6d::Zero()};  // world
  if (cfg_.predict_in_flight) e = in_flight_effect(accel_in_flight_, cfg_.dt);
  const Eigen::Vector3d dv = e.velocity.head<3>(), dp = e.position.head<3>();
  const Eigen::Vector3d dw = e.velocity.tail<3>(), dth = e.position.tail<3>();
  const Eigen::Vector3d v_pred = k.v + dv;
  Eigen::Vector3d e_p = p_des_ - (k.p + tau_d * k.v + dp);
  double height = tau_d * k.v.z() + dp.z();
  for (int i = 0; i < kLegs; ++i)
    if (k.stance[i]) height += -(R * k.meas[i].r).z();
  if (k.n_stance > 0) {
    height = height / k.n_stance + cfg_.foot_radius / std::max(estimator_.ground_normal().z(), 0.5);
    e_p.z() = cfg_.body_height - height;
  }
  const Eigen::Vector3d e_v = k.v_des - v_pred;
  const Eigen::Quaterniond q_des(Eigen::AngleAxisd(yaw_des_, Eigen::Vector3d::UnitZ()));
  // Rotation over the delay (world frame): tau_d w + the in-flight angular accelerations.
  const Eigen::Vector3d half_turn = 0.5 * (tau_d * (R * k.w_body) + dth);
  const Eigen::Quaterniond q_pred =
      (Eigen::Quaterniond(1.0, half_turn.x(), half_turn.y(), half_turn.z()) * estimator_.orientation())
          .normalized();
  const Eigen::Vector3d w_pred_body = k.w_body + R.transpose() * dw;
  k.p_pred = k.p + tau_d * k.v + dp;
  k.v_pred = v_pred;
  k.R_pred = q_pred.toRotationMatrix();
  k.w_pred_body = w_pred_body;
  Eigen::Quaterniond q_err = q_des * q_pred.conjugate();  // world frame error
  if (q_err.w() < 0) q_err.coeffs() = -q_err.coeffs();  // shortest path
  const Eigen::Vector3d e_R_body = R.transpose() * (2.0 * q_err.vec());
  const Eigen::Vector3d w_des_body = R.transpose() * Eigen::Vector3d(0, 0, v_cmd_.z());
  // The commanded turn's centripetal acceleration (w_z x v_des) as a feed-forward: otherwise a
  // turning trot needs a lateral velocity error of v w / kd to make it.
  const Eigen::Vector3d a_turn(-v_cmd_.z() * k.v_des.y(), v_cmd_.z() * k.v_des.x(), 0.0);
  k.wrench.head<3>() = mass_ * (heading_frame_position_feedback(e_p) + cfg_.kd_velocity.cwiseProduct(e_v) +
                                a_turn + Eigen::Vector3d(0, 0, kGravity));
  k.wrench.tail<3>() = R * (inertia_ * (cfg_.kp_orientation.cwiseProduct(e_R_body) +
                                        cfg_.kd_angular.cwiseProduct(w_des_body - w_pred_body)));
  (void)out;
}

// Stance is commanded where the schedule says so and the foot is on the ground, or is still in
// the swing that the commands acting now drive and lands by the time this command does (both
// schedules agree once the delay has passed: a foot still in the air then is late).
bool QuadrupedController::commanded_stance(int leg) const noexcept {
  return gait_.legs()[leg].stance && (contacts_.contact(leg) || !acting_schedule_[leg].stance);
}

Eigen::Vector3d QuadrupedController::foothold_offset(const QuadrupedInput& in, int leg) const noexcept {
  const double bound = kMaxFootholdOffset * legs_[leg].geometry().length();  // [m]
  return in.foothold_offset.segment<3>(3 * leg).cwiseMax(-bound).cwiseMin(bound);
}

// 8. Swing legs (and stance legs still looking for the ground): foothold, swing, IK, joint PD.
// Their motors push back on the trunk: the abduction and hip-pitch torques beyond gravity
// compensation are a moment on the trunk that the stance feet must cancel (measured: the swing
// legs' reaction pitched the trunk ~1.2 deg each step at 0.5 m/s).
void QuadrupedController::swing_legs(const QuadrupedInput& in, QuadrupedOutput& out) noexcept {
  Tick& k = tick_;
  const auto& schedule = gait_.legs();
  // The schedule runs for the commands: a swing command lands a delay later, so the foot's
  // reference and the state it is compared with are both taken there: the trunk and the swing
  // joints predicted one delay ahead (predict_swing), or the trunk now and the joints to first
  // order (q + delay qd, qd).
  const bool predict = cfg_.predict_swing;
  const Eigen::Matrix3d& R = predict ? k.R_pred : k.R;
  const Eigen::Vector3d& p = predict ? k.p_pred : k.p;
  const Eigen::Vector3d& v = predict ? k.v_pred : k.v;
  const Eigen::Vector3d& w_body = predict ? k.w_pred_body : k.w_body;
  const double tau_d = cfg_.actuation_delay;
  const double t_swing = gait_.swing_duration(), t_stance = gait_.stance_duration();
  InFlightEffect<Vector12d> joints{Vector12d::Zero(), Vector12d::Zero()};
  if (predict) joints = in_flight_effect(qdd_in_flight_, cfg_.dt);
  k.swing_reaction.setZero();  // trunk frame [N m]
  // The trunk's turn at the commanded yaw rate over half a stance [rad] (MIT Cheetah's foothold
  // rule; the target is taken again every tick as the trunk turns, so at touch-down it is the
  // hip at mid-stance). Measured in quadruped-turn (0.5 m/s, 0.5 rad/s, seeds 0-4), yaw rate
  // RMS error without it / with it: Go1 at 35 ms 0.094-0.096 / 0.082-0.083 (limit 0.1), ours
  // 0.085-0.087 / 0.047; at 10 ms Go1 0.059 / 0.068, ours 0.063 / 0.063, roll/pitch RMS lower on
  // every Unitree-class robot. The turn over the swing left as well (the hip at touch-down
  // turned on): Go1 at 10 ms 0.084, at 35 ms 2.4-2.8 deg roll/pitch RMS.
  const Eigen::Matrix3d half_stance_turn =
      Eigen::AngleAxisd(v_cmd_.z() * 0.5 * t_stance, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  for (int i = 0; i < kLegs; ++i) {
    if (k.stance[i]) continue;
    const Eigen::Vector3d q = in.q.segment<3>(3 * i), qd = in.qd.segment<3>(3 * i);
    const Eigen::Vector3d q_pred = q + tau_d * qd + joints.position.segment<3>(3 * i);
    const Eigen::Vector3d qd_pred = qd + joints.velocity.segment<3>(3 * i);
    const LegGeometry& g = legs_[i].geometry();
    const LegPhase& ph = schedule[i];
    Eigen::Vector3d p_foot, v_foot, a_foot = Eigen::Vector3d::Zero();
    if (!ph.stance) {
      if (was_stance_[i]) swing_start_[i] = k.p + k.R * k.meas[i].r;  // lift-off point
      // Raibert foothold: at mid-stance under the hip moved to the CoM's x (so that the diagonal
      // support line passes through the CoM), shifted against the velocity error; turning, the
      // hip turned on by half a stance (half_stance_turn).
      const Eigen::Vector3d hip =
          p + half_stance_turn * (R * (g.abd_origin + Eigen::Vector3d(com_.x() + cfg_.foothold_shift.x(),
                                                                      g.l_abd + cfg_.foothold_shift.y(), 0)));
      Eigen::Vector3d target = hip + v * ph.remaining + 0.5 * t_stance * k.v_des +
                               cfg_.raibert_gain * (v - k.v_des);
      target.z() = estimator_.ground_height(target.x(), target.y()) + cfg_.foot_radius -
                   cfg_.touchdown_depth;
      target += R * foothold_offset(in, i);
      swing_target_[i] = target;
      // The reference where the foot should be when this command lands, and (swing_feedforward)
      // the joint acceleration it asks for, fed forward through each joint's own inertia.
      const double ahead = cfg_.swing_feedforward && !predict && t_swing > 0 ? tau_d / t_swing : 0.0;
      const SwingSample s = sample_swing(swing_start_[i], target, cfg_.swing_height,
                                         std::min(ph.progress + ahead, 1.0), t_swing);
      p_foot = s.p;
      v_foot = s.v;
      a_foot = s.a;
      late_time_[i] = 0.0;
    } else {
      // Scheduled on the ground but no contact yet: keep reaching down until the foot finds it.
      if (was_stance_[i]) swing_target_[i] = k.p + k.R * k.meas[i].r;  // never swung: start from here
      late_time_[i] += cfg_.dt;
      p_foot = swing_target_[i] - Eigen::Vector3d(0, 0, kLateReachSpeed * late_time_[i]);
      v_foot = Eigen::Vector3d(0, 0, -kLateReachSpeed);
    }
    was_stance_[i] = false;
    const Eigen::Vector3d r_des = R.transpose() * (p_foot - p);
    Eigen::Vector3d q_des = q_leg_valid_[i];
    if (legs_[i].inverse(r_des, q_des) == Status::kOk) q_leg_valid_[i] = q_des;
    else k.status = worst(k.status, Status::kUnreachable);
    const Eigen::Vector3d v_rel = R.transpose() * (v_foot - v) - w_body.cross(r_des);
    const Eigen::Matrix3d Jd = legs_[i].jacobian(q_des);
    Eigen::Vector3d qd_des = Eigen::Vector3d::Zero(), qdd_des = Eigen::Vector3d::Zero();
    if (std::abs(Jd.determinant()) > 1e-6) {
      const Lu3 lu(Jd);
      qd_des = lu.solve(v_rel);
      if (cfg_.swing_feedforward) qdd_des = lu.solve(R.transpose() * a_foot);
    }
    const Eigen::Vector3d tau_pd = cfg_.swing_kp.cwiseProduct(q_des - (predict ? q_pred : q + tau_d * qd)) +
                                   cfg_.swing_kd.cwiseProduct(qd_des - (predict ? qd_pred : qd)) +
                                   swing_inertia_.cwiseProduct(qdd_des);
    out.tau.segment<3>(3 * i) = k.tau_gravity[i] + tau_pd;
    const Eigen::Vector3d& sg = g.sign;
    const double c0 = std::cos(sg[0] * q[0]), s0 = std::sin(sg[0] * q[0]);
    k.swing_reaction += sg[0] * tau_pd[0] * Eigen::Vector3d::UnitX() +
                        sg[1] * tau_pd[1] * Eigen::Vector3d(0, c0, s0);
  }
  if (cfg_.swing_reaction_feedforward) k.wrench.tail<3>() += k.R * k.swing_reaction;
}

// 8b. What the swing torques sent (after saturation) will do to their joints when they land,
// beyond gravity, through the leg's joint-space inertia (for the joint predictor; a stance leg's
// joints are held by the ground: 0).
void QuadrupedController::swing_joint_accelerations(const QuadrupedInput& in, const Vector12d& tau) noexcept {
  Tick& k = tick_;
  for (int i = 0; i < kLegs; ++i) {
    if (k.stance[i]) {
      k.qdd.segment<3>(3 * i).setZero();
      continue;
    }
    const Eigen::Vector3d torque = tau.segment<3>(3 * i) - k.tau_gravity[i];
    if (cfg_.swing_inertia_at_pose) {
      // H at the pose the command lands in (first order over the delay): a folded swing leg is
      // lighter about the hip than standing. Measured alternatives (35 ms): H at the pose now
      // lost Go1's gain (0.4 N s/kg push 2.45-3.84 deg); at the swing reference's pose, and with
      // the standing H for feet at or below the ground, our model still fell on compliant ground.
      const Eigen::Vector3d q_land =
          in.q.segment<3>(3 * i) + cfg_.actuation_delay * in.qd.segment<3>(3 * i);
      k.qdd.segment<3>(3 * i) = Ldlt3(leg_inertia_[i].at(q_land)).solve(torque);
    } else {
      k.qdd.segment<3>(3 * i) = leg_mass_inverse_[i] * torque;
    }
  }
}

// 8c. The trunk's angular acceleration when the torques sent (after saturation) land, from the
// floating base's dynamics with the legs' masses (predict_leg_dynamics, trunk_rotation.hpp); the
// rigid model of distribute_forces stays where it cannot be used (a straight stance leg).
void QuadrupedController::trunk_rotation_from_torques(const Vector12d& tau) noexcept {
  Tick& k = tick_;
  if (!cfg_.predict_in_flight || !cfg_.predict_leg_dynamics) return;
  LegTorques legs;
  for (int i = 0; i < kLegs; ++i) {
    legs.jacobian[i] = k.J[i];
    legs.foot[i] = k.meas[i].r - com_;
    legs.pinned[i] = k.stance[i];
    legs.torque[i] = tau.segment<3>(3 * i) - k.tau_gravity[i];
  }
  Vector6d a;
  if (trunk_acceleration(inertia_free_, legs, k.R.transpose() * Eigen::Vector3d(0, 0, -kGravity), &a))
    k.accel.tail<3>() = k.R * a.tail<3>();
}

// 9. Force distribution over the legs that are both scheduled and detected on the ground.
void QuadrupedController::distribute_forces(QuadrupedOutput& out) noexcept {
  Tick& k = tick_;
  out.wrench = k.wrench;
  std::array<Eigen::Vector3d, kLegs> feet;
  for (int i = 0; i < kLegs; ++i) feet[i] = k.R * (k.meas[i].r - com_);
  if (k.n_stance > 0) {
    const Status qp = force_qp_.solve(k.wrench, feet, k.stance, k.load, estimator_.ground_normal(), f_);
    k.status = worst(k.status, qp);
    out.qp_iterations = force_qp_.last_result().iterations;
  } else {
    f_.setZero();
    out.qp_iterations = 0;
  }
  out.foot_force = f_;
  // The trunk acceleration this command will produce when it lands (for the predictor): the
  // stance forces' wrench, less gravity and the swing legs' reaction, over mass and inertia.
  Eigen::Vector3d force = Eigen::Vector3d(0, 0, -kGravity * mass_), moment = -k.R * k.swing_reaction;
  for (int i = 0; i < kLegs; ++i) {
    force += f_.segment<3>(3 * i);
    moment += feet[i].cross(f_.segment<3>(3 * i));
  }
  int swinging = 0;  // the set of swing legs, bit i for leg i
  for (int i = 0; i < kLegs; ++i) swinging |= k.stance[i] ? 0 : 1 << i;
  const Eigen::Matrix3d& I_body = cfg_.predict_legs_free ? inertia_by_swing_set_[swinging] : inertia_;
  const Eigen::Matrix3d I_world = k.R * I_body * k.R.transpose();
  k.accel.head<3>() = force / mass_;
  k.accel.tail<3>() = Ldlt3(I_world).solve(moment);  // Eigen's ldlt() bit for bit (ldlt3.hpp)
}

// 10. Stance legs push with -J^T f.
void QuadrupedController::stance_legs(QuadrupedOutput& out) noexcept {
  Tick& k = tick_;
  for (int i = 0; i < kLegs; ++i) {
    if (!k.stance[i]) continue;
    out.tau.segment<3>(3 * i) =
        k.tau_gravity[i] - k.J[i].transpose() * (k.R.transpose() * f_.segment<3>(3 * i));
    late_time_[i] = 0.0;
    was_stance_[i] = true;
  }
}

}  // namespace kiloloop
