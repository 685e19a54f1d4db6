#pragma once
// Input and output of the joint-space torque controllers (PD + gravity, computed torque).
#include <Eigen/Core>

#include "kiloloop/status.hpp"

namespace kiloloop {

struct JointControlInput {
  double t = 0.0;               // [s] controller time of this tick
  double stamp = 0.0;           // [s] time the measurement was sampled (stale if t - stamp is large)
  Eigen::VectorXd q;            // (nq) [rad] measured position
  Eigen::VectorXd qd;           // (nq) [rad/s] measured velocity
  Eigen::VectorXd q_ref;        // (nq) [rad] reference position
  Eigen::VectorXd qd_ref;       // (nq) [rad/s] reference velocity
  Eigen::VectorXd qdd_ref;      // (nq) [rad/s^2] reference acceleration (feed-forward)
};

struct JointControlOutput {
  Eigen::VectorXd tau;  // (nq) [N m] joint torque command, always finite and within effort limits
  Status status = Status::kNotConfigured;
};

// Former name of the step counters: every controller counts its statuses in StatusCounters.
using StepCounters = StatusCounters;

}  // namespace kiloloop

namespace kiloloop {

// Zero-filled input and output sized for nq joints (allocates: call at configure time).
JointControlInput make_joint_input(int nq);
JointControlOutput make_joint_output(int nq);

}  // namespace kiloloop
