#include "kiloloop/kinematics/ur_analytic_ik.hpp"

#include <algorithm>
#include <string>
#include <cmath>
#include <random>

#include "kiloloop/kinematics/chain_kinematics.hpp"

namespace kiloloop {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kAlpha[6] = {kPi / 2, 0.0, 0.0, kPi / 2, -kPi / 2, 0.0};

// Standard DH link transform Rz(theta) Tz(d) Tx(a) Rx(alpha).
Eigen::Isometry3d dh(double theta, double d, double a, double alpha) {
  const double ct = std::cos(theta), st = std::sin(theta);
  const double ca = std::cos(alpha), sa = std::sin(alpha);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() << ct, -st * ca, st * sa, st, ct * ca, -ct * sa, 0, sa, ca;
  T.translation() << a * ct, a * st, d;
  return T;
}

// Nearest value to `seed` among angle + 2 pi k inside [lo, hi]; false when there is none.
bool wrap_near(double angle, double seed, double lo, double hi, double* out) {
  const double two_pi = 2.0 * kPi;
  double best = angle + two_pi * std::round((seed - angle) / two_pi);
  // The nearest may be outside the limits while a farther one is inside: try the neighbours.
  double chosen = 0.0, chosen_dist = std::numeric_limits<double>::infinity();
  for (int k = -1; k <= 1; ++k) {
    const double c = best + k * two_pi;
    if (c < lo || c > hi) continue;
    const double dist = std::abs(c - seed);
    if (dist < chosen_dist) chosen = c, chosen_dist = dist;
  }
  if (!std::isfinite(chosen_dist)) return false;
  *out = chosen;
  return true;
}

}  // namespace

std::vector<DhLink> UrDhParameters::table() const {
  const double d[6] = {d1, 0.0, 0.0, d4, d5, d6};
  const double a[6] = {0.0, a2, a3, 0.0, 0.0, 0.0};
  std::vector<DhLink> links(6);
  for (int i = 0; i < 6; ++i) {
    links[i].d = d[i];
    links[i].a = a[i];
    links[i].alpha = kAlpha[i];
  }
  return links;
}

Status UrAnalyticIk::configure(const UrDhParameters& p, const Eigen::Isometry3d& base,
                               const Eigen::Matrix<double, 6, 1>& lower,
                               const Eigen::Matrix<double, 6, 1>& upper, UrAnalyticIk* out,
                               std::string* why) {
  const double v[6] = {p.d1, p.a2, p.a3, p.d4, p.d5, p.d6};
  for (double x : v) {
    if (!std::isfinite(x)) {
      if (why) *why = "UR DH parameters must be finite";
      return Status::kInvalidConfig;
    }
  }
  if (p.a2 == 0.0 || p.a3 == 0.0 || p.d6 == 0.0) {
    if (why) *why = "UR DH parameters: a2, a3 and d6 must be non-zero";
    return Status::kInvalidConfig;
  }
  if (!(lower.array() <= upper.array()).all()) {
    if (why) *why = "UR IK: joint limits must satisfy lower <= upper";
    return Status::kInvalidConfig;
  }
  UrAnalyticIk ik;
  ik.dh_ = p;
  ik.base_ = base;
  ik.base_inv_ = base.inverse();
  ik.lower_ = lower;
  ik.upper_ = upper;
  *out = ik;
  return Status::kOk;
}

