#pragma once
// A random but valid joint-controller input (q, qd in [-1, 1], a reference 0.01 rad away, small
// qd_ref and qdd_ref) for the joint controllers' tests.
#include <random>

#include "kiloloop/control/joint_io.hpp"

namespace kiloloop::testing {

inline JointControlInput random_joint_input(std::mt19937& rng, int n) {
  std::uniform_real_distribution<double> u(-1, 1);
  JointControlInput in = make_joint_input(n);
  for (int i = 0; i < n; ++i) {
    in.q[i] = u(rng);
    in.qd[i] = u(rng);
    in.q_ref[i] = in.q[i] + 0.01 * u(rng);
    in.qd_ref[i] = 0.1 * u(rng);
    in.qdd_ref[i] = 0.1 * u(rng);
  }
  return in;
}

}  // namespace kiloloop::testing
