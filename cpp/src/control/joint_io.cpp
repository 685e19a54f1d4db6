#include "kiloloop/control/joint_io.hpp"

namespace kiloloop {

JointControlInput make_joint_input(int nq) {
  JointControlInput in;
  in.q = in.qd = in.q_ref = in.qd_ref = in.qdd_ref = Eigen::VectorXd::Zero(nq);
  return in;
}

JointControlOutput make_joint_output(int nq) {
  JointControlOutput out;
  out.tau = Eigen::VectorXd::Zero(nq);
  return out;
}

}  // namespace kiloloop
