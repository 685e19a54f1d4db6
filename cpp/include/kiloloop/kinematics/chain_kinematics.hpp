#pragma once
// ChainKinematics: forward kinematics and the geometric Jacobian of a serial chain, compiled at
// configure from the model's KDL chain into one (pre, axis, post) triple per joint so that the
// inner loop of an IK solver is a handful of 3x3 products. KDL's ChainFkSolverPos and
// ChainJntToJacSolver give the same numbers (tested) but walk KDL::Frame objects per segment.
//
// Frames: T_root_tip and the Jacobian of the chain tip in the chain root frame; rows
// [linear; angular], reference point at the tip (the same convention as Dynamics).
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "kiloloop/model/robot_model.hpp"
#include "kiloloop/status.hpp"

namespace kiloloop {

using Vector6d = Eigen::Matrix<double, 6, 1>;

// Pose error of T relative to the target: [p_target - p; log(R_target R^T)] in the root frame
// [m; rad]. Its angular part is a rotation vector (angle <= pi), exact for large errors too.
Vector6d pose_error(const Eigen::Isometry3d& target, const Eigen::Isometry3d& T) noexcept;

class ChainKinematics {
 public:
  ChainKinematics() = default;
  // Fails with kModelError when the model has no serial chain or a joint type is unsupported.
  static Status configure(const RobotModel& model, ChainKinematics* out, std::string* why);

  int nq() const { return nq_; }
  // T_root_tip at q (nq). No size or finiteness check: callers check once per solve.
  void forward(const Eigen::Ref<const Eigen::VectorXd>& q, Eigen::Isometry3d& T) noexcept;
  // T_root_tip and J (6, nq) at q in one pass.
  void forward_jacobian(const Eigen::Ref<const Eigen::VectorXd>& q, Eigen::Isometry3d& T,
                        Eigen::Ref<Eigen::MatrixXd> J) noexcept;

 private:
  struct Joint {
    Eigen::Isometry3d pre = Eigen::Isometry3d::Identity();   // configure only: to the axis point
    Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();         // unit axis in the joint frame
    Eigen::Isometry3d post = Eigen::Isometry3d::Identity();  // after the joint motion -> next joint
    bool prismatic = false;
  };
  // T <- T * motion(q) * post.
  static void apply(const Joint& j, double q, Eigen::Isometry3d& T) noexcept;

  int nq_ = 0;
  std::vector<Joint> joints_;
  Eigen::Isometry3d base_ = Eigen::Isometry3d::Identity();  // fixed segments before joint 1
  Eigen::Matrix3Xd axes_, points_;  // (3, nq) joint axes and points in the root frame (scratch)
};

}  // namespace kiloloop