namespace {

// A joint axis as a line in the root frame at q = 0.
struct Line {
  Eigen::Vector3d u;  // unit direction (the joint's positive rotation)
  Eigen::Vector3d p;  // a point on it [m]
};

// The point of `b` nearest to line `a`, and the distance between the lines [m]. Parallel lines
// give b.p and their distance.
Eigen::Vector3d nearest_on(const Line& a, const Line& b, double* distance) {
  const Eigen::Vector3d w = b.p - a.p;
  const double c = a.u.dot(b.u), den = 1.0 - c * c;
  double t = 0.0;  // along b
  if (den > 1e-12) t = (c * a.u.dot(w) - b.u.dot(w)) / den;
  const Eigen::Vector3d on_b = b.p + t * b.u;
  const Eigen::Vector3d rel = on_b - a.p;
  *distance = (rel - a.u * a.u.dot(rel)).norm();
  return on_b;
}

// Angle from x_from to x_to about z (both perpendicular to z) [rad].
double angle_about(const Eigen::Vector3d& x_from, const Eigen::Vector3d& x_to, const Eigen::Vector3d& z) {
  return std::atan2(x_from.cross(x_to).dot(z), x_from.dot(x_to));
}

Eigen::Isometry3d frame(const Eigen::Vector3d& x, const Eigen::Vector3d& z, const Eigen::Vector3d& o) {
  Eigen::Isometry3d F = Eigen::Isometry3d::Identity();
  F.linear().col(0) = x;
  F.linear().col(1) = z.cross(x);
  F.linear().col(2) = z;
  F.translation() = o;
  return F;
}

// x_i along +-n (unit), the sign giving the smaller DH offset from x_prev about z: a URDF whose
// zero pose is the DH zero pose gets zero offsets (and UR's negative a2, a3).
Eigen::Vector3d x_nearest(const Eigen::Vector3d& n, const Eigen::Vector3d& x_prev, const Eigen::Vector3d& z) {
  return std::abs(angle_about(x_prev, n, z)) <= 0.5 * kPi + 1e-12 ? n : Eigen::Vector3d(-n);
}

double sign_of(double v) { return v < 0.0 ? -1.0 : 1.0; }

std::string joint_label(const std::vector<std::string>& names, int i) {
  return "joint " + std::to_string(i + 1) + " ('" + names[i] + "')";
}

// The UR geometry of a chain, read off its joint axes at q = 0 (see from_model).
struct UrFit {
  UrDhParameters dh;
  Eigen::Isometry3d base, tool;
  Eigen::Matrix<double, 6, 1> sign, offset;
};

Status fit_ur(const RobotModel& model, double tol, UrFit* fit, std::string* why) {
  auto fail = [&](const std::string& msg) {
    if (why) *why = "UR analytic IK: not a UR-style arm: " + msg;
    return Status::kModelError;
  };
  if (!model.has_chain() || model.nq() != 6) return fail("the chain must have 6 joints");
  const KDL::Chain& chain = model.chain();
  const std::vector<std::string>& names = model.joint_names();
  std::vector<Line> L;
  KDL::Frame T = KDL::Frame::Identity();
  for (unsigned s = 0; s < chain.getNrOfSegments(); ++s) {
    const KDL::Joint& j = chain.getSegment(s).getJoint();
    if (j.getType() == KDL::Joint::TransAxis || j.getType() == KDL::Joint::TransX ||
        j.getType() == KDL::Joint::TransY || j.getType() == KDL::Joint::TransZ)
      return fail(joint_label(names, static_cast<int>(L.size())) + " is prismatic");
    if (j.getType() != KDL::Joint::None) {
      const KDL::Vector u = T.M * j.JointAxis(), p = T * j.JointOrigin();
      L.push_back({Eigen::Vector3d(u.x(), u.y(), u.z()).normalized(), Eigen::Vector3d(p.x(), p.y(), p.z())});
    }
    T = T * chain.getSegment(s).pose(0.0);
  }
  Eigen::Isometry3d T_tip = Eigen::Isometry3d::Identity();
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) T_tip.linear()(r, c) = T.M(r, c);
    T_tip.translation()[r] = T.p[r];
  }
  auto perpendicular = [&](int i, int j) { return std::abs(L[i].u.dot(L[j].u)) <= tol; };
  auto parallel = [&](int i, int j) { return L[i].u.cross(L[j].u).norm() <= tol; };
  auto label = [&](int i) { return joint_label(names, i); };
  UrFit f;
  f.sign.setOnes();
  double dist = 0.0;

  // Joint 1 -> DH frame 0 (z0 = axis 1); rows 1..6 below are the standard DH rows.
  const Eigen::Vector3d z0 = L[0].u;
  // Row 1: alpha = +pi/2, a = 0: axes 1 and 2 perpendicular and meeting.
  if (!perpendicular(0, 1)) return fail(label(1) + " axis not perpendicular to " + label(0));
  const Eigen::Vector3d O1 = nearest_on(L[0], L[1], &dist);
  if (dist > tol) return fail(label(0) + " and " + label(1) + " axes do not intersect (" + std::to_string(dist) + " m apart)");
  const Eigen::Vector3d x1 = z0.cross(L[1].u).normalized();
  const Eigen::Vector3d z1 = x1.cross(z0);  // Rx(+pi/2) takes z0 to z1
  // Frame 0: origin at the root origin's foot on axis 1 (so d1 is the height of the shoulder
  // above the root, as in UR's tables), x0 = x1 at q = 0 (offset 0).
  const Eigen::Vector3d O0 = L[0].p - z0 * z0.dot(L[0].p);
  f.dh.d1 = (O1 - O0).dot(z0);
  f.base = frame(x1, z0, O0);
  f.offset[0] = 0.0;
  // Rows 2, 3: alpha = 0, d = 0: axes 2, 3, 4 parallel; a2, a3 their distances.
  Eigen::Vector3d x_prev = x1, O_prev = O1;
  for (int i = 2; i <= 3; ++i) {
    if (!parallel(i, i - 1)) return fail(label(i) + " axis not parallel to " + label(i - 1));
    f.sign[i] = sign_of(L[i].u.dot(z1));
    // The foot on axis i+1 of the plane through O_prev perpendicular to z1.
    const Eigen::Vector3d O = L[i].p + z1 * z1.dot(O_prev - L[i].p);
    const Eigen::Vector3d n = O - O_prev;
    if (n.norm() <= tol) return fail(label(i - 1) + " and " + label(i) + " axes coincide");
    const Eigen::Vector3d x = x_nearest(n.normalized(), x_prev, z1);
    (i == 2 ? f.dh.a2 : f.dh.a3) = n.dot(x);
    f.offset[i - 1] = angle_about(x_prev, x, z1);
    x_prev = x, O_prev = O;
  }
  // Row 4: alpha = +pi/2, a = 0: axes 4 and 5 perpendicular and meeting, d4 along axis 4.
  if (!perpendicular(4, 3)) return fail(label(4) + " axis not perpendicular to " + label(3));
  const Eigen::Vector3d O4 = nearest_on(L[3], L[4], &dist);
  if (dist > tol) return fail(label(3) + " and " + label(4) + " axes do not intersect (" + std::to_string(dist) + " m apart)");
  f.dh.d4 = (O4 - O_prev).dot(z1);
  const Eigen::Vector3d x4 = x_nearest(z1.cross(L[4].u).normalized(), x_prev, z1);
  const Eigen::Vector3d z4 = x4.cross(z1);
  f.offset[3] = angle_about(x_prev, x4, z1);
  f.sign[4] = sign_of(L[4].u.dot(z4));
  // Row 5: alpha = -pi/2, a = 0: axes 5 and 6 perpendicular and meeting, d5 along axis 5.
  if (!perpendicular(5, 4)) return fail(label(5) + " axis not perpendicular to " + label(4));
  const Eigen::Vector3d O5 = nearest_on(L[4], L[5], &dist);
  if (dist > tol) return fail(label(4) + " and " + label(5) + " axes do not intersect (" + std::to_string(dist) + " m apart)");
  f.dh.d5 = (O5 - O4).dot(z4);
  const Eigen::Vector3d x5 = x_nearest(z4.cross(L[5].u).normalized(), x4, z4);
  const Eigen::Vector3d z5 = z4.cross(x5);  // Rx(-pi/2) takes z4 to z5
  f.offset[4] = angle_about(x4, x5, z4);
  f.sign[5] = sign_of(L[5].u.dot(z5));
  // Row 6: alpha = 0, a = 0: frame 6 on axis 6 level with the tip, x6 = x5 at q = 0. The closed
  // form needs the flange off the wrist centre (d6 != 0); for a tip at the wrist centre a virtual
  // flange 0.1 m out is used (the tool transform absorbs it).
  f.dh.d6 = (T_tip.translation() - O5).dot(z5);
  if (std::abs(f.dh.d6) < 1e-3) f.dh.d6 = 0.1;
  f.offset[5] = 0.0;
  f.tool = frame(x5, z5, O5 + f.dh.d6 * z5).inverse() * T_tip;
  // Joint 2 goes with z1 by construction (x1 = z0 x axis 2).
  f.sign[0] = 1.0, f.sign[1] = 1.0;
  *fit = f;
  return Status::kOk;
}

}  // namespace

