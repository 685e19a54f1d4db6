#pragma once
// What the joint torques sent do to the trunk when they land: the floating base's forward dynamics
// in the standing pose, the stance feet pinned to the ground (their forces the constraint's), the
// swing legs free. A Smith predictor that turns the trunk by the contact moment over a rigid
// inertia misses what the legs do within the delay: measured on Go1 at 30 ms, the trunk's roll-rate
// change over the delay correlated at 0.17 with that moment and at -0.90 with the abduction
// torques in flight (bench/go1_35ms_diagnosis.md); with the legs' masses (59 % of Go1's) the
// trunk meets the motors' reaction before the feet's forces settle.
//
// Coordinates: trunk twist nu = [v; w] at the standing CoM (trunk frame), leg joints q_i. Mass
// matrix [C, A_i; A_i^T, H_i] (C composite, A_i the leg's momentum per joint velocity, H_i its
// joint-space inertia: FreeLegInertia). With u_i = tau_i - tau_gravity_i, the foot Jacobian J_i
// (trunk frame) and G_i = [I, -[r_i]x] (r_i the foot from the CoM), a pinned foot's force is
//   f_i = Phi_i^-1 (-J_i H_i^-1 u_i + B_i nu_dot),  Phi_i = J_i H_i^-1 J_i^T,  B_i = J_i H_i^-1 A_i^T - G_i,
// and the trunk's acceleration solves (velocity products neglected)
//   (C - sum_all A H^-1 A^T + sum_pinned B^T Phi^-1 B) nu_dot
//       = [m g; 0] - sum_all A H^-1 u + sum_pinned B^T Phi^-1 J H^-1 u.
// At rest (u_i = -J_i^T f_i for forces that balance the weight) nu_dot = 0. The controller uses
// the angular part (the trunk's linear motion stays predicted from the forces over the mass):
// with the linear part too our model's 35 ms trot fell (roll/pitch RMS 70 deg; 1.45 without).
// A pinned foot whose constraint force would pull on the ground was also tried as lifting
// (solved again free): no figure of the 35 ms checks changed, so it is left out.
#include <array>

#include <Eigen/Core>

#include "kiloloop/quadruped/free_leg_inertia.hpp"

namespace kiloloop {

struct LegTorques {
  // Zeros: `{}` on a std::array of Eigen objects runs Eigen's default constructors, which leave
  // the storage uninitialized (measured: a test that set one leg's torque read 1e264 from the
  // others at -O1).
  LegTorques() noexcept {
    for (int i = 0; i < 4; ++i) {
      jacobian[i].setZero();
      foot[i].setZero();
      torque[i].setZero();
    }
  }
  std::array<Eigen::Matrix3d, 4> jacobian;     // foot velocity per joint velocity, trunk frame
  std::array<Eigen::Vector3d, 4> foot;         // [m] foot from the CoM, trunk frame
  std::array<bool, 4> pinned{};                // stance: the foot held by the ground
  std::array<Eigen::Vector3d, 4> torque;       // [N m] tau - tau_gravity per leg
};

// [m/s^2; rad/s^2] trunk frame into *accel; gravity [m/s^2] in the trunk frame. false (accel
// untouched) where a pinned leg is singular or the result is not finite. Allocation-free.
bool trunk_acceleration(const FreeLegInertia& inertia, const LegTorques& legs,
                        const Eigen::Vector3d& gravity, Eigen::Matrix<double, 6, 1>* accel) noexcept;

}  // namespace kiloloop
