#pragma once
// Rotor allocation of a quadrotor: body wrench [T; tau_x; tau_y; tau_z] -> four rotor thrusts.
//
// Rotor i at r_i in the body frame pushes f_i along body +z and twists the body about z with
// spin_i * drag * f_i, so the wrench is A f with rows [1], [y_i], [-x_i], [spin_i drag]; A is
// inverted once at configure. Unsaturated, A f reproduces the wrench exactly. When a thrust leaves
// [thrust_min, thrust_max] the priorities are those of flight stacks (PX4's mixer): roll/pitch
// torque first (scaled down only if their spread alone does not fit), then collective thrust
// (shifted only as far as roll/pitch need), and yaw torque last (reduced to the largest share
// that fits); the status is kSaturated and `achieved` says what was actually allocated.
// Optional motor-lag compensation: a first-order lead u = f + tau_m df/dt inverting the motor
// filter (MuJoCo's dyntype "filter", d/dt f = (u - f) / tau_m).
#include <string>

#include <Eigen/Core>

#include "kiloloop/status.hpp"

namespace kiloloop {

struct RotorAllocationConfig {
  Eigen::Matrix<double, 3, 4> positions =
      (Eigen::Matrix<double, 3, 4>() << 0.176777, 0.176777, -0.176777, -0.176777,  //
       0.176777, -0.176777, 0.176777, -0.176777,                                     //
       0.0, 0.0, 0.0, 0.0).finished();        // [m] rotor centres in the body frame, columns
  Eigen::Vector4d spin{1.0, -1.0, -1.0, 1.0};  // +1: the rotor's drag pushes body yaw up
  double drag_coefficient = 0.016;             // [m] yaw torque / thrust
  double thrust_min = 0.0;                     // [N] per rotor
  double thrust_max = 8.0;                     // [N] per rotor
  bool lag_compensation = false;               // add tau_m * d/dt of the thrust command
  double time_constant = 0.03;                 // [s] motor lag tau_m (used when compensating)
  double dt = 0.001;                           // [s] control period
};

Status validate(const RotorAllocationConfig& config, std::string* why);

// wrench = [T [N]; tau_x; tau_y; tau_z [N m]], body frame; thrust (4) [N] per rotor.
class RotorAllocation {
 public:
  static Status configure(const RotorAllocationConfig& config, RotorAllocation* out,
                          std::string* why);

  // Writes thrusts within the limits and the wrench they produce; never NaN (a non-finite wrench
  // gives kNonFiniteReference and all rotors at thrust_min). Lag compensation, when on, is applied
  // to `thrust` (the motor command) while `achieved` is the steady-state wrench of the thrusts.
  Status allocate(const Eigen::Vector4d& wrench, Eigen::Vector4d* thrust,
                  Eigen::Vector4d* achieved = nullptr) noexcept;
  void reset() noexcept { have_prev_ = false; }

  const Eigen::Matrix4d& mixer() const { return A_; }        // wrench = A thrust
  const Eigen::Matrix4d& allocation() const { return A_inv_; }  // thrust = A^-1 wrench
  const RotorAllocationConfig& config() const { return cfg_; }

 private:
  RotorAllocationConfig cfg_;
  Eigen::Matrix4d A_ = Eigen::Matrix4d::Identity();
  Eigen::Matrix4d A_inv_ = Eigen::Matrix4d::Identity();
  Eigen::Vector4d prev_ = Eigen::Vector4d::Zero();  // last thrust before lag compensation
  bool have_prev_ = false;
  bool configured_ = false;
};

}  // namespace kiloloop
