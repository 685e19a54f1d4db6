#include "kiloloop/kinematics/leg_kinematics.hpp"
#include "kiloloop/model/kdl_eigen.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>

#include <kdl/chain.hpp>
#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/jntarray.hpp>

namespace kiloloop {
namespace {

// [rad] How far a joint axis may lie off the trunk's x (abduction) or y (hip pitch, knee) at
// q = 0 and still count as that axis. Real URDFs write pi/2 as 1.57079 (6.3e-6 rad short) or
// 1.5708 (3.7e-6 rad long), so their hip frames' axes lie a few 1e-6 rad off; 1e-3 rad moves a
// foot 0.5 mm at 0.5 m of leg, far below the contact and estimation errors the controller
// handles. A real tilt (a canted hip, 0.1 rad and more) is another layout: refused by name.
constexpr double kAxisTol = 1e-3;
constexpr double kFkTol = 1e-9;    // [m] closed form vs KDL at test configurations, exact axes
constexpr double kDegreesPerRadian = 57.295779513082321;  // for messages (M_PI is POSIX only)

// [rad] The angle between the axis a (unit) and the line of e (+e or -e).
double angle_off(const Eigen::Vector3d& a, const Eigen::Vector3d& e) {
  return std::atan2(a.cross(e).norm(), std::abs(a.dot(e)));
}

// +1 / -1 when a lies within kAxisTol of +e / -e, 0 otherwise.
double axis_sign(const Eigen::Vector3d& a, const Eigen::Vector3d& e) {
  if (!(angle_off(a, e) <= kAxisTol)) return 0.0;
  return a.dot(e) > 0.0 ? 1.0 : -1.0;
}

std::string format_double(double x, const char* format) {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, x);
  return buf;
}

// [m] the foot point `offset` (foot link frame) in the frame T maps from. A zero offset is the
// link origin itself, T.p unchanged (no +-0 sums: robots without an offset keep their exact
// numbers).
Eigen::Vector3d foot_point(const KDL::Frame& T, const Eigen::Vector3d& offset) {
  if ((offset.array() == 0.0).all()) return to_eigen(T.p);
  return to_eigen(T * KDL::Vector(offset.x(), offset.y(), offset.z()));
}

// a and b bit for bit (+0 and -0 differ: their sines do).
bool same_double(double a, double b) {
  std::uint64_t ua, ub;
  std::memcpy(&ua, &a, sizeof a);
  std::memcpy(&ub, &b, sizeof b);
  return ua == ub;
}

}  // namespace

KneeBends allowed_bends(const LegGeometry& g) {
  const double b0 = g.sign[2] * g.lower[2] + g.a_shank - g.a_thigh;  // bend at the limits
  const double b1 = g.sign[2] * g.upper[2] + g.a_shank - g.a_thigh;
  KneeBends out;
  out.backward = std::min(b0, b1) < -1e-9;
  out.forward = std::max(b0, b1) > 1e-9;
  return out;
}

