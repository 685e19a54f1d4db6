#include "kiloloop/dynamics/chain_rne.hpp"
#include "kiloloop/model/kdl_eigen.hpp"

#include <cmath>

#include <Eigen/Geometry>  // cross products

#include <kdl/frames.hpp>
#include <kdl/segment.hpp>

namespace kiloloop {

Status ChainRne::configure(const KDL::Chain& chain, ChainRne* out, std::string* why) {
  // The Rodrigues split of a revolute pose (Segment::rot_0 ..), from its axis, origin and tip.
  auto split = [](Segment& s) {
    if (s.kind != Kind::kRevolute) return;
    const Eigen::Matrix3d aat = s.axis * s.axis.transpose();
    Eigen::Matrix3d cross;  // [a]x
    cross << 0.0, -s.axis.z(), s.axis.y(), s.axis.z(), 0.0, -s.axis.x(), -s.axis.y(), s.axis.x(), 0.0;
    s.rot_0 = aat * s.tip_rot;
    s.rot_c = s.tip_rot - s.rot_0;
    s.rot_s = cross * s.tip_rot;
    s.pos_0 = s.origin + aat * s.tip_pos;
    s.pos_c = s.tip_pos - aat * s.tip_pos;
    s.pos_s = s.axis.cross(s.tip_pos);
  };
  ChainRne r;
  for (unsigned i = 0; i < chain.getNrOfSegments(); ++i) {
    const KDL::Segment& seg = chain.getSegment(i);
    const KDL::Joint& joint = seg.getJoint();
    Segment s;
    switch (joint.getType()) {
      case KDL::Joint::Fixed: s.kind = Kind::kFixed; break;
      case KDL::Joint::RotAxis: case KDL::Joint::RotX: case KDL::Joint::RotY: case KDL::Joint::RotZ:
        s.kind = Kind::kRevolute;
        break;
      default: s.kind = Kind::kPrismatic; break;
    }
    // KDL's segment pose is joint.pose(q) * f_tip with f_tip = joint.pose(0)^-1 getFrameToTip()
    // (Segment keeps that private): the tip frame after the joint's own offset.
    const KDL::Frame tip = joint.pose(0.0).Inverse() * seg.getFrameToTip();
    s.tip_rot = to_eigen(tip.M);
    s.tip_pos = to_eigen(tip.p);
    s.axis = Eigen::Vector3d::Zero();
    s.origin = Eigen::Vector3d::Zero();
    s.s_lin = s.s_ang = Eigen::Vector3d::Zero();
    if (s.kind != Kind::kFixed) {
      s.joint = r.nq_++;
      s.axis = to_eigen(joint.JointAxis()).normalized();
      s.origin = to_eigen(joint.JointOrigin());
      s.rotor_inertia = joint.getInertia();
      // S in the tip frame: rotation about the axis through the joint origin, whose tip-frame
      // expression does not depend on q (the joint's rotation leaves its own axis fixed).
      if (s.kind == Kind::kRevolute) {
        s.s_ang = s.tip_rot.transpose() * s.axis;
        s.s_lin = s.tip_rot.transpose() * s.axis.cross(s.tip_pos);
      } else {
        s.s_lin = s.tip_rot.transpose() * s.axis;
      }
    }
    const KDL::RigidBodyInertia& I = seg.getInertia();
    s.mass = I.getMass();
    s.h = s.mass * to_eigen(I.getCOG());
    const KDL::RotationalInertia Io = I.getRotationalInertia();
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) s.inertia(a, b) = Io.data[3 * a + b];
    s.has_inertia = s.mass != 0.0 || !s.inertia.isZero(0.0);
    split(s);
    r.segments_.push_back(s);
  }
  // The joint pose and unit twist this pass assumes must be KDL's (scale 1, offset 0).
  for (unsigned i = 0; i < chain.getNrOfSegments(); ++i) {
    const Segment& s = r.segments_[i];
    if (s.kind == Kind::kFixed) continue;
    for (double q : {0.0, 0.7, -2.1}) {
      State x;
      r.pose(s, q, x);
      const KDL::Frame f = chain.getSegment(i).pose(q);
      const KDL::Twist t = chain.getSegment(i).twist(q, 1.0);
      const KDL::Twist S = f.M.Inverse(t);
      const double err = (to_eigen(f.M) - x.rot).cwiseAbs().maxCoeff() + (to_eigen(f.p) - x.pos).cwiseAbs().maxCoeff() +
                         (to_eigen(S.vel) - s.s_lin).cwiseAbs().maxCoeff() + (to_eigen(S.rot) - s.s_ang).cwiseAbs().maxCoeff();
      if (!(err < 1e-9 * (1.0 + s.tip_pos.norm() + s.origin.norm()))) {
        if (why) *why = "ChainRne: joint '" + chain.getSegment(i).getJoint().getName() +
                        "' has a scale or offset this pass does not model";
        return Status::kModelError;
      }
    }
  }
  // A fixed segment moves rigidly with the segment before it: its inertia joins that segment's
  // (transformed into its frame) and its frame to tip is carried into the next segment's joint
  // placement, so each tick does one pass per moving segment (plus a leading fixed one) instead of
  // one per segment (a URDF chain carries fixed base, flange and tool frames). Exact in exact arithmetic: the
  // torques move at round-off only (chain_rne_test.cpp against KDL).
  {
    const std::vector<Segment> in = r.segments_;
    std::vector<Segment> kept;
    std::vector<KDL::RigidBodyInertia> inertia;  // of each kept segment, in its tip frame
    KDL::Frame F = KDL::Frame::Identity();       // the current parent frame in the last kept one
    auto frame_of = [](const Eigen::Matrix3d& m, const Eigen::Vector3d& p) {
      return KDL::Frame(KDL::Rotation(m(0, 0), m(0, 1), m(0, 2), m(1, 0), m(1, 1), m(1, 2), m(2, 0), m(2, 1), m(2, 2)),
                        KDL::Vector(p.x(), p.y(), p.z()));
    };
    for (size_t i = 0; i < in.size(); ++i) {
      const KDL::RigidBodyInertia& I = chain.getSegment(static_cast<unsigned>(i)).getInertia();
      const KDL::Frame tip = frame_of(in[i].tip_rot, in[i].tip_pos);
      if (in[i].kind == Kind::kFixed && !kept.empty()) {
        F = F * tip;
        inertia.back() = inertia.back() + F * I;
        continue;
      }
      Segment s = in[i];
      if (!kept.empty()) {  // re-express the joint and its tip in the last kept segment's frame
        const Eigen::Matrix3d R = to_eigen(F.M);
        s.axis = R * in[i].axis;
        s.origin = to_eigen(F.p) + R * in[i].origin;
        s.tip_rot = R * in[i].tip_rot;
        s.tip_pos = R * in[i].tip_pos;
      }
      kept.push_back(s);
      inertia.push_back(I);
      F = KDL::Frame::Identity();
    }
    for (size_t k = 0; k < kept.size(); ++k) {
      Segment& s = kept[k];
      s.mass = inertia[k].getMass();
      s.h = s.mass * to_eigen(inertia[k].getCOG());
      const KDL::RotationalInertia Io = inertia[k].getRotationalInertia();
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) s.inertia(a, b) = Io.data[3 * a + b];
      s.has_inertia = s.mass != 0.0 || !s.inertia.isZero(0.0);
    }
    r.segments_ = std::move(kept);
    r.tail_rot_ = to_eigen(F.M);
    r.tail_pos_ = to_eigen(F.p);
  }
  for (Segment& s : r.segments_) split(s);  // the folded joints' own
  State rest;  // every pose identity, every motion and force zero until the first pass
  rest.rot.setIdentity();
  rest.pos = rest.v = rest.w = rest.a = rest.aw = rest.f = rest.n = Eigen::Vector3d::Zero();
  r.state_.assign(r.segments_.size(), rest);
  *out = std::move(r);
  return Status::kOk;
}

