#include "kiloloop/trajectory/trapezoid.hpp"

#include <cmath>
#include <limits>

#include "kiloloop/trajectory/segment_lookup.hpp"

namespace kiloloop {
namespace {

// Shortest rest-to-rest time over distance d >= 0 with limits v, a > 0.
double min_time(double d, double v, double a) {
  if (d <= 0.0) return 0.0;
  if (d >= v * v / a) return d / v + v / a;  // reaches the cruise velocity
  return 2.0 * std::sqrt(d / a);             // triangular
}

}  // namespace

Status TrapezoidTrajectory::configure(const Eigen::MatrixXd& waypoints, const Eigen::VectorXd& v_max,
                                      const Eigen::VectorXd& a_max, double t0,
                                      TrapezoidTrajectory* out, std::string* why) {
  auto fail = [&](const char* msg) {
    if (why) *why = msg;
    return Status::kInvalidConfig;
  };
  const Eigen::Index n = waypoints.rows(), m = waypoints.cols();
  if (n < 1 || m < 2) return fail("need at least one joint and two waypoints");
  if (v_max.size() != n || a_max.size() != n) return fail("v_max and a_max must have nq entries");
  if (!waypoints.allFinite()) return fail("waypoints must be finite");
  if (!v_max.allFinite() || !a_max.allFinite() || (v_max.array() <= 0.0).any() ||
      (a_max.array() <= 0.0).any())
    return fail("v_max and a_max must be finite and > 0");
  if (!std::isfinite(t0)) return fail("t0 must be finite");

  TrapezoidTrajectory traj;
  traj.times_.resize(m);
  traj.times_[0] = t0;
  traj.start_ = waypoints.leftCols(m - 1);
  traj.delta_ = waypoints.rightCols(m - 1) - waypoints.leftCols(m - 1);
  traj.vel_.resize(m - 1);
  traj.acc_.resize(m - 1);
  constexpr double kInf = std::numeric_limits<double>::infinity();
  for (Eigen::Index k = 0; k + 1 < m; ++k) {
    // Limits of the path parameter s in [0, 1]: the tightest joint decides.
    double v = kInf, a = kInf;
    for (Eigen::Index j = 0; j < n; ++j) {
      const double d = std::fabs(traj.delta_(j, k));
      if (d == 0.0) continue;
      v = std::fmin(v, v_max[j] / d);
      a = std::fmin(a, a_max[j] / d);
    }
    if (v == kInf) v = a = 1.0;  // no motion: a zero-length segment
    const double T = traj.delta_.col(k).cwiseAbs().maxCoeff() > 0.0 ? min_time(1.0, v, a) : 0.0;
    // Triangular profiles never reach v: keep the peak rate that the time implies.
    traj.vel_[k] = std::fmin(v, std::sqrt(a));
    traj.acc_[k] = a;
    traj.times_[k + 1] = traj.times_[k] + T;
  }
  *out = std::move(traj);
  return Status::kOk;
}

Status TrapezoidTrajectory::sample(double t, Eigen::Ref<Eigen::VectorXd> q,
                                   Eigen::Ref<Eigen::VectorXd> qd,
                                   Eigen::Ref<Eigen::VectorXd> qdd) const noexcept {
  const Eigen::Index n = start_.rows();
  if (times_.size() < 2) return Status::kNotConfigured;
  if (q.size() != n || qd.size() != n || qdd.size() != n) return Status::kBadSize;
  Status status = Status::kOk;
  if (!std::isfinite(t)) {
    t = times_[0];
    status = Status::kNonFiniteReference;
  }
  const Eigen::Index k = segment_at(times_, t);
  const double T = times_[k + 1] - times_[k];
  const double tau = std::fmin(std::fmax(t - times_[k], 0.0), T);
  // Path parameter s(tau) in [0, 1], its rate and acceleration.
  double s = 1.0, sd = 0.0, sdd = 0.0;
  if (T > 0.0 && tau < T) {
    const double v = vel_[k], a = acc_[k], ta = v / a;
    if (tau < ta) {
      s = 0.5 * a * tau * tau, sd = a * tau, sdd = a;
    } else if (tau <= T - ta) {
      s = 0.5 * a * ta * ta + v * (tau - ta), sd = v;
    } else {
      const double r = T - tau;  // time left
      s = 1.0 - 0.5 * a * r * r, sd = a * r, sdd = -a;
    }
  } else if (T > 0.0 && t < times_[k]) {
    s = 0.0;  // before the start: hold the first waypoint
  }
  for (Eigen::Index j = 0; j < n; ++j) {
    const double d = delta_(j, k);
    // s = 1 lands exactly on the next waypoint (no rounding residue in start + delta).
    q[j] = s == 1.0 ? start_(j, k) + d : start_(j, k) + s * d;
    qd[j] = sd * d;
    qdd[j] = sdd * d;
  }
  return status;
}

}  // namespace kiloloop
