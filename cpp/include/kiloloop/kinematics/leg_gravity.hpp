#pragma once
// Gravity torques of one leg (trunk -> foot chain) for gravity given in the trunk frame, which
// turns with the trunk: one gravity-only Newton-Euler pass (ChainRne) with that gravity vector
// (before: three KDL ChainDynParam passes with unit gravity along the trunk axes, G's columns,
// summed; the same torque to round-off at a third of the passes). With
//   tau = tau_g(q) - J^T f
// a leg in contact makes the ground push on its foot with exactly f (its own weight carried).
#include <string>

#include <Eigen/Core>

#include "kiloloop/dynamics/chain_rne.hpp"
#include "kiloloop/model/robot_model.hpp"
#include "kiloloop/status.hpp"

namespace kiloloop {

class LegGravity {
 public:
  LegGravity() = default;
  LegGravity(LegGravity&&) = default;
  LegGravity& operator=(LegGravity&&) = default;
  static Status configure(const RobotModel& model, const std::string& trunk, const std::string& foot,
                          LegGravity* out, std::string* why);
  // q: the leg's 3 joints; gravity_trunk: [m/s^2] in the trunk frame. Allocation-free. cos_q,
  // sin_q (optional, both or neither): their cosines and sines, where the caller has them
  // (LegKinematics::foot_and_jacobian's).
  Eigen::Vector3d torque(const Eigen::Vector3d& q, const Eigen::Vector3d& gravity_trunk,
                         const Eigen::Vector3d* cos_q = nullptr,
                         const Eigen::Vector3d* sin_q = nullptr) noexcept;

 private:
  ChainRne rne_;  // owns copies of the chain's constants: no reference to the model's tree
};

}  // namespace kiloloop