Status leg_geometry_from_model(const RobotModel& model, const std::string& trunk,
                               const std::string& foot, LegGeometry* out, std::string* why,
                               KneeDirection knee, const Eigen::Vector3d& foot_offset) {
  auto fail = [&](const std::string& msg) {
    if (why) *why = "leg '" + foot + "': " + msg;
    return Status::kModelError;
  };
  KDL::Chain chain;
  if (!model.tree().getChain(trunk, foot, chain)) return fail("no chain from '" + trunk + "'");
  // Joint points and axes at q = 0, in the trunk frame.
  Eigen::Vector3d points[3], axes[3];
  std::string names[3];
  int j = 0;
  KDL::Frame T = KDL::Frame::Identity();
  for (const KDL::Segment& seg : chain.segments) {
    const KDL::Joint& joint = seg.getJoint();
    if (joint.getType() != KDL::Joint::None) {
      if (j == 3) return fail("more than 3 joints");
      points[j] = to_eigen(T * joint.JointOrigin());
      axes[j] = to_eigen(T.M * joint.JointAxis());
      names[j] = joint.getName();
      ++j;
    }
    T = T * seg.pose(0.0);
  }
  if (j != 3) return fail("expected 3 joints, found " + std::to_string(j));
  // The offset is a point on the shank, near the foot: finite, and shorter than the shank
  // (anything longer is a unit or frame mistake, e.g. millimetres or the trunk frame).
  const double shank = (to_eigen(T.p) - points[2]).norm();
  if (!foot_offset.allFinite() || !(foot_offset.norm() < shank))
    return fail("foot_offset (" + std::to_string(foot_offset.norm()) + " m) must be finite and "
                "shorter than the shank (" + std::to_string(shank) + " m, knee axis -> foot link "
                "origin): the contact sphere's centre in the foot link's frame [m]");
  const Eigen::Vector3d tip = foot_point(T, foot_offset);
  const Eigen::Vector3d ex = Eigen::Vector3d::UnitX(), ey = Eigen::Vector3d::UnitY();
  LegGeometry g;
  const Eigen::Vector3d expected[3] = {ex, ey, ey};
  const char* roles[3] = {"abduction", "hip pitch", "knee"};
  double worst_off = 0.0;  // [rad]
  for (int i = 0; i < 3; ++i) {
    g.sign[i] = axis_sign(axes[i], expected[i]);
    const double off = angle_off(axes[i], expected[i]);
    if (g.sign[i] == 0.0)
      return fail("joint '" + names[i] + "' (" + roles[i] + ") has its axis " +
                  format_double(off * kDegreesPerRadian, "%.4g") + " deg off the trunk's " +
                  (i == 0 ? "x" : "y") + " axis at q = 0; the leg kinematics take abduction / hip "
                  "pitch / knee legs whose axes lie within " +
                  format_double(kAxisTol * kDegreesPerRadian, "%.3g") + " deg of x, y, y "
                  "(canted or rotated joint axes are not supported)");
    worst_off = std::max(worst_off, off);
  }
  const Eigen::Vector3d abd_to_pitch = points[1] - points[0], pitch_to_knee = points[2] - points[1],
                        knee_to_foot = tip - points[2];
  // The abduction axis is the x line through points[0]; its point moves to the pitch joint's x.
  // Every y offset after it lies along the pitch axis and only shifts the leg plane sideways.
  g.abd_origin = points[0] + ex * abd_to_pitch.x();
  g.l_abd = abd_to_pitch.y() + pitch_to_knee.y() + knee_to_foot.y();
  g.h_abd = abd_to_pitch.z();
  g.l_thigh = std::hypot(pitch_to_knee.x(), pitch_to_knee.z());
  g.l_shank = std::hypot(knee_to_foot.x(), knee_to_foot.z());
  if (!(g.l_thigh > 1e-4) || !(g.l_shank > 1e-4)) return fail("thigh and shank must have length");
  // (-l sin a, -l cos a) is the segment at q = 0.
  g.a_thigh = std::atan2(-pitch_to_knee.x(), -pitch_to_knee.z());
  g.a_shank = std::atan2(-knee_to_foot.x(), -knee_to_foot.z());
  for (int i = 0; i < 3; ++i) {
    const auto& names_all = model.joint_names();
    for (int k = 0; k < model.nq(); ++k)
      if (names_all[k] == names[i]) {
        g.lower[i] = model.lower()[k];
        g.upper[i] = model.upper()[k];
      }
  }
  if (knee == KneeDirection::kAuto)
    knee = allowed_bends(g).backward ? KneeDirection::kBackward : KneeDirection::kForward;
  g.knee = knee;
  // The closed form must reproduce KDL's FK (catches layouts the algebra above cannot express).
  // Axes a little off (rounded angles) move the foot by at most that angle times each lever
  // after it: the tolerance grows by worst_off times the leg's total lever length, three times.
  const LegKinematics leg(g);
  KDL::ChainFkSolverPos_recursive fk(chain);
  KDL::JntArray qk(3);
  const double levers = abd_to_pitch.norm() + pitch_to_knee.norm() + knee_to_foot.norm();
  const double tol = kFkTol + 3.0 * worst_off * levers;  // [m]
  const double probes[3][3] = {{0.3, 0.7, -1.2}, {-0.4, -0.5, 1.1}, {0.1, 1.9, 0.4}};
  for (const auto& p : probes) {
    for (int k = 0; k < 3; ++k) qk(k) = p[k];
    KDL::Frame Tq;
    fk.JntToCart(qk, Tq);
    const double err =
        (leg.foot_position(Eigen::Vector3d(p[0], p[1], p[2])) - foot_point(Tq, foot_offset)).norm();
    if (!(err <= tol))
      return fail("layout not supported: the abduction / pitch / knee closed form misses the "
                  "URDF's foot position by " + format_double(err * 1e3, "%.3g") + " mm (allowed " +
                  format_double(tol * 1e3, "%.3g") + " mm) at q = (" + format_double(p[0], "%g") +
                  ", " + format_double(p[1], "%g") + ", " + format_double(p[2], "%g") +
                  "): a pitch or knee axis not parallel to the hip pitch axis, or an offset "
                  "along an axis the closed form cannot express");
  }
  *out = g;
  return Status::kOk;
}

// The joint angles' sines and cosines, once: the foot and its Jacobian are read off them.
inline LegKinematics::Angles LegKinematics::angles(const Eigen::Vector3d& qj) const noexcept {
  const Eigen::Vector3d q = qj.cwiseProduct(g_.sign);
  const double p1 = q[1] + g_.a_thigh, p12 = q[1] + q[2] + g_.a_shank;
  Angles a;
  a.q0 = q[0], a.p1 = p1;
  a.s1 = std::sin(p1), a.c1 = std::cos(p1), a.s12 = std::sin(p12), a.c12 = std::cos(p12);
  a.s0 = std::sin(q[0]), a.c0 = std::cos(q[0]);
  // In the leg plane (abduction frame): x forward, z down the leg.
  a.z = g_.h_abd - g_.l_thigh * a.c1 - g_.l_shank * a.c12;
  return a;
}

