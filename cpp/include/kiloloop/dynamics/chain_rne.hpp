#pragma once
// ChainRne: recursive Newton-Euler inverse dynamics over a KDL serial chain, our own pass with
// everything constant precomputed at configure: per segment the joint axis, the frame to the
// tip, the motion subspace S in the segment frame (constant for KDL's joints: a rotation leaves
// its own axis fixed, a translation does not rotate) and the inertia (mass, first moment,
// rotational inertia about the segment origin). KDL::ChainIdSolver_RNE runs the same recursion
// but rebuilds the joint pose three times a segment (pose, twist(q, qd), twist(q, 1)) and
// re-expresses S every call; fixed segments are folded into their parent here. On the UR5 chain
// this pass takes 0.79 us of CPU time a call against KDL's 1.33-1.81 us (-O2, a loaded 2-core VM,
// 2026-11-23); its gravity-only pass 0.41-0.49 us. Results equal KDL's to round-off
// (chain_rne_test.cpp).
//
// Same algorithm and conventions as KDL: twists [v; w] and wrenches [f; n] in each segment's
// tip frame, gravity as a base acceleration -g, torques include the joint's rotor inertia
// (KDL::Joint::getInertia() * qdd). Joint scale and offset other than 1 and 0 are refused at
// configure (our model builders never set them).
#include <string>
#include <vector>

#include <Eigen/Core>
#include <kdl/chain.hpp>

#include "kiloloop/status.hpp"

namespace kiloloop {

class ChainRne {
 public:
  // Fails (kModelError, why) on a joint whose pose this pass does not reproduce (scale/offset).
  static Status configure(const KDL::Chain& chain, ChainRne* out, std::string* why);

  int nq() const { return nq_; }

  // tau = M(q) qdd + C(q, qd) qd + g(q) for gravity [m/s^2] in the chain root frame. (nq) each;
  // allocation-free. Inputs are not checked (Dynamics checks sizes and finiteness).
  void inverse_dynamics(const double* q, const double* qd, const double* qdd,
                        const Eigen::Vector3d& gravity, double* tau) noexcept;
  // The same pass on a moving base (an arm under a multirotor): the root frame's twist [v0; w0]
  // and spatial acceleration [a0; aw0] in its own axes (a0 carries -g: what an accelerometer at
  // the root reads, minus w0 x v0). root_wrench (6, may be null): [f; n] the base applies to the
  // chain at the root origin, root axes.
  void inverse_dynamics(const double* q, const double* qd, const double* qdd, const Eigen::Vector3d& v0,
                        const Eigen::Vector3d& w0, const Eigen::Vector3d& a0, const Eigen::Vector3d& aw0,
                        double* tau, double* root_wrench) noexcept;
  // tau = g(q): the same pass with qd = qdd = 0 (no velocity terms computed).
  void gravity_torque(const double* q, const Eigen::Vector3d& gravity, double* tau) noexcept;

  // The chain tip's pose in the root frame at q (rotation, position [m]): KDL's
  // ChainFkSolverPos_recursive over the same precomputed poses (trailing fixed frames included).
  void tip_pose(const double* q, Eigen::Matrix3d* rot, Eigen::Vector3d* pos) const noexcept;
  // The same at the q of the last inverse_dynamics or gravity_torque call, from the segment poses
  // that pass computed (no trigonometry again). Identity before any pass.
  void last_tip_pose(Eigen::Matrix3d* rot, Eigen::Vector3d* pos) const noexcept;
  // Only its position, composed leaf to root (p = pos_k + rot_k p: a matrix-vector product a
  // segment instead of last_tip_pose's matrix-matrix one); equal to it up to round-off.
  void last_tip_position(Eigen::Vector3d* pos) const noexcept;
  // The chain's first moment of mass sum(m_i c_i) [kg m] at q in the root frame, and its mass [kg].
  void first_moment(const double* q, Eigen::Vector3d* moment, double* mass) const noexcept;

 private:
  enum class Kind { kFixed, kRevolute, kPrismatic };
  struct Segment {
    Kind kind = Kind::kFixed;
    int joint = -1;              // index into q, -1 for a fixed segment
    Eigen::Vector3d axis;        // unit joint axis in the parent frame
    Eigen::Vector3d origin;      // joint origin in the parent frame [m]
    Eigen::Matrix3d tip_rot;     // frame to tip: rotation and translation [m]
    Eigen::Vector3d tip_pos;
    Eigen::Vector3d s_lin, s_ang;  // motion subspace S in the segment frame (per unit qd)
    // Revolute: the pose at q split by Rodrigues, R(a, q) = cos q I + sin q [a]x + (1 - cos q) a a^T,
    // into constants (configure): rot = rot_0 + cos q rot_c + sin q rot_s, pos likewise [m].
    // Per tick 9 + 3 entries of two products each, instead of building R(a, q) and multiplying.
    Eigen::Matrix3d rot_0, rot_c, rot_s;
    Eigen::Vector3d pos_0, pos_c, pos_s;
    double mass = 0.0;             // [kg]
    Eigen::Vector3d h;             // first moment m c about the segment origin [kg m]
    Eigen::Matrix3d inertia;       // rotational inertia about the segment origin [kg m^2]
    double rotor_inertia = 0.0;    // KDL::Joint::getInertia() [kg m^2 or kg]
    bool has_inertia = false;
  };
  // Per-call state of one segment: its pose in the parent frame, velocity, acceleration, force.
  struct State {
    Eigen::Matrix3d rot;
    Eigen::Vector3d pos, v, w, a, aw, f, n;
  };
  void pose(const Segment& s, double q, State& x) const noexcept;
  // The same from cos q and sin q (read by a revolute joint only).
  void pose(const Segment& s, double q, double cos_q, double sin_q, State& x) const noexcept;
  void backward(double* tau, const double* qdd, double* root_wrench) noexcept;
  // Root-frame pose of the chain tip from one pose per kept segment (parent frame), in order.
  template <class PoseOf>
  void compose_tip(PoseOf pose_of, Eigen::Matrix3d* rot, Eigen::Vector3d* pos) const noexcept;

  int nq_ = 0;
  std::vector<Segment> segments_;
  // Fixed frames after the last moving segment (a flange, a tool point): the chain tip in the
  // last kept segment's tip frame. Identity when the chain ends on a joint.
  Eigen::Matrix3d tail_rot_ = Eigen::Matrix3d::Identity();
  Eigen::Vector3d tail_pos_ = Eigen::Vector3d::Zero();
  std::vector<State> state_;
};

}  // namespace kiloloop
