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

Status UrAnalyticIk::from_model(const RobotModel& model, UrAnalyticIk* out, std::string* why,
                                double tolerance) {
  if (!model.has_chain() || model.nq() != 6) {
    if (why) *why = "UR analytic IK needs a 6-joint serial chain";
    return Status::kModelError;
  }
  // Joint-frame poses at q = 0 from the model's own kinematics: FK of the chain truncated after
  // each joint. Here T_k = frame of the link moved by joint k = DH frame k-1 (at q = 0).
  const KDL::Chain& chain = model.chain();
  std::vector<Eigen::Isometry3d> frames;  // link frames of joints 1..6, then the tip
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  for (unsigned s = 0; s < chain.getNrOfSegments(); ++s) {
    const KDL::Segment& seg = chain.getSegment(s);
    const bool moving = seg.getJoint().getType() != KDL::Joint::None;
    const KDL::Frame f = seg.pose(0.0);
    Eigen::Isometry3d F = Eigen::Isometry3d::Identity();
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) F.linear()(r, c) = f.M(r, c);
      F.translation()[r] = f.p[r];
    }
    // A UR-shaped chain's moving segment ends in the link frame whose z is the joint axis.
    if (moving) frames.push_back(T * F);
    T = T * F;
  }
  frames.push_back(T);
  if (frames.size() != 7) {
    if (why) *why = "UR analytic IK: expected 6 moving joints";
    return Status::kModelError;
  }
  // Between consecutive joint frames: Tz(d) Tx(a) Rx(alpha).
  UrDhParameters p;
  double d[6], a[6];
  for (int i = 0; i < 6; ++i) {
    const Eigen::Isometry3d D = frames[i].inverse() * frames[i + 1];
    d[i] = D.translation().z();
    a[i] = D.translation().x();
  }
  p.d1 = d[0], p.a2 = a[1], p.a3 = a[2], p.d4 = d[3], p.d5 = d[4], p.d6 = d[5];
  const Eigen::Isometry3d base = frames[0];
  UrAnalyticIk ik;
  Eigen::Matrix<double, 6, 1> lo = model.lower(), hi = model.upper();
  Status s = configure(p, base, lo, hi, &ik, why);
  if (failed(s)) return s;
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
    const Vector6d e = pose_error(Tm, base * ik.forward(q));
    deviation = std::max({deviation, e.head<3>().norm(), e.tail<3>().norm()});
  }
  if (!(deviation <= tolerance)) {
    if (why)
      *why = "UR analytic IK: the chain's kinematics are not UR standard DH (deviation " +
             std::to_string(deviation) + " m/rad)";
    return Status::kModelError;
  }
  ik.deviation_ = deviation;
  *out = ik;
  return Status::kOk;
}

Eigen::Isometry3d UrAnalyticIk::forward(const Eigen::Matrix<double, 6, 1>& q) const noexcept {
  const double d[6] = {dh_.d1, 0.0, 0.0, dh_.d4, dh_.d5, dh_.d6};
  const double a[6] = {0.0, dh_.a2, dh_.a3, 0.0, 0.0, 0.0};
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  for (int i = 0; i < 6; ++i) T = T * dh(q[i], d[i], a[i], kAlpha[i]);
  return T;
}

Status UrAnalyticIk::solve(const Eigen::Isometry3d& target, const Eigen::Matrix<double, 6, 1>& seed,
                           Solutions& out, int* count) const noexcept {
  *count = 0;
  if (!target.matrix().allFinite()) return Status::kNonFiniteReference;
  if (!seed.allFinite()) return Status::kNonFiniteMeasurement;
  const UrDhParameters& p = dh_;
  const Eigen::Isometry3d T06 = base_inv_ * target;
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
      double t6 = seed[5];  // wrist singularity: t6 is free
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
        for (int i = 0; i < 6 && inside; ++i) inside = wrap_near(raw[i], seed[i], lower_[i], upper_[i], &q[i]);
        if (!inside) continue;
        cand.col(n) = q;
        dist[n] = (q - seed).squaredNorm();
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
  for (int i = 0; i < n; ++i) out.col(i) = cand.col(order[i]);
  *count = n;
  return n > 0 ? Status::kOk : Status::kUnreachable;
}

}  // namespace kiloloop
