#pragma once
// Gravity torques of one leg (trunk -> foot chain) for gravity given in the trunk frame, which
// turns with the trunk. Gravity torque is linear in the gravity vector, tau_g = G(q) g, so three
// KDL ChainDynParam solvers with unit gravity along the trunk axes give G's columns. With
//   tau = tau_g(q) - J^T f
// a leg in contact makes the ground push on its foot with exactly f (its own weight carried).
#include <array>
#include <memory>
#include <string>

#include <Eigen/Core>
#include <kdl/chain.hpp>
#include <kdl/chaindynparam.hpp>
#include <kdl/jntarray.hpp>

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
  // q: the leg's 3 joints; gravity_trunk: [m/s^2] in the trunk frame. Allocation-free.
  Eigen::Vector3d torque(const Eigen::Vector3d& q, const Eigen::Vector3d& gravity_trunk) noexcept;

 private:
  std::unique_ptr<KDL::Chain> chain_;  // heap-held: the solvers keep a reference to it
  std::array<std::unique_ptr<KDL::ChainDynParam>, 3> unit_;
  KDL::JntArray q_, tau_;
};

}  // namespace kiloloop
