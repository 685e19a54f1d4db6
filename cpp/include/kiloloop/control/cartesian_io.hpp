#pragma once
// Input and output of the Cartesian (end-effector) torque controllers: impedance and hybrid
// force/position. Poses, twists and wrenches are of the chain tip, in the chain root frame;
// 6-vectors are [linear; angular]. Wrenches are those the tip APPLIES ON the environment, so
// that the static joint torque producing a wrench F is tau = J^T F.
#include <Eigen/Core>

#include "kiloloop/status.hpp"

namespace kiloloop {

using Vector6d = Eigen::Matrix<double, 6, 1>;

struct CartesianControlInput {
  double t = 0.0;          // [s] controller time of this tick
  double stamp = 0.0;      // [s] when q, qd and the wrench were sampled
  Eigen::VectorXd q;       // (nq) [rad] measured position
  Eigen::VectorXd qd;      // (nq) [rad/s] measured velocity
  Eigen::Vector3d p_ref = Eigen::Vector3d::Zero();            // [m] tip position reference
  Eigen::Matrix3d R_ref = Eigen::Matrix3d::Identity();        // tip orientation reference
  Vector6d twist_ref = Vector6d::Zero();                      // [m/s; rad/s]
  Vector6d accel_ref = Vector6d::Zero();                      // [m/s^2; rad/s^2] feed-forward
  Vector6d wrench_ref = Vector6d::Zero();                     // [N; N m] desired applied wrench
  Vector6d wrench_measured = Vector6d::Zero();                // [N; N m] measured applied wrench
};

struct CartesianControlOutput {
  Eigen::VectorXd tau;                       // (nq) [N m] finite, within the effort limits
  Vector6d pose_error = Vector6d::Zero();    // [m; rad] reference - measured (rotation vector)
  Vector6d wrench_command = Vector6d::Zero();  // [N; N m] the task-space wrench commanded
  Status status = Status::kNotConfigured;
};

// Former name of the step counters: every controller counts its statuses in StatusCounters.
using CartesianCounters = StatusCounters;

// Zero-filled input (identity orientation) and output sized for nq joints (allocates).
CartesianControlInput make_cartesian_input(int nq);
CartesianControlOutput make_cartesian_output(int nq);

}  // namespace kiloloop
