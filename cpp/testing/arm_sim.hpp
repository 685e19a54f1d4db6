#pragma once
// A rigid-body simulation of a serial arm for closed-loop C++ tests: the model's exact dynamics
// (KDL), semi-implicit Euler, optional external wrench on the tip. Test-only; allocates freely.
#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "kiloloop/dynamics/dynamics.hpp"

namespace kiloloop::testing {

// [rad] The UR5 pose the supervisor tests start from: clear of the joint limits and of singularities.
inline Eigen::VectorXd ur5_home() {
  return (Eigen::VectorXd(6) << 0.0, -1.2, 1.6, -1.97, -1.57, 0.0).finished();
}

class ArmSim {
 public:
  ArmSim(RobotModelPtr model, const Eigen::VectorXd& q0) : q(q0), qd(Eigen::VectorXd::Zero(q0.size())) {
    std::string why;
    Dynamics::configure(model, {0, 0, -9.81}, &dyn_, &why);
    const int n = static_cast<int>(q0.size());
    M_.resize(n, n);
    J_.resize(6, n);
    bias_.resize(n);
    zero_ = Eigen::VectorXd::Zero(n);
  }
  // Advances by dt with joint torque tau and an external wrench on the tip (root frame, the
  // wrench the ENVIRONMENT applies on the tip), in `substeps` Euler steps.
  void step(const Eigen::VectorXd& tau, double dt, int substeps = 10,
            const Eigen::Matrix<double, 6, 1>& wrench_on_tip = Eigen::Matrix<double, 6, 1>::Zero()) {
    const double h = dt / substeps;
    for (int k = 0; k < substeps; ++k) {
      dyn_.mass_matrix(q, M_);
      dyn_.inverse_dynamics(q, qd, zero_, bias_);
      dyn_.jacobian(q, J_);
      qd += h * M_.ldlt().solve(tau + J_.transpose() * wrench_on_tip - bias_);
      q += h * qd;
    }
  }
  Eigen::Matrix4d pose() {
    Eigen::Matrix4d T;
    dyn_.forward_kinematics(q, T);
    return T;
  }
  Eigen::VectorXd q, qd;

 private:
  Dynamics dyn_;
  Eigen::MatrixXd M_, J_;
  Eigen::VectorXd bias_, zero_;
};

}  // namespace kiloloop::testing
