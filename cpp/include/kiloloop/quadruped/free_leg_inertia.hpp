#pragma once
// The trunk's rotational inertia as a moment from the stance feet meets it within the actuation
// delay: a swing leg hangs from its hip through a position loop no faster than the delay allows,
// so its own inertia largely stays behind (its joints free), while a stance leg, pinned at the
// foot with its mass near the hip, moves with the trunk (locked). All legs free is the
// articulated-body inertia of the floating base; checked against MuJoCo's mass matrix (Schur
// complement over the joints): roll 0.034 vs 0.031 kg m^2 on Go1 (composite 0.123: the legs
// are 59 % of its mass), 0.130 vs 0.132 on our model (composite 0.312).
#include <array>
#include <string>

#include <Eigen/Core>
#include <kdl/chain.hpp>

#include "kiloloop/model/robot_model.hpp"

namespace kiloloop {

using Matrix6d = Eigen::Matrix<double, 6, 6>;

// The chain trunk -> foot with each link carrying what hangs off it outside the chain (rigid
// with it; joints off the chain at 0): a leg's rotors belong to the link that holds them (Go1
// hangs each joint's rotor off the previous link). Configure-time.
KDL::Chain leg_chain(const RobotModel& model, const std::string& trunk, const std::string& foot);

// The whole robot standing in the pose q (12, leg-major per `feet`), about its CoM (trunk frame,
// [linear; angular]): the composite 6x6 [m I, 0; 0, I_c] and each leg's joint-space coupling
// A H^-1 A^T (A: the leg's momentum per unit joint velocity, H its joint-space inertia).
struct FreeLegInertia {
  // Zeros (`{}` would leave the Eigen storage of the arrays uninitialized): an unconfigured
  // controller's copy reads as legs without mass.
  FreeLegInertia() noexcept {
    for (int i = 0; i < 4; ++i) {
      coupling[i].setZero();
      momentum[i].setZero();
      joint_inertia_inverse[i].setZero();
    }
  }
  Matrix6d composite = Matrix6d::Identity();
  std::array<Matrix6d, 4> coupling;
  // Per leg, the parts of the coupling (standing pose): A, the momentum about the CoM per unit
  // joint velocity ([linear; angular], trunk frame), and H^-1, the joint-space inertia's inverse.
  // With them the floating base's mass matrix is [composite, A; A^T, H] (trunk_rotation.hpp).
  std::array<Eigen::Matrix<double, 6, 3>, 4> momentum;
  std::array<Eigen::Matrix3d, 4> joint_inertia_inverse;
  // [kg m^2] rotational inertia about the CoM with the legs marked free: composite less their
  // couplings, the linear part eliminated (allocation-free; all free: the articulated-body
  // inertia of the floating base).
  Eigen::Matrix3d rotational(const std::array<bool, 4>& free) const noexcept;
};

// Configure-time (allocates).
FreeLegInertia free_leg_inertia(const RobotModel& model, const std::string& trunk,
                                const std::array<std::string, 4>& feet,
                                const Eigen::Matrix<double, 12, 1>& q, double mass,
                                const Eigen::Vector3d& com, const Eigen::Matrix3d& composite);

}  // namespace kiloloop
