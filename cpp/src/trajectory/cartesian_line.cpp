#include "kiloloop/trajectory/cartesian_line.hpp"

#include <cmath>

namespace kiloloop {

Status CartesianLine::configure(const Eigen::Isometry3d& start, const Eigen::Isometry3d& end,
                                double t0, double duration, CartesianLine* out, std::string* why) {
  if (!start.matrix().allFinite() || !end.matrix().allFinite() || !std::isfinite(t0)) {
    if (why) *why = "CartesianLine: start, end and t0 must be finite";
    return Status::kInvalidConfig;
  }
  if (!(duration > 0.0) || !std::isfinite(duration)) {
    if (why) *why = "CartesianLine: duration must be finite and > 0";
    return Status::kInvalidConfig;
  }
  for (const Eigen::Isometry3d* T : {&start, &end}) {
    const Eigen::Matrix3d R = T->linear();
    if ((R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-9 ||
        R.determinant() < 0.0) {
      if (why) *why = "CartesianLine: start and end rotations must be orthonormal (det +1)";
      return Status::kInvalidConfig;
    }
  }
  CartesianLine c;
  c.p0_ = start.translation();
  c.p1_ = end.translation();
  c.R0_ = start.linear();
  const Eigen::AngleAxisd aa(Eigen::Matrix3d(c.R0_.transpose() * end.linear()));
  c.w_ = aa.angle() * aa.axis();
  c.t0_ = t0;
  c.duration_ = duration;
  *out = c;
  return Status::kOk;
}

Status CartesianLine::sample(double t, Eigen::Isometry3d& pose, Vector6d& twist,
                             Vector6d& accel) const noexcept {
  Status status = Status::kOk;
  if (!std::isfinite(t)) {
    t = t0_;
    status = Status::kNonFiniteReference;
  }
  double u = (t - t0_) / duration_;
  double s = 0.0, sd = 0.0, sdd = 0.0;
  if (u >= 1.0) {
    s = 1.0;
  } else if (u > 0.0) {
    const double u2 = u * u, u3 = u2 * u;
    s = u3 * (10.0 - 15.0 * u + 6.0 * u2);
    sd = 30.0 * u2 * (1.0 - 2.0 * u + u2) / duration_;
    sdd = 60.0 * u * (1.0 - 3.0 * u + 2.0 * u2) / (duration_ * duration_);
  }
  const Eigen::Vector3d dp = p1_ - p0_;
  pose = Eigen::Isometry3d::Identity();
  pose.translation() = p0_ + s * dp;
  const double angle = w_.norm();
  pose.linear() = angle > 0.0 ? Eigen::Matrix3d(R0_ * Eigen::AngleAxisd(s * angle, w_ / angle)) : R0_;
  const Eigen::Vector3d axis_root = R0_ * w_;
  twist << sd * dp, sd * axis_root;
  accel << sdd * dp, sdd * axis_root;
  return status;
}

}  // namespace kiloloop