// The segment's tip frame in its parent frame at joint position q: rot = R_joint tip_rot,
// pos = origin + R_joint tip_pos (revolute, through the Rodrigues split), or a translation along
// the axis (prismatic).
void ChainRne::pose(const Segment& s, double q, State& x) const noexcept {
  if (s.kind == Kind::kRevolute) pose(s, q, std::cos(q), std::sin(q), x);
  else pose(s, q, 1.0, 0.0, x);
}

void ChainRne::pose(const Segment& s, double q, double c, double sn, State& x) const noexcept {
  switch (s.kind) {
    case Kind::kFixed:
      x.rot = s.tip_rot;
      x.pos = s.tip_pos;
      break;
    case Kind::kRevolute: {
      x.rot = s.rot_0 + c * s.rot_c + sn * s.rot_s;
      x.pos = s.pos_0 + c * s.pos_c + sn * s.pos_s;
      break;
    }
    case Kind::kPrismatic:
      x.rot = s.tip_rot;
      x.pos = s.origin + q * s.axis + s.tip_pos;
      break;
  }
}

void ChainRne::inverse_dynamics(const double* q, const double* qd, const double* qdd,
                                const Eigen::Vector3d& gravity, double* tau) noexcept {
  // Root at rest, accelerating at -g (gravity as a base acceleration, as KDL).
  const Eigen::Vector3d zero = Eigen::Vector3d::Zero();
  inverse_dynamics(q, qd, qdd, zero, zero, -gravity, zero, tau, nullptr);
}

