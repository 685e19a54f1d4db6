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

bool is_translational(const KDL::Joint& joint) {
  const KDL::Joint::JointType t = joint.getType();
  return t == KDL::Joint::TransAxis || t == KDL::Joint::TransX || t == KDL::Joint::TransY ||
         t == KDL::Joint::TransZ;
}

// Per joint, a bound on the distance from (a point of) its axis to any capsule point that it moves,
// whatever the configuration: by the triangle inequality along the chain, a revolute joint k's
// origin o_k is |tip_k - o_k| from the next frame (rotation about o_k keeps it), each later segment
// adds at most |o_i| + |tip_i - o_i|, and the capsule end adds its norm in its link frame.
// A point at distance d from an axis moves at most d per radian about it, so along an edge a capsule
// point moves at most reach . |dq|, and so does every capsule-box distance.
Eigen::VectorXd joint_reach(const RobotModel& model, const std::vector<LinkCapsule>& capsules,
                            const std::vector<int>& capsule_frame) {
  const KDL::Chain& chain = model.chain();
  const unsigned n = chain.getNrOfSegments();
  std::vector<double> seg_len(n), seg_in(n);  // |tip - o| and |o| of each segment
  std::vector<int> joint_of(n, -1);
  int j = 0;
  for (unsigned k = 0; k < n; ++k) {
    const KDL::Segment& seg = chain.getSegment(k);
    const KDL::Vector o = seg.getJoint().JointOrigin();
    seg_len[k] = (seg.getFrameToTip().p - o).Norm();
    seg_in[k] = o.Norm();
    if (seg.getJoint().getType() != KDL::Joint::Fixed) joint_of[k] = j++;
  }
  Eigen::VectorXd reach = Eigen::VectorXd::Zero(model.nq());
  for (std::size_t c = 0; c < capsules.size(); ++c) {
    const int m = capsule_frame[c];  // frame m is the tip of segment m - 1
    const double end = std::fmax(capsules[c].a.norm(), capsules[c].b.norm());
    double d = end;
    for (int k = m - 1; k >= 0; --k) {  // d: bound from o_k to the capsule, built outward-in
      d += seg_len[k];
      if (joint_of[k] >= 0) reach[joint_of[k]] = std::fmax(reach[joint_of[k]], d);
      d += seg_in[k];
    }
  }
  return reach;
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
  if (!(c.edge_tolerance > 0.0) || !std::isfinite(c.edge_tolerance)) return fail("edge_tolerance must be finite and > 0");
  if (c.max_edge_samples < 2) return fail("max_edge_samples must be >= 2");
  for (unsigned k = 0; k < model.chain().getNrOfSegments(); ++k)
    if (is_translational(model.chain().getSegment(k).getJoint()))
      return fail("joint '" + model.chain().getSegment(k).getJoint().getName() +
                  "' is prismatic: the collision checker supports revolute and fixed joints");
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
  c.grid_clearance_ = Eigen::VectorXd::Zero(config.max_edge_samples);
  c.reach_ = joint_reach(*c.model_, config.capsules, c.capsule_frame_);
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

double ArmCollisionChecker::clearance_along(const VecRef& q0, const VecRef& q1, double s) noexcept {
  if (s >= 1.0) q_interp_ = q1;  // the end exactly, not q0 + 1.0 * (q1 - q0)
  else q_interp_ = q0 + s * (q1 - q0);
  return clearance(q_interp_);
}

bool ArmCollisionChecker::segment_free(const VecRef& q0, const VecRef& q1, double max_step) noexcept {
  if (q0.size() != nq_ || q1.size() != nq_ || !(max_step > 0.0)) return false;
  const double span = (q1 - q0).cwiseAbs().maxCoeff();
  if (!std::isfinite(span)) return false;
  const double steps_real = std::ceil(span / max_step);
  if (steps_real + 1.0 > config_.max_edge_samples) return false;
  const int steps = std::max(1, static_cast<int>(steps_real));
  // Pass 1, the fixed grid (cheap, and where a colliding edge usually shows itself): every sample
  // must have clearance > edge_tolerance.
  for (int i = 0; i <= steps; ++i) {
    grid_clearance_[i] = clearance_along(q0, q1, static_cast<double>(i) / steps);
    if (!(grid_clearance_[i] > config_.edge_tolerance)) return false;  // also NaN
  }
  // Pass 2, between the samples. Along q(s) = q0 + s (q1 - q0) every capsule-box distance changes
  // at most `rate` per unit s, so on [a, b] the distance stays > margin if c_a + c_b > rate (b - a)
  // (the two cones from the ends cover it). An interval that this does not prove free is halved,
  // its midpoint checked like a grid sample; the work is capped by max_edge_samples.
  const double rate = reach_.dot((q1 - q0).cwiseAbs());
  struct Interval {
    double a, ca, b, cb;
  };
  constexpr int kMaxDepth = 64;
  Interval stack[kMaxDepth];
  int budget = config_.max_edge_samples - (steps + 1);
  for (int i = 0; i < steps; ++i) {
    int top = 0;
    stack[top++] = {static_cast<double>(i) / steps, grid_clearance_[i], static_cast<double>(i + 1) / steps,
                    grid_clearance_[i + 1]};
    while (top > 0) {
      const Interval iv = stack[--top];
      if (iv.ca + iv.cb > rate * (iv.b - iv.a)) continue;
      if (--budget < 0 || top + 2 > kMaxDepth) return false;
      const double m = 0.5 * (iv.a + iv.b);
      const double cm = clearance_along(q0, q1, m);
      if (!(cm > config_.edge_tolerance)) return false;
      stack[top++] = {m, cm, iv.b, iv.cb};
      stack[top++] = {iv.a, iv.ca, m, cm};  // the nearer half first
    }
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