inline Eigen::Vector3d LegKinematics::foot_from(const Angles& a) const noexcept {
  const double x = -g_.l_thigh * a.s1 - g_.l_shank * a.s12;
  return g_.abd_origin + Eigen::Vector3d(x, g_.l_abd * a.c0 - a.z * a.s0, g_.l_abd * a.s0 + a.z * a.c0);
}

inline Eigen::Matrix3d LegKinematics::jacobian_from(const Angles& a) const noexcept {
  const double dx_dq1 = -g_.l_thigh * a.c1 - g_.l_shank * a.c12, dx_dq2 = -g_.l_shank * a.c12;
  const double dz_dq1 = g_.l_thigh * a.s1 + g_.l_shank * a.s12, dz_dq2 = g_.l_shank * a.s12;
  Eigen::Matrix3d J;
  J(0, 0) = 0.0;
  J(1, 0) = -g_.l_abd * a.s0 - a.z * a.c0;
  J(2, 0) = g_.l_abd * a.c0 - a.z * a.s0;
  J(0, 1) = dx_dq1;
  J(1, 1) = -dz_dq1 * a.s0;
  J(2, 1) = dz_dq1 * a.c0;
  J(0, 2) = dx_dq2;
  J(1, 2) = -dz_dq2 * a.s0;
  J(2, 2) = dz_dq2 * a.c0;
  return J * g_.sign.asDiagonal();
}

Eigen::Vector3d LegKinematics::foot_position(const Eigen::Vector3d& q) const noexcept {
  return foot_from(angles(q));
}

Eigen::Matrix3d LegKinematics::jacobian(const Eigen::Vector3d& q) const noexcept {
  return jacobian_from(angles(q));
}

void LegKinematics::foot_and_jacobian(const Eigen::Vector3d& q, Eigen::Vector3d* foot,
                                      Eigen::Matrix3d* jacobian, Trig* trig) const noexcept {
  const Angles a = angles(q);
  *foot = foot_from(a);
  *jacobian = jacobian_from(a);
  if (!trig) return;
  trig->pitch_axis = Eigen::Vector3d(0.0, a.c0, a.s0);
  trig->c0 = a.c0, trig->s0 = a.s0;
  trig->c1 = a.c1, trig->s1 = a.s1;
  trig->c12 = a.c12, trig->s12 = a.s12;
}

Status LegKinematics::inverse(const Eigen::Vector3d& foot, Eigen::Vector3d& q) const noexcept {
  const Eigen::Vector3d r = foot - g_.abd_origin;
  if (!r.allFinite()) return Status::kUnreachable;
  // Abduction: in the y-z plane the leg plane sits l_abd off the axis; the foot is below it.
  const double yz2 = r.y() * r.y() + r.z() * r.z();
  const double z2 = yz2 - g_.l_abd * g_.l_abd;
  if (z2 <= 0.0) return Status::kUnreachable;
  const double zz = -std::sqrt(z2);  // abduction-frame z of the foot
  const double q0 = std::atan2(r.z(), r.y()) - std::atan2(zz, g_.l_abd);
  // Knee bend from the distance hip pitch axis -> foot in the leg plane (law of cosines).
  const double x = r.x(), z = zz - g_.h_abd;
  const double c2 = (x * x + z * z - g_.l_thigh * g_.l_thigh - g_.l_shank * g_.l_shank) /
                    (2.0 * g_.l_thigh * g_.l_shank);
  if (c2 > 1.0 || c2 < -1.0) return Status::kUnreachable;
  const double beta = g_.knee == KneeDirection::kForward ? std::acos(c2) : -std::acos(c2);
  const double sin_beta = std::sin(beta), cos_beta = std::cos(beta);
  const double a = g_.l_thigh + g_.l_shank * cos_beta, b = g_.l_shank * sin_beta;
  const double p1 = std::atan2(-x, -z) - std::atan2(b, a);
  // Back to joint angles: internal q1 = p1 - a_thigh, q2 = beta - (a_shank - a_thigh), each
  // wrapped into (-pi, pi], then the axis signs. Where q2 is beta itself, the same double (a
  // shank in line with the thigh at q = 0: a_shank == a_thigh, most legs), its sine and cosine
  // are beta's, already at hand.
  auto wrap = [](double v) { return std::atan2(std::sin(v), std::cos(v)); };
  const double knee = beta - g_.a_shank + g_.a_thigh;
  const double knee_wrapped = same_double(knee, beta) ? std::atan2(sin_beta, cos_beta) : wrap(knee);
  const Eigen::Vector3d internal(wrap(q0), wrap(p1 - g_.a_thigh), knee_wrapped);
  const Eigen::Vector3d sol = internal.cwiseProduct(g_.sign);
  if ((sol.array() < g_.lower.array()).any() || (sol.array() > g_.upper.array()).any())
    return Status::kUnreachable;
  q = sol;
  return Status::kOk;
}

}  // namespace kiloloop
