#pragma once
// Quintic joint trajectory through waypoints (MATLAB/Corke's `jtraj`, extended to via points).
// Each segment is a 5th-order polynomial matching position, velocity and acceleration at both
// ends, so position, velocity and acceleration are continuous. Start and end are at rest; via
// velocities follow Craig's heuristic (mean of the neighbouring slopes, zero where the slope
// changes sign, per joint), via accelerations are zero. Sampling is noexcept and allocation-free.
#include <string>

#include <Eigen/Core>

#include "kiloloop/status.hpp"

namespace kiloloop {

class QuinticTrajectory {
 public:
  QuinticTrajectory() = default;
  // waypoints: (nq, m) columns are configurations; times: (m) strictly increasing [s], m >= 2.
  static Status configure(const Eigen::MatrixXd& waypoints, const Eigen::VectorXd& times,
                          QuinticTrajectory* out, std::string* why);

  int nq() const { return static_cast<int>(coeffs_.rows()); }
  double start_time() const { return times_.size() ? times_[0] : 0.0; }
  double end_time() const { return times_.size() ? times_[times_.size() - 1] : 0.0; }

  // Position [rad], velocity [rad/s], acceleration [rad/s^2] at time t [s]. Before the start and
  // after the end it holds the end point at rest. A non-finite t returns kNonFiniteReference and
  // the start point at rest.
  Status sample(double t, Eigen::Ref<Eigen::VectorXd> q, Eigen::Ref<Eigen::VectorXd> qd,
                Eigen::Ref<Eigen::VectorXd> qdd) const noexcept;

 private:
  Eigen::VectorXd times_;   // (m)
  Eigen::MatrixXd coeffs_;  // (nq, 6 (m-1)): c0..c5 of segment k in columns 6k..6k+5
};

}  // namespace kiloloop
