#pragma once
// Closed-form inverse kinematics of the Universal Robots family (UR3/5/10/e): standard DH with
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

  UrAnalyticIk() = default;
  // base: T_root_frame0 (fixed frames before joint 1); lower/upper: (6) joint limits [rad].
  static Status configure(const UrDhParameters& dh, const Eigen::Isometry3d& base,
                          const Eigen::Matrix<double, 6, 1>& lower,
                          const Eigen::Matrix<double, 6, 1>& upper, UrAnalyticIk* out,
                          std::string* why);
  // Reads the DH parameters off a model whose chain is written as UR standard DH (models/ur5:
  // link i frame = DH frame i-1 rotated by q_i), then checks FK against the model's own chain at
  // seeded random configurations; kModelError with the reason when it deviates by more than
  // `tolerance` [m and rad]. A loose tolerance accepts a nearly-UR chain (e.g. a calibrated arm)
  // whose closed-form solutions are then only seeds, to be refined numerically (ArmIk).
  static Status from_model(const RobotModel& model, UrAnalyticIk* out, std::string* why,
                           double tolerance = 1e-9);

  const UrDhParameters& parameters() const { return dh_; }
  // T_root_frame0: the fixed frames before joint 1 (configure's `base`).
  const Eigen::Isometry3d& base() const { return base_; }
  // Largest FK deviation of the model's chain from this closed form seen by from_model [m, rad].
  double deviation() const { return deviation_; }
  // T_root_tool0 at q (6), the closed-form standard-DH product.
  Eigen::Isometry3d forward(const Eigen::Matrix<double, 6, 1>& q) const noexcept;

  // All solutions for T_root_tool0 = target (columns 0..count-1 of `out`, nearest to `seed`
  // first). kOk with count >= 1; kUnreachable with count 0 when the target is out of reach or
  // every solution violates the limits; kNonFiniteReference for a non-finite target or seed.
  // At the wrist singularity (sin t5 = 0) t6 is free and is taken from the seed.
  Status solve(const Eigen::Isometry3d& target, const Eigen::Matrix<double, 6, 1>& seed,
               Solutions& out, int* count) const noexcept;

 private:
  UrDhParameters dh_;
  Eigen::Isometry3d base_ = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d base_inv_ = Eigen::Isometry3d::Identity();
  Eigen::Matrix<double, 6, 1> lower_, upper_;
  double deviation_ = 0.0;
};

}  // namespace kiloloop
