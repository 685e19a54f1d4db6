#pragma once
// Trapezoidal-velocity joint trajectory through waypoints with per-joint velocity and acceleration
// limits (MATLAB/Corke's `lspb`/`trapveltraj`, multi-joint and synchronized).
// Every segment is rest-to-rest and phase-synchronized: q(t) = q_k + s(t) (q_k+1 - q_k) with one
// trapezoidal s(t) in [0, 1] (triangular when the cruise speed is not reached) whose speed and
// acceleration limits are the tightest over the moving joints,
//   s_dot_max = min_j v_max_j / |dq_j|,  s_ddot_max = min_j a_max_j / |dq_j|.
// So all joints start and arrive together AND the motion stays on the straight joint-space segment
// (what a planner checked for collisions is what is executed). |qd_j| <= v_max_j and
// |qdd_j| <= a_max_j on every joint.
// Sampling is noexcept and allocation-free.
#include <string>

#include <Eigen/Core>

#include "kiloloop/status.hpp"

namespace kiloloop {

class TrapezoidTrajectory {
 public:
  TrapezoidTrajectory() = default;
  // waypoints: (nq, m) columns are configurations, m >= 2; v_max, a_max: (nq) [rad/s], [rad/s^2],
  // finite and > 0; t0 [s] start time. Consecutive equal waypoints give a zero-length segment.
  static Status configure(const Eigen::MatrixXd& waypoints, const Eigen::VectorXd& v_max,
                          const Eigen::VectorXd& a_max, double t0, TrapezoidTrajectory* out,
                          std::string* why);

  int nq() const { return static_cast<int>(start_.rows()); }
  int segments() const { return static_cast<int>(times_.size()) - 1; }
  double start_time() const { return times_.size() ? times_[0] : 0.0; }
  double end_time() const { return times_.size() ? times_[times_.size() - 1] : 0.0; }
  const Eigen::VectorXd& times() const { return times_; }  // (m) [s] arrival at each waypoint

  // Position [rad], velocity [rad/s], acceleration [rad/s^2] at time t [s]; holds the end points
  // at rest outside [start, end]. A non-finite t gives kNonFiniteReference and the start point.
  Status sample(double t, Eigen::Ref<Eigen::VectorXd> q, Eigen::Ref<Eigen::VectorXd> qd,
                Eigen::Ref<Eigen::VectorXd> qdd) const noexcept;

 private:
  Eigen::VectorXd times_;  // (m)
  Eigen::MatrixXd start_;  // (nq, m-1) start position of each segment [rad]
  Eigen::MatrixXd delta_;  // (nq, m-1) displacement of each segment [rad]
  Eigen::VectorXd vel_;    // (m-1) cruise rate of the path parameter s [1/s]
  Eigen::VectorXd acc_;    // (m-1) acceleration of s [1/s^2]
};

}  // namespace kiloloop
