#pragma once
// Closed-form inverse kinematics of the Universal Robots family (UR3/5/10/16/e): standard DH with
// alpha = (pi/2, 0, 0, pi/2, -pi/2, 0), three parallel joints (2, 3, 4) and a shoulder offset.
// Up to 8 solutions: shoulder left/right (theta1) x wrist up/down (theta5) x elbow up/down
// (theta3). Each angle is shifted by multiples of 2 pi to the value nearest the seed inside the
// joint limits; solutions outside the limits are dropped; the rest are sorted nearest-to-seed
// first (Euclidean joint distance). solve() is noexcept and allocation-free.
//
// Derivation (frames = standard DH frames, p05 = wrist centre = T06 * (0, 0, -d6)):
//   joint 1 axis z1 is perpendicular to the arm plane, at distance d4 from the wrist centre:
//     p05.x sin t1 - p05.y cos t1 = d4
//   z1 . (p06 - p01) = d4 + d6 cos t5;   z1 in frame 6 = (s5 c6, -s5 s6, c5)
//   in frame 1, joints 2-4 are a planar 2-link arm (a2, a3) reaching T14's origin (x, y).
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "kiloloop/model/dh.hpp"
#include "kiloloop/model/robot_model.hpp"
#include "kiloloop/status.hpp"

namespace kiloloop {

struct UrDhParameters {
  double d1 = 0.0, a2 = 0.0, a3 = 0.0, d4 = 0.0, d5 = 0.0, d6 = 0.0;  // [m] (a2, a3 < 0 on UR)
  // The standard DH table (geometry only, no mass) of these parameters.
  std::vector<DhLink> table() const;
};

class UrAnalyticIk {
 public:
  static constexpr int kMaxSolutions = 8;
  using Solutions = Eigen::Matrix<double, 6, kMaxSolutions>;
  using Vector6 = Eigen::Matrix<double, 6, 1>;

  UrAnalyticIk() = default;
  // base: T_root_frame0 (fixed frames before joint 1); lower/upper: (6) joint limits [rad].
  // The joint angles are the DH angles and the tip is DH frame 6 (no tool transform).
  static Status configure(const UrDhParameters& dh, const Eigen::Isometry3d& base,
                          const Eigen::Matrix<double, 6, 1>& lower,
                          const Eigen::Matrix<double, 6, 1>& upper, UrAnalyticIk* out,
                          std::string* why);
  // Recognises a UR-style arm (UR3/5/10/16, e-series, any base and tool frames, any joint zero
  // and axis sign) from its geometry rather than from one frame layout: the joint axes at q = 0
  // must be 1 perp. and meeting 2, 2 || 3 || 4, 4 perp. and meeting 5, 5 perp. and meeting 6.
  // From those axis lines it builds the standard DH frames, giving the DH parameters, the joint
  // map theta_i = sign_i q_i + offset_i and the constant base and tool transforms, then checks
  // T_root_tip = base * DH(theta(q)) * tool against the chain's FK at seeded random
  // configurations. kModelError with the reason (which joint pair breaks the pattern, or the FK
  // deviation) when a check fails by more than `tolerance` [m and rad]. A loose tolerance accepts
  // a nearly-UR chain (e.g. a calibrated arm) whose closed-form solutions are then only seeds, to
  // be refined numerically (ArmIk).
  static Status from_model(const RobotModel& model, UrAnalyticIk* out, std::string* why,
                           double tolerance = 1e-9);

  const UrDhParameters& parameters() const { return dh_; }
  // T_root_frame0: the fixed frames before joint 1 (configure's `base`).
  const Eigen::Isometry3d& base() const { return base_; }
  // T_frame6_tip: DH frame 6 (on joint 6's axis) to the chain tip; identity from configure.
  const Eigen::Isometry3d& tool() const { return tool_; }
  // theta_i = joint_sign_i q_i + joint_offset_i: model joint positions to DH angles [rad].
  const Vector6& joint_sign() const { return sign_; }
  const Vector6& joint_offset() const { return offset_; }
  // Largest FK deviation of the model's chain from this closed form seen by from_model [m, rad].
  double deviation() const { return deviation_; }
  // T_root_tip at joint positions q (6): base * DH(theta(q)) * tool.
  Eigen::Isometry3d forward(const Eigen::Matrix<double, 6, 1>& q) const noexcept;

  // All solutions for T_root_tip = target (columns 0..count-1 of `out`, joint positions of the
  // model, nearest to `seed` first). kOk with count >= 1; kUnreachable with count 0 when the
  // target is out of reach or every solution violates the limits; kNonFiniteReference for a
  // non-finite target or seed. At the wrist singularity (sin t5 = 0) t6 is free and is taken
  // from the seed.
  Status solve(const Eigen::Isometry3d& target, const Eigen::Matrix<double, 6, 1>& seed,
               Solutions& out, int* count) const noexcept;

 private:
  UrDhParameters dh_;
  Eigen::Isometry3d base_ = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d base_inv_ = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d tool_ = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d tool_inv_ = Eigen::Isometry3d::Identity();
  Vector6 sign_ = Vector6::Ones(), offset_ = Vector6::Zero();
  // Joint limits in DH angles (theta) [rad].
  Vector6 lower_, upper_;
  double deviation_ = 0.0;
};

}  // namespace kiloloop
