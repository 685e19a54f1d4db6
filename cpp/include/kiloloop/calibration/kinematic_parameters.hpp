#pragma once
// KinematicParameters: the geometry a kinematic calibration identifies, in a parameterization
// that stays well-conditioned where standard DH is not (parallel consecutive joint axes, e.g.
// UR joints 2-3-4, where a tiny tilt of one axis moves the DH common normal arbitrarily far).
// Per revolute joint i (modified DH, Craig, plus Hayati's beta about y):
//   T_i(q_i) = Rx(alpha_i) Tx(a_i) Ry(beta_i) Rz(theta_i + q_i) Tz(d_i)
// beta_i is identified only where joint i's nominal axis is parallel to joint i-1's
// (`has_beta`); elsewhere it stays 0 (it would duplicate d_{i-1}'s effect).
// Whole chain: T_base * prod T_i(q_i), base = Trans(base_position) Exp(base_rotation);
// the measured point sits at `tool` in the last joint frame.
// Offline (calibration) code: these functions allocate and are not for the 1 kHz path.
#include <string>
#include <vector>

#include <Eigen/Core>

#include "kiloloop/model/dh.hpp"
#include "kiloloop/model/robot_model.hpp"
#include "kiloloop/status.hpp"

namespace kiloloop {

struct KinematicParameters {
  Eigen::Vector3d base_position = Eigen::Vector3d::Zero();  // [m]
  Eigen::Vector3d base_rotation = Eigen::Vector3d::Zero();  // [rad] rotation vector
  Eigen::VectorXd alpha, a, beta, theta, d;                 // (n) [rad], [m], [rad], [rad], [m]
  std::vector<bool> has_beta;                               // (n) beta is a free parameter
  Eigen::Vector3d tool = Eigen::Vector3d::Zero();           // [m] measured point, last frame

  int nq() const { return static_cast<int>(alpha.size()); }
  // Number of entries of pack(): 6 + 5 n + 3 (fixed betas included, as zeros).
  int size() const { return 6 + 5 * nq() + 3; }
  Eigen::VectorXd pack() const;
  // Fails (false) on a wrong size; has_beta is kept.
  bool unpack(const Eigen::VectorXd& x);
  // Position of the measured point in the root (measurement) frame at q (n) [m].
  Eigen::Vector3d position(const Eigen::VectorXd& q) const;

  // Converts a revolute DH table (either convention) into this form, with the tool point at the
  // last DH frame's origin plus `tool_point` in that frame. Prismatic joints: kModelError.
  static Status from_dh(const std::vector<DhLink>& links, DhConvention convention,
                        const Eigen::Vector3d& tool_point, KinematicParameters* out,
                        std::string* why);
  // Nominal parameters of a UR-shaped model: the DH table read off its chain (UrAnalyticIk::
  // from_model, which checks the hypothesis) and its fixed frames before joint 1 as the base, so
  // position(q) = T_root_tool0(q) * tool_point. A non-UR chain: kModelError with the reason.
  static Status from_ur_model(const RobotModel& model, const Eigen::Vector3d& tool_point,
                              KinematicParameters* out, std::string* why);
};

}  // namespace kiloloop