Status UrAnalyticIk::from_model(const RobotModel& model, UrAnalyticIk* out, std::string* why,
                                double tolerance) {
  UrFit f;
  Status s = fit_ur(model, tolerance, &f, why);
  if (failed(s)) return s;
  // Limits in DH angles: theta = sign q + offset.
  Eigen::Matrix<double, 6, 1> lo, hi;
  for (int i = 0; i < 6; ++i) {
    const double a = f.sign[i] * model.lower()[i] + f.offset[i], b = f.sign[i] * model.upper()[i] + f.offset[i];
    lo[i] = std::min(a, b), hi[i] = std::max(a, b);
  }
  UrAnalyticIk ik;
  s = configure(f.dh, f.base, lo, hi, &ik, why);
  if (failed(s)) return s;
  ik.tool_ = f.tool;
  ik.tool_inv_ = f.tool.inverse();
  ik.sign_ = f.sign;
  ik.offset_ = f.offset;
  // The hypothesis "this chain is UR standard DH" is checked, not assumed.
  ChainKinematics kin;
  s = ChainKinematics::configure(model, &kin, why);
  if (failed(s)) return s;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-kPi, kPi);
  double deviation = 0.0;
  for (int k = 0; k < 20; ++k) {
    Eigen::Matrix<double, 6, 1> q;
    for (int i = 0; i < 6; ++i) q[i] = u(rng);
    Eigen::Isometry3d Tm;
    kin.forward(q, Tm);
    const Vector6d e = pose_error(Tm, ik.forward(q));
    deviation = std::max({deviation, e.head<3>().norm(), e.tail<3>().norm()});
  }
  if (!(deviation <= tolerance)) {
    if (why)
      *why = "UR analytic IK: not a UR-style arm: the chain's FK deviates from the identified UR geometry by " +
             std::to_string(deviation) + " m/rad (tolerance " + std::to_string(tolerance) + ")";
    return Status::kModelError;
  }
  ik.deviation_ = deviation;
  *out = ik;
  return Status::kOk;
}