void ChainRne::inverse_dynamics(const double* q, const double* qd, const double* qdd, const Eigen::Vector3d& v0,
                                const Eigen::Vector3d& w0, const Eigen::Vector3d& a0, const Eigen::Vector3d& aw0,
                                double* tau, double* root_wrench) noexcept {
  Eigen::Vector3d v_p = v0, w_p = w0, a_p = a0, aw_p = aw0;
  for (size_t i = 0; i < segments_.size(); ++i) {
    const Segment& s = segments_[i];
    State& x = state_[i];
    const bool moving = s.kind != Kind::kFixed;
    pose(s, moving ? q[s.joint] : 0.0, x);
    const Eigen::Matrix3d& E = x.rot;
    // Parent twist and acceleration into this frame: [E^T (v - p x w); E^T w].
    x.w.noalias() = E.transpose() * w_p;
    x.v.noalias() = E.transpose() * (v_p - x.pos.cross(w_p));
    x.aw.noalias() = E.transpose() * aw_p;
    x.a.noalias() = E.transpose() * (a_p - x.pos.cross(aw_p));
    if (moving) {
      const double dq = qd[s.joint], ddq = qdd[s.joint];
      const Eigen::Vector3d vj = s.s_lin * dq, wj = s.s_ang * dq;
      x.v += vj;
      x.w += wj;
      // + S qdd + v x vj (motion cross product; S is constant in this frame).
      x.a += s.s_lin * ddq + x.w.cross(vj) + x.v.cross(wj);
      x.aw += s.s_ang * ddq + x.w.cross(wj);
    }
    if (s.has_inertia) {
      // f = I a + v x* (I v), I t = [m t_v - h x t_w; I_o t_w + h x t_v].
      const Eigen::Vector3d pv = s.mass * x.v - s.h.cross(x.w);
      const Eigen::Vector3d lv = s.inertia * x.w + s.h.cross(x.v);
      x.f = s.mass * x.a - s.h.cross(x.aw) + x.w.cross(pv);
      x.n = s.inertia * x.aw + s.h.cross(x.a) + x.w.cross(lv) + x.v.cross(pv);
    } else {
      x.f.setZero();
      x.n.setZero();
    }
    v_p = x.v;
    w_p = x.w;
    a_p = x.a;
    aw_p = x.aw;
  }
  backward(tau, qdd, root_wrench);
}

