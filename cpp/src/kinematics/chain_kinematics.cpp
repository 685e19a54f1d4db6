#include "kiloloop/kinematics/chain_kinematics.hpp"
#include "kiloloop/model/kdl_eigen.hpp"

#include <cmath>

#include <kdl/chain.hpp>

namespace kiloloop {
namespace {

}  // namespace

Vector6d pose_error(const Eigen::Isometry3d& target, const Eigen::Isometry3d& T) noexcept {
  Vector6d e;
  e.head<3>() = target.translation() - T.translation();
  // Rotation vector of R_target R^T; AngleAxis handles angles near 0 and pi.
  const Eigen::AngleAxisd aa(Eigen::Matrix3d(target.linear() * T.linear().transpose()));
  e.tail<3>() = aa.angle() * aa.axis();
  return e;
}

Status ChainKinematics::configure(const RobotModel& model, ChainKinematics* out, std::string* why) {
  if (!model.has_chain()) {
    if (why) *why = "ChainKinematics needs a serial chain: load the model with a tip link";
    return Status::kModelError;
  }
  ChainKinematics k;
  const KDL::Chain& chain = model.chain();
  // KDL: segment pose(q) = joint.pose(q) * f_tip, joint.pose(q) a rotation about (or a
  // translation along) `axis` through `origin`, both in the segment's base frame. Fixed
  // segments fold into the previous joint's `post` (or into `base_` before the first joint).
  Eigen::Isometry3d pending = Eigen::Isometry3d::Identity();  // fixed frames since last joint
  for (unsigned s = 0; s < chain.getNrOfSegments(); ++s) {
    const KDL::Segment& seg = chain.getSegment(s);
    const KDL::Joint& jnt = seg.getJoint();
    const Eigen::Isometry3d tip = to_eigen(seg.getFrameToTip());
    if (jnt.getType() == KDL::Joint::None) {
      pending = pending * tip;
      continue;
    }
    Joint j;
    const Eigen::Vector3d origin = to_eigen(jnt.JointOrigin());
    j.axis = to_eigen(jnt.JointAxis()).normalized();
    switch (jnt.getType()) {
      case KDL::Joint::RotAxis: case KDL::Joint::RotX: case KDL::Joint::RotY: case KDL::Joint::RotZ:
        j.prismatic = false;
        break;
      case KDL::Joint::TransAxis: case KDL::Joint::TransX: case KDL::Joint::TransY:
      case KDL::Joint::TransZ:
        j.prismatic = true;
        break;
      default:
        if (why) *why = "ChainKinematics: unsupported joint type of '" + jnt.getName() + "'";
        return Status::kModelError;
    }
    // The motion about a line through `origin`: Tr(origin) * motion(q) * Tr(-origin).
    j.pre = Eigen::Isometry3d::Identity();
    j.pre.translation() = origin;
    j.post = Eigen::Isometry3d::Identity();
    j.post.translation() = -origin;
    j.post = j.post * tip;
    if (k.joints_.empty()) {
      k.base_ = pending;
    } else {
      k.joints_.back().post = k.joints_.back().post * pending;
    }
    pending = Eigen::Isometry3d::Identity();
    k.joints_.push_back(j);
  }
  if (k.joints_.empty()) {
    if (why) *why = "ChainKinematics: the chain has no moving joint";
    return Status::kModelError;
  }
  k.joints_.back().post = k.joints_.back().post * pending;
  // Fold each joint's `pre` (a pure translation to its axis point) into what comes before it,
  // so that a tick costs one rotation and one rigid product per joint.
  k.base_ = k.base_ * k.joints_.front().pre;
  for (std::size_t i = 0; i + 1 < k.joints_.size(); ++i)
    k.joints_[i].post = k.joints_[i].post * k.joints_[i + 1].pre;
  for (Joint& j : k.joints_) j.pre = Eigen::Isometry3d::Identity();
  k.nq_ = static_cast<int>(k.joints_.size());
  if (k.nq_ != model.nq()) {
    if (why) *why = "ChainKinematics: joint count differs from the model's";
    return Status::kModelError;
  }
  k.axes_.resize(3, k.nq_);
  k.points_.resize(3, k.nq_);
  *out = std::move(k);
  return Status::kOk;
}

void ChainKinematics::apply(const Joint& j, double q, Eigen::Isometry3d& T) noexcept {
  if (j.prismatic) {
    T.translation() += T.linear() * (j.axis * q);
  } else {
    T.linear() = T.linear() * Eigen::AngleAxisd(q, j.axis).toRotationMatrix();
  }
  T = T * j.post;
}

void ChainKinematics::forward(const Eigen::Ref<const Eigen::VectorXd>& q,
                              Eigen::Isometry3d& T) noexcept {
  T = base_;
  for (int i = 0; i < nq_; ++i) apply(joints_[i], q[i], T);
}

void ChainKinematics::forward_jacobian(const Eigen::Ref<const Eigen::VectorXd>& q,
                                       Eigen::Isometry3d& T, Eigen::Ref<Eigen::MatrixXd> J) noexcept {
  T = base_;
  for (int i = 0; i < nq_; ++i) {
    const Joint& j = joints_[i];
    // The joint axis and a point on it, in the root frame, before the joint moves.
    axes_.col(i) = T.linear() * j.axis;
    points_.col(i) = T.translation();
    apply(j, q[i], T);
  }
  const Eigen::Vector3d tip = T.translation();
  for (int i = 0; i < nq_; ++i) {
    const Eigen::Vector3d z = axes_.col(i);
    if (joints_[i].prismatic) {
      J.col(i).head<3>() = z;
      J.col(i).tail<3>().setZero();
    } else {
      J.col(i).head<3>() = z.cross(tip - points_.col(i));
      J.col(i).tail<3>() = z;
    }
  }
}

}  // namespace kiloloop
