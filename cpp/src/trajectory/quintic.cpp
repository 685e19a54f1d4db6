#include "kiloloop/trajectory/quintic.hpp"

#include <cmath>

#include "kiloloop/trajectory/segment_lookup.hpp"

namespace kiloloop {
namespace {

// Coefficients of p(s) = sum c_i s^i on s in [0, T] matching (p, v, a) at both ends.
void quintic_coefficients(double p0, double v0, double a0, double p1, double v1, double a1,
                          double T, double* c) {
  const double T2 = T * T, T3 = T2 * T, T4 = T3 * T, T5 = T4 * T;
  const double h = p1 - p0;
  c[0] = p0;
  c[1] = v0;
  c[2] = 0.5 * a0;
  c[3] = (20.0 * h - (8.0 * v1 + 12.0 * v0) * T - (3.0 * a0 - a1) * T2) / (2.0 * T3);
  c[4] = (-30.0 * h + (14.0 * v1 + 16.0 * v0) * T + (3.0 * a0 - 2.0 * a1) * T2) / (2.0 * T4);
  c[5] = (12.0 * h - 6.0 * (v1 + v0) * T - (a0 - a1) * T2) / (2.0 * T5);
}

}  // namespace

Status QuinticTrajectory::configure(const Eigen::MatrixXd& waypoints, const Eigen::VectorXd& times,
                                    QuinticTrajectory* out, std::string* why) {
  auto fail = [&](const char* msg) {
    if (why) *why = msg;
    return Status::kInvalidConfig;
  };
  const Eigen::Index n = waypoints.rows(), m = waypoints.cols();
  if (n < 1 || m < 2) return fail("need at least one joint and two waypoints");
  if (times.size() != m) return fail("times must have one entry per waypoint");
  if (!waypoints.allFinite() || !times.allFinite()) return fail("waypoints and times must be finite");
  for (Eigen::Index k = 1; k < m; ++k)
    if (!(times[k] > times[k - 1])) return fail("times must be strictly increasing");

  // Via velocities (Craig, "Introduction to Robotics", sec. 7.3).
  Eigen::MatrixXd vel = Eigen::MatrixXd::Zero(n, m);
  for (Eigen::Index k = 1; k + 1 < m; ++k) {
    for (Eigen::Index j = 0; j < n; ++j) {
      const double s0 = (waypoints(j, k) - waypoints(j, k - 1)) / (times[k] - times[k - 1]);
      const double s1 = (waypoints(j, k + 1) - waypoints(j, k)) / (times[k + 1] - times[k]);
      vel(j, k) = (s0 * s1 > 0.0) ? 0.5 * (s0 + s1) : 0.0;
    }
  }
  QuinticTrajectory traj;
  traj.times_ = times;
  traj.coeffs_.resize(n, 6 * (m - 1));
  for (Eigen::Index k = 0; k + 1 < m; ++k) {
    for (Eigen::Index j = 0; j < n; ++j) {
      double c[6];
      quintic_coefficients(waypoints(j, k), vel(j, k), 0.0, waypoints(j, k + 1), vel(j, k + 1), 0.0,
                           times[k + 1] - times[k], c);
      for (int i = 0; i < 6; ++i) traj.coeffs_(j, 6 * k + i) = c[i];
    }
  }
  *out = std::move(traj);
  return Status::kOk;
}

Status QuinticTrajectory::sample(double t, Eigen::Ref<Eigen::VectorXd> q,
                                 Eigen::Ref<Eigen::VectorXd> qd,
                                 Eigen::Ref<Eigen::VectorXd> qdd) const noexcept {
  const Eigen::Index n = coeffs_.rows();
  if (times_.size() < 2) return Status::kNotConfigured;
  if (q.size() != n || qd.size() != n || qdd.size() != n) return Status::kBadSize;
  Status status = Status::kOk;
  if (!std::isfinite(t)) {
    t = times_[0];
    status = Status::kNonFiniteReference;
  }
  // Segment k covers [times_k, times_k+1]; clamping s holds the end points at rest.
  const Eigen::Index k = segment_at(times_, t);
  const double T = times_[k + 1] - times_[k];
  const double s = std::fmin(std::fmax(t - times_[k], 0.0), T);
  for (Eigen::Index j = 0; j < n; ++j) {
    const double* c = &coeffs_(j, 6 * k);
    // Row-wise access of a column-major matrix: read the six coefficients by stride.
    const Eigen::Index stride = coeffs_.rows();
    const double c0 = c[0], c1 = c[stride], c2 = c[2 * stride], c3 = c[3 * stride],
                 c4 = c[4 * stride], c5 = c[5 * stride];
    q[j] = c0 + s * (c1 + s * (c2 + s * (c3 + s * (c4 + s * c5))));
    qd[j] = c1 + s * (2.0 * c2 + s * (3.0 * c3 + s * (4.0 * c4 + s * 5.0 * c5)));
    qdd[j] = 2.0 * c2 + s * (6.0 * c3 + s * (12.0 * c4 + s * 20.0 * c5));
  }
  return status;
}

}  // namespace kiloloop
