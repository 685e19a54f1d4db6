#include "kiloloop/planning/arm_collision.hpp"

#include <cmath>
#include <limits>

namespace kiloloop {
namespace {

// Frame index of a link: 0 for the chain root, k + 1 for the child link of segment k; -1 if none.
int frame_of(const RobotModel& model, const std::string& link) {
  if (link == model.root_name()) return 0;
  const KDL::Chain& chain = model.chain();
  for (unsigned k = 0; k < chain.getNrOfSegments(); ++k)
    if (chain.getSegment(k).getName() == link) return static_cast<int>(k) + 1;
  return -1;
}

}  // namespace

Status validate(const ArmCollisionConfig& c, const RobotModel& model, std::string* why) {
  auto fail = [&](const std::string& msg) {
    if (why) *why = msg;
    return Status::kInvalidConfig;
  };
  if (!model.has_chain()) {
    if (why) *why = "collision checking needs a serial chain";
    return Status::kModelError;
  }
  if (!(c.margin >= 0.0) || !std::isfinite(c.margin)) return fail("margin must be finite and >= 0");
  for (const LinkCapsule& cap : c.capsules) {
    if (frame_of(model, cap.link) < 0) return fail("capsule link '" + cap.link + "' is not in the chain");
    if (!cap.a.allFinite() || !cap.b.allFinite() || !(cap.radius >= 0.0) || !std::isfinite(cap.radius))
      return fail("capsule on '" + cap.link + "': ends must be finite and radius >= 0");
  }
  for (const OrientedBox& box : c.boxes) {
    if (!box.center.allFinite() || !box.half_extents.allFinite() || (box.half_extents.array() < 0.0).any())
      return fail("box: center and half_extents must be finite, half_extents >= 0");
    if (!box.rotation.allFinite() ||
        (box.rotation.transpose() * box.rotation - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-9)
      return fail("box: rotation must be orthonormal");
  }
  return Status::kOk;
}

Status ArmCollisionChecker::configure(const ArmCollisionConfig& config, RobotModelPtr model,
                                      ArmCollisionChecker* out, std::string* why) {
  if (!model) {
    if (why) *why = "model is null";
    return Status::kModelError;
  }
  const Status s = validate(config, *model, why);
  if (failed(s)) return s;
  ArmCollisionChecker c;
  c.model_ = std::move(model);
  c.nq_ = c.model_->nq();
  c.config_ = config;
  for (const LinkCapsule& cap : config.capsules) c.capsule_frame_.push_back(frame_of(*c.model_, cap.link));
  c.frames_.assign(c.model_->chain().getNrOfSegments() + 1, Eigen::Isometry3d::Identity());
  c.q_interp_ = Eigen::VectorXd::Zero(c.nq_);
  *out = std::move(c);
  return Status::kOk;
}

bool ArmCollisionChecker::link_frames(const VecRef& q) noexcept {
  if (q.size() != nq_ || !q.allFinite()) return false;
  const KDL::Chain& chain = model_->chain();
  KDL::Frame F = KDL::Frame::Identity();
  unsigned j = 0;
  for (unsigned k = 0; k < chain.getNrOfSegments(); ++k) {
    const KDL::Segment& seg = chain.getSegment(k);
    const double qj = seg.getJoint().getType() != KDL::Joint::Fixed ? q[j++] : 0.0;
    F = F * seg.pose(qj);
    Eigen::Isometry3d& T = frames_[k + 1];
    for (int r = 0; r < 3; ++r) {
      for (int col = 0; col < 3; ++col) T.linear()(r, col) = F.M(r, col);
      T.translation()[r] = F.p[r];
    }
  }
  return true;
}

double ArmCollisionChecker::clearance(const VecRef& q) noexcept {
  ++checks_;
  if (!link_frames(q)) return std::numeric_limits<double>::quiet_NaN();
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t c = 0; c < config_.capsules.size(); ++c) {
    const LinkCapsule& cap = config_.capsules[c];
    const Eigen::Isometry3d& T = frames_[capsule_frame_[c]];
    const Eigen::Vector3d a = T * cap.a, b = T * cap.b;
    for (const OrientedBox& box : config_.boxes)
      best = std::fmin(best, capsule_box_distance(a, b, cap.radius, box));
  }
  return best - config_.margin;
}

bool ArmCollisionChecker::segment_free(const VecRef& q0, const VecRef& q1, double max_step) noexcept {
  if (q0.size() != nq_ || q1.size() != nq_ || !(max_step > 0.0)) return false;
  const double span = (q1 - q0).cwiseAbs().maxCoeff();
  if (!std::isfinite(span)) return false;
  const int steps = std::max(1, static_cast<int>(std::ceil(span / max_step)));
  for (int i = 0; i <= steps; ++i) {
    q_interp_ = q0 + (static_cast<double>(i) / steps) * (q1 - q0);
    if (!(clearance(q_interp_) > 0.0)) return false;
  }
  return true;
}

Status ArmCollisionChecker::capsules_at(const VecRef& q, Eigen::Ref<Eigen::Matrix3Xd> a,
                                        Eigen::Ref<Eigen::Matrix3Xd> b) noexcept {
  const Eigen::Index n = static_cast<Eigen::Index>(config_.capsules.size());
  if (a.cols() != n || b.cols() != n) return Status::kBadSize;
  if (!link_frames(q)) return q.size() != nq_ ? Status::kBadSize : Status::kNonFiniteReference;
  for (Eigen::Index c = 0; c < n; ++c) {
    const Eigen::Isometry3d& T = frames_[capsule_frame_[c]];
    a.col(c) = T * config_.capsules[c].a;
    b.col(c) = T * config_.capsules[c].b;
  }
  return Status::kOk;
}

}  // namespace kiloloop
