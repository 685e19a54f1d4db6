#include "kiloloop/kinematics/leg_kinematics.hpp"

#include <cmath>

#include <kdl/chain.hpp>

namespace kiloloop {
namespace {

constexpr double kGeomTol = 1e-9;  // [m] URDF numbers are exact; anything else is a different layout

Eigen::Vector3d to_eigen(const KDL::Vector& v) { return {v.x(), v.y(), v.z()}; }

}  // namespace

Status leg_geometry_from_model(const RobotModel& model, const std::string& trunk,
                               const std::string& foot, LegGeometry* out, std::string* why) {
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
  const Eigen::Vector3d tip = to_eigen(T.p);
  const Eigen::Vector3d ex = Eigen::Vector3d::UnitX(), ey = Eigen::Vector3d::UnitY();
  if ((axes[0] - ex).norm() > kGeomTol || (axes[1] - ey).norm() > kGeomTol ||
      (axes[2] - ey).norm() > kGeomTol)
    return fail("joint axes must be x, y, y at q = 0");
  const Eigen::Vector3d abd_to_pitch = points[1] - points[0], pitch_to_knee = points[2] - points[1],
                        knee_to_foot = tip - points[2];
  if (std::abs(pitch_to_knee.x()) > kGeomTol || std::abs(pitch_to_knee.y()) > kGeomTol ||
      std::abs(knee_to_foot.x()) > kGeomTol || std::abs(knee_to_foot.y()) > kGeomTol ||
      std::abs(abd_to_pitch.z()) > kGeomTol)
    return fail("knee and foot must lie straight below the hip pitch axis at q = 0");
  LegGeometry g;
  // The abduction axis is the x line through points[0]; shift its point to the pitch joint's x
  // so that l_abd is purely lateral.
  g.abd_origin = points[0] + ex * abd_to_pitch.x();
  g.l_abd = abd_to_pitch.y();
  g.l_thigh = -pitch_to_knee.z();
  g.l_shank = -knee_to_foot.z();
  if (!(g.l_thigh > 0) || !(g.l_shank > 0)) return fail("thigh and shank must point down at q = 0");
  for (int i = 0; i < 3; ++i) {
    const auto& names_all = model.joint_names();
    int idx = -1;
    for (int k = 0; k < model.nq(); ++k)
      if (names_all[k] == names[i]) idx = k;
    if (idx >= 0) {
      g.lower[i] = model.lower()[idx];
      g.upper[i] = model.upper()[idx];
    }
  }
  *out = g;
  return Status::kOk;
}

Eigen::Vector3d LegKinematics::foot_position(const Eigen::Vector3d& q) const noexcept {
  const double s1 = std::sin(q[1]), c1 = std::cos(q[1]);
  const double s12 = std::sin(q[1] + q[2]), c12 = std::cos(q[1] + q[2]);
  // In the leg plane (abduction frame): x forward, z down the leg.
  const double x = -g_.l_thigh * s1 - g_.l_shank * s12;
  const double z = -g_.l_thigh * c1 - g_.l_shank * c12;
  const double s0 = std::sin(q[0]), c0 = std::cos(q[0]);
  return g_.abd_origin + Eigen::Vector3d(x, g_.l_abd * c0 - z * s0, g_.l_abd * s0 + z * c0);
}

Eigen::Matrix3d LegKinematics::jacobian(const Eigen::Vector3d& q) const noexcept {
  const double s1 = std::sin(q[1]), c1 = std::cos(q[1]);
  const double s12 = std::sin(q[1] + q[2]), c12 = std::cos(q[1] + q[2]);
  const double z = -g_.l_thigh * c1 - g_.l_shank * c12;
  const double dx_dq1 = -g_.l_thigh * c1 - g_.l_shank * c12, dx_dq2 = -g_.l_shank * c12;
  const double dz_dq1 = g_.l_thigh * s1 + g_.l_shank * s12, dz_dq2 = g_.l_shank * s12;
  const double s0 = std::sin(q[0]), c0 = std::cos(q[0]);
  Eigen::Matrix3d J;
  J(0, 0) = 0.0;
  J(1, 0) = -g_.l_abd * s0 - z * c0;
  J(2, 0) = g_.l_abd * c0 - z * s0;
  J(0, 1) = dx_dq1;
  J(1, 1) = -dz_dq1 * s0;
  J(2, 1) = dz_dq1 * c0;
  J(0, 2) = dx_dq2;
  J(1, 2) = -dz_dq2 * s0;
  J(2, 2) = dz_dq2 * c0;
  return J;
}

Status LegKinematics::inverse(const Eigen::Vector3d& foot, Eigen::Vector3d& q) const noexcept {
  const Eigen::Vector3d r = foot - g_.abd_origin;
  if (!r.allFinite()) return Status::kUnreachable;
  // Abduction: in the y-z plane the leg plane sits l_abd off the axis; the foot is below it.
  const double yz2 = r.y() * r.y() + r.z() * r.z();
  const double z2 = yz2 - g_.l_abd * g_.l_abd;
  if (z2 <= 0.0) return Status::kUnreachable;
  const double z = -std::sqrt(z2);
  const double q0 = std::atan2(r.z(), r.y()) - std::atan2(z, g_.l_abd);
  // Knee from the distance hip pitch axis -> foot in the leg plane (law of cosines).
  const double x = r.x();
  const double c2 = (x * x + z * z - g_.l_thigh * g_.l_thigh - g_.l_shank * g_.l_shank) /
                    (2.0 * g_.l_thigh * g_.l_shank);
  if (c2 > 1.0 || c2 < -1.0) return Status::kUnreachable;
  const double q2 = -std::acos(c2);
  const double a = g_.l_thigh + g_.l_shank * std::cos(q2), b = g_.l_shank * std::sin(q2);
  const double q1 = std::atan2(-x, -z) - std::atan2(b, a);
  // Wrap the abduction angle into (-pi, pi].
  const double q0w = std::atan2(std::sin(q0), std::cos(q0));
  const Eigen::Vector3d sol(q0w, q1, q2);
  if ((sol.array() < g_.lower.array()).any() || (sol.array() > g_.upper.array()).any())
    return Status::kUnreachable;
  q = sol;
  return Status::kOk;
}

}  // namespace kiloloop