Eigen::Isometry3d UrAnalyticIk::forward(const Eigen::Matrix<double, 6, 1>& q) const noexcept {
  const double d[6] = {dh_.d1, 0.0, 0.0, dh_.d4, dh_.d5, dh_.d6};
  const double a[6] = {0.0, dh_.a2, dh_.a3, 0.0, 0.0, 0.0};
  Eigen::Isometry3d T = base_;
  for (int i = 0; i < 6; ++i) T = T * dh(sign_[i] * q[i] + offset_[i], d[i], a[i], kAlpha[i]);
  return T * tool_;
}

Status UrAnalyticIk::solve(const Eigen::Isometry3d& target, const Eigen::Matrix<double, 6, 1>& seed,
                           Solutions& out, int* count) const noexcept {
  *count = 0;
  if (!target.matrix().allFinite()) return Status::kNonFiniteReference;
  if (!seed.allFinite()) return Status::kNonFiniteMeasurement;
  const UrDhParameters& p = dh_;
  const Eigen::Isometry3d T06 = base_inv_ * target * tool_inv_;
  // The seed in DH angles; solutions are mapped back to joint positions at the end.
  const Eigen::Matrix<double, 6, 1> seed_t = sign_.cwiseProduct(seed) + offset_;
  const Eigen::Matrix3d& R = T06.linear();
  const Eigen::Vector3d p06 = T06.translation();
  const Eigen::Vector3d p05 = p06 - p.d6 * R.col(2);
  const double r = std::hypot(p05.x(), p05.y());
  // Tolerance for arguments of asin/acos a hair outside [-1, 1] from rounding.
  constexpr double kSlack = 1e-10;
  if (r < std::abs(p.d4) * (1.0 - kSlack)) return Status::kUnreachable;
  const double psi = std::atan2(p05.y(), p05.x());
  const double phi = std::asin(std::clamp(p.d4 / r, -1.0, 1.0));
  const double t1s[2] = {psi + phi, psi + kPi - phi};
  Solutions cand;
  double dist[kMaxSolutions];
  int n = 0;
  for (double t1 : t1s) {
    const double s1 = std::sin(t1), c1 = std::cos(t1);
    const double c5 = (p06.x() * s1 - p06.y() * c1 - p.d4) / p.d6;
    if (std::abs(c5) > 1.0 + kSlack) continue;
    const double t5a = std::acos(std::clamp(c5, -1.0, 1.0));
    // z1 (base frame) expressed in frame 6 gives theta6.
    const Eigen::Vector3d z1(s1, -c1, 0.0);
    const Eigen::Vector3d v = R.transpose() * z1;
    for (double t5 : {t5a, -t5a}) {
      const double s5 = std::sin(t5);
      double t6 = seed_t[5];  // wrist singularity: t6 is free
      if (std::abs(s5) > 1e-10) t6 = std::atan2(-v.y() / s5, v.x() / s5);
      // Frames 1 -> 4 in the plane of the parallel joints 2, 3, 4.
      const Eigen::Isometry3d T14 = dh(t1, p.d1, 0.0, kAlpha[0]).inverse() * T06 *
                                    (dh(t5, p.d5, 0.0, kAlpha[4]) * dh(t6, p.d6, 0.0, 0.0)).inverse();
      const double x = T14.translation().x(), y = T14.translation().y();
      const double c3 = (x * x + y * y - p.a2 * p.a2 - p.a3 * p.a3) / (2.0 * p.a2 * p.a3);
      if (std::abs(c3) > 1.0 + kSlack) continue;
      const double t3a = std::acos(std::clamp(c3, -1.0, 1.0));
      // Orientation of frame 4 in frame 1: Rz(t2 + t3 + t4) Rx(pi/2).
      const double t234 = std::atan2(T14.linear()(1, 0), T14.linear()(0, 0));
      for (double t3 : {t3a, -t3a}) {
        const double t2 = std::atan2(y, x) - std::atan2(p.a3 * std::sin(t3), p.a2 + p.a3 * std::cos(t3));
        const double t4 = t234 - t2 - t3;
        const double raw[6] = {t1, t2, t3, t4, t5, t6};
        Eigen::Matrix<double, 6, 1> q;
        bool inside = true;
        for (int i = 0; i < 6 && inside; ++i) inside = wrap_near(raw[i], seed_t[i], lower_[i], upper_[i], &q[i]);
        if (!inside) continue;
        cand.col(n) = q;
        dist[n] = (q - seed_t).squaredNorm();  // |sign| = 1: the same distance in joint space
        ++n;
      }
    }
  }
  // Insertion sort by distance to the seed (n <= 8), stable: deterministic order on ties.
  int order[kMaxSolutions];
  for (int i = 0; i < n; ++i) order[i] = i;
  for (int i = 1; i < n; ++i) {
    const int key = order[i];
    int j = i - 1;
    while (j >= 0 && dist[order[j]] > dist[key]) {
      order[j + 1] = order[j];
      --j;
    }
    order[j + 1] = key;
  }
  for (int i = 0; i < n; ++i) out.col(i) = sign_.cwiseProduct(cand.col(order[i]) - offset_);
  *count = n;
  return n > 0 ? Status::kOk : Status::kUnreachable;
}

}  // namespace kiloloop