void ChainRne::gravity_torque(const double* q, const Eigen::Vector3d& gravity, double* tau) noexcept {
  Eigen::Vector3d a_p = -gravity;  // no velocity and no angular acceleration anywhere
  for (size_t i = 0; i < segments_.size(); ++i) {
    const Segment& s = segments_[i];
    State& x = state_[i];
    const double qi = s.kind != Kind::kFixed ? q[s.joint] : 0.0;
    pose(s, qi, x);
    x.a.noalias() = x.rot.transpose() * a_p;
    if (s.has_inertia) {
      x.f = s.mass * x.a;
      x.n = s.h.cross(x.a);
    } else {
      x.f.setZero();
      x.n.setZero();
    }
    a_p = x.a;
  }
  backward(tau, nullptr, nullptr);
}

template <class PoseOf>
void ChainRne::compose_tip(PoseOf pose_of, Eigen::Matrix3d* rot, Eigen::Vector3d* pos) const noexcept {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < segments_.size(); ++i) {
    const State& x = pose_of(i);
    p.noalias() += R * x.pos;
    R = R * x.rot;
  }
  *pos = p + R * tail_pos_;
  *rot = R * tail_rot_;
}

void ChainRne::tip_pose(const double* q, Eigen::Matrix3d* rot, Eigen::Vector3d* pos) const noexcept {
  State x;
  compose_tip(
      [&](size_t i) -> const State& {
        const Segment& s = segments_[i];
        pose(s, s.kind != Kind::kFixed ? q[s.joint] : 0.0, x);
        return x;
      },
      rot, pos);
}

void ChainRne::last_tip_pose(Eigen::Matrix3d* rot, Eigen::Vector3d* pos) const noexcept {
  compose_tip([&](size_t i) -> const State& { return state_[i]; }, rot, pos);
}

void ChainRne::last_tip_position(Eigen::Vector3d* pos) const noexcept {
  Eigen::Vector3d p = tail_pos_;
  for (size_t k = segments_.size(); k-- > 0;) {
    const State& x = state_[k];
    p = x.pos + x.rot * p;
  }
  *pos = p;
}

void ChainRne::first_moment(const double* q, Eigen::Vector3d* moment, double* mass) const noexcept {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  double m = 0.0;
  State x;
  for (const Segment& s : segments_) {
    pose(s, s.kind != Kind::kFixed ? q[s.joint] : 0.0, x);
    p.noalias() += R * x.pos;
    R = R * x.rot;
    // m c in the root frame: the segment's mass at its tip origin plus its first moment h
    // (about that origin, tip axes) turned into root axes.
    sum += s.mass * p;
    sum.noalias() += R * s.h;
    m += s.mass;
  }
  *moment = sum;
  *mass = m;
}

// Leaf to root: tau_j = S . f (+ rotor inertia qdd), and each segment's wrench onto its parent,
// [E f; E n + p x E f]; the root segment's onto the base when asked.
void ChainRne::backward(double* tau, const double* qdd, double* root_wrench) noexcept {
  if (root_wrench)
    for (int i = 0; i < 6; ++i) root_wrench[i] = 0.0;
  for (size_t k = segments_.size(); k-- > 0;) {
    const Segment& s = segments_[k];
    State& x = state_[k];
    if (s.kind != Kind::kFixed) {
      tau[s.joint] = s.s_lin.dot(x.f) + s.s_ang.dot(x.n);
      if (qdd) tau[s.joint] += s.rotor_inertia * qdd[s.joint];
    }
    if (k > 0 || root_wrench) {
      const Eigen::Vector3d f = x.rot * x.f;
      const Eigen::Vector3d n = x.rot * x.n + x.pos.cross(f);
      if (k > 0) {
        state_[k - 1].f += f;
        state_[k - 1].n += n;
      } else {
        Eigen::Map<Eigen::Matrix<double, 6, 1>>(root_wrench) << f, n;
      }
    }
  }
}

}  // namespace kiloloop
