#pragma once
// PositionController: position/velocity PID in the world frame -> desired acceleration, and the
// map from a desired thrust vector (+ yaw, handled separately) to a desired attitude.
//   a_des = a_ref + kp (p_ref - p) + kd (v_ref - v) + ki int(p_ref - p)
// The thrust vector F = m (a_des - g) (+ the arm's reaction when fed forward) is the composed
// controller's business; here it only becomes an attitude: body z along F, tilted at most
// max_tilt (the horizontal part is shortened, the vertical kept), body x towards yaw.
#include <string>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "kiloloop/status.hpp"

namespace kiloloop {

struct PositionControlConfig {
  Eigen::Vector3d kp{16.0, 16.0, 25.0};  // [1/s^2] x, y, z (world)
  Eigen::Vector3d kd{8.0, 8.0, 10.0};    // [1/s]
  Eigen::Vector3d ki{4.0, 4.0, 8.0};     // [1/s^3] 0 turns the integral off
  // [m/s^2] largest acceleration the integral may command, per axis (anti-windup clamp).
  Eigen::Vector3d integral_limit{3.0, 3.0, 4.0};
  double max_tilt = 0.6;                 // [rad] tilt of the commanded attitude (~34 deg)
  double dt = 0.001;                     // [s]
};

Status validate(const PositionControlConfig& config, std::string* why);

class PositionController {
 public:
  static Status configure(const PositionControlConfig& config, PositionController* out,
                          std::string* why);

  // Writes a_des (3) [m/s^2], world. `saturated` freezes the integral (anti-windup).
  Status step(const Eigen::Vector3d& p, const Eigen::Vector3d& v, const Eigen::Vector3d& p_ref,
              const Eigen::Vector3d& v_ref, const Eigen::Vector3d& a_ref, bool saturated,
              Eigen::Vector3d* a_des) noexcept;
  void reset() noexcept { integral_.setZero(); }

  // Desired attitude (world <- body) for the thrust vector F (world) and yaw [rad]; F is first
  // limited to max_tilt from vertical (and to a positive vertical part). Returns the limited F.
  Eigen::Vector3d attitude_from_thrust(const Eigen::Vector3d& F, double yaw,
                                       Eigen::Quaterniond* q_des) const noexcept;

  const Eigen::Vector3d& integral() const { return integral_; }  // [m s]

 private:
  PositionControlConfig cfg_;
  double tan_max_tilt_ = 0.0;  // tan(max_tilt), made at configure
  Eigen::Vector3d integral_ = Eigen::Vector3d::Zero();
  bool configured_ = false;
};

}  // namespace kiloloop
