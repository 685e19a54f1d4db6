#pragma once
// Rotor allocation of a multirotor with n >= 4 rotors at any positions and thrust axes:
// body wrench [T; tau_x; tau_y; tau_z] -> n rotor thrusts.
//
// Rotor i at r_i (body frame, about the point the torques are taken about: the controller passes
// positions relative to the body's centre of mass) pushes f_i along its unit axis a_i and, spinning
// counter-clockwise about a_i (spin_i = +1), twists the body along -a_i with c_i f_i (its drag
// torque, c_i [m] = torque_coefficient). Column i of the effectiveness matrix B (6 x n) is
// [a_i; r_i x a_i - spin_i c_i a_i]. The allocation is the exact pseudo-inverse P of the rows that
// are used, computed once at configure:
//   - always the collective force along body z and the three torques (4 rows);
//   - the lateral force rows too when the axes give them authority (tilted rotors, n >= 6, full
//     rank): they are commanded to zero, so a tilted vehicle flies like a flat one (the position
//     loop tilts the body) and its rotors' lateral components cancel instead of pushing it around.
// Unsaturated, B f reproduces the wrench exactly (minimum-norm thrusts when n exceeds the rows).
// When a thrust leaves [thrust_min, thrust_max_i] the priorities are those of flight stacks
// (PX4's mixer): roll/pitch torque first (scaled down only if their spread alone does not fit),
// then collective thrust (shifted only as far as roll/pitch need), and yaw torque last (reduced
// to the largest share that fits); the status is kSaturated and `achieved` says what was
// actually allocated. A layout that cannot produce some wrench direction (coplanar rotors with no
// drag torque: no yaw authority; rotors on a line: no roll) is refused at configure, naming it.
// Optional motor-lag compensation: a first-order lead u = f + tau_m df/dt inverting the motor
// filter (MuJoCo's dyntype "filter", d/dt f = (u - f) / tau_m).
#include <string>

#include <Eigen/Core>

#include "kiloloop/status.hpp"

namespace kiloloop {

struct RotorAllocationConfig {
  // [m] rotor centres, body frame, one column per rotor (n >= 4). Default: an X quadrotor,
  // 0.25 m from the centre on the diagonals (FL, FR, RL, RR).
  Eigen::Matrix3Xd positions =
      (Eigen::Matrix<double, 3, 4>() << 0.176777, 0.176777, -0.176777, -0.176777,  //
       0.176777, -0.176777, 0.176777, -0.176777,                                     //
       0.0, 0.0, 0.0, 0.0).finished();
  // (3, n) thrust directions, body frame (normalized at configure); empty: +z for every rotor.
  Eigen::Matrix3Xd axes;
  // (n) +1: the rotor turns counter-clockwise about its axis, its drag torque acts along -axis.
  Eigen::VectorXd spin = (Eigen::VectorXd(4) << -1.0, 1.0, 1.0, -1.0).finished();
  Eigen::VectorXd torque_coefficient = Eigen::VectorXd::Constant(1, 0.016);  // (1 or n) [m]
  double thrust_min = 0.0;                                                    // [N] per rotor
  Eigen::VectorXd thrust_max = Eigen::VectorXd::Constant(1, 8.0);             // (1 or n) [N]
  bool lag_compensation = false;  // add tau_m * d/dt of the thrust command
  double time_constant = 0.03;    // [s] motor lag tau_m (used when compensating)
  double dt = 0.001;              // [s] control period
};

// n = positions.cols(); every per-rotor vector has n (or 1, broadcast) entries.
Status validate(const RotorAllocationConfig& config, std::string* why);

// wrench = [T [N]; tau_x; tau_y; tau_z [N m]], body frame; thrust (n) [N] per rotor.
class RotorAllocation {
 public:
  static Status configure(const RotorAllocationConfig& config, RotorAllocation* out,
                          std::string* why);

  // Writes thrusts within the limits and the wrench they produce; never NaN (a non-finite wrench
  // gives kNonFiniteReference and all rotors at thrust_min; a thrust vector of the wrong size
  // kBadSize, nothing written). Lag compensation, when on, is applied to `thrust` (the motor
  // command) while `achieved` is the steady-state wrench of the thrusts.
  Status allocate(const Eigen::Vector4d& wrench, Eigen::Ref<Eigen::VectorXd> thrust,
                  Eigen::Vector4d* achieved = nullptr) noexcept;
  void reset() noexcept { have_prev_ = false; }

  int n() const { return n_; }
  const Eigen::MatrixXd& mixer() const { return A_; }          // (4, n) [T; tau] = A thrust
  const Eigen::MatrixXd& effectiveness() const { return B_; }  // (6, n) [F; tau] = B thrust
  const Eigen::MatrixXd& allocation() const { return P_; }     // (n, rows) pseudo-inverse
  // (n) [N/N] each rotor's share of one newton of collective thrust with zero torque.
  const Eigen::VectorXd& collective_share() const { return u_; }
  bool uses_lateral_rows() const { return lateral_; }
  // [N] the largest collective thrust with zero torque that keeps every rotor in range.
  double max_collective() const { return max_collective_; }
  const Eigen::VectorXd& thrust_max() const { return hi_; }   // (n) [N]
  const RotorAllocationConfig& config() const { return cfg_; }

 private:
  RotorAllocationConfig cfg_;
  int n_ = 0;
  bool lateral_ = false;
  int row_T_ = 0;  // column of P for the collective (0, or 2 with the lateral rows)
  double max_collective_ = 0.0;
  Eigen::MatrixXd B_, A_, P_;
  Eigen::VectorXd u_, hi_;
  // Scratch and state, sized n at configure.
  Eigen::VectorXd f_, f_rp_, f_yaw_, prev_;
  bool have_prev_ = false;
  bool configured_ = false;
};

}  // namespace kiloloop
