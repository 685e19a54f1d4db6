#include "kiloloop/kinematics/leg_gravity.hpp"

#include <algorithm>
#include <cmath>
#include <random>

#include <Eigen/QR>

namespace kiloloop {
namespace {
// pi [rad] (M_PI is POSIX, not ISO C++: firmware toolchains); its own name in the unity build
constexpr double kHalfTurn = 3.14159265358979323846;

// Three draws as a vector, drawn z, then y, then x. Sequenced on purpose: the order in which a
// call's arguments are evaluated is unspecified in C++ (GCC takes them right to left on x86-64,
// left to right on aarch64), so Vector3d(draw(), draw(), draw()) is another vector on another
// target. z first is the order the x86-64 build always had: its fits and baselines stay.
template <class Draw>
Eigen::Vector3d draw_vector(Draw&& draw) {
  const double z = draw();
  const double y = draw();
  const double x = draw();
  return Eigen::Vector3d(x, y, z);
}
}  // namespace

// b[3 u + v] = U_u V_v, U = {1, c1, s1, c12, s12}, V = {1, c0, s0}.
void LegGravity::terms(const LegKinematics::Trig& t, double* b) noexcept {
  const double U[5] = {1.0, t.c1, t.s1, t.c12, t.s12};
  for (int u = 0; u < 5; ++u) {
    b[3 * u] = U[u];
    b[3 * u + 1] = U[u] * t.c0;
    b[3 * u + 2] = U[u] * t.s0;
  }
}

Status LegGravity::configure(const RobotModel& model, const std::string& trunk, const std::string& foot,
                             const LegKinematics& kinematics, LegGravity* out, std::string* why) {
  auto fail = [&](const std::string& what) {
    if (why) *why = "leg '" + foot + "': " + what;
    return Status::kModelError;
  };
  KDL::Chain chain;
  if (!model.tree().getChain(trunk, foot, chain) || chain.getNrOfJoints() != 3)
    return fail("no 3-joint chain from '" + trunk + "'");
  ChainRne rne;
  const Status s = ChainRne::configure(chain, &rne, why);
  if (s != Status::kOk) return s;
  // Fit: the first moment at 60 poses over the joints' whole circle (deterministic), least squares.
  std::mt19937 rng(20261125);
  std::uniform_real_distribution<double> angle(-kHalfTurn, kHalfTurn);
  constexpr int kFit = 60;
  Eigen::Matrix<double, kFit, kTerms> B;
  Eigen::Matrix<double, kFit, 3> M;
  auto draw = [&] { return angle(rng); };
  for (int k = 0; k < kFit; ++k) {
    const Eigen::Vector3d q = draw_vector(draw);
    Eigen::Vector3d foot_pos, moment;
    Eigen::Matrix3d J;
    LegKinematics::Trig trig;
    kinematics.foot_and_jacobian(q, &foot_pos, &J, &trig);
    double b[kTerms];
    terms(trig, b);
    for (int j = 0; j < kTerms; ++j) B(k, j) = b[j];
    double mass = 0.0;
    rne.first_moment(q.data(), &moment, &mass);
    M.row(k) = moment.transpose();
  }
  LegGravity g;
  g.kinematics_ = kinematics;
  g.moment_ = B.colPivHouseholderQr().solve(M);
  // Check: torques against ChainRne's gravity pass at other poses and gravity directions.
  double worst = 0.0, scale = 0.0;
  for (int k = 0; k < 40; ++k) {
    const Eigen::Vector3d q = draw_vector(draw);
    const Eigen::Vector3d gravity = 9.81 * draw_vector(draw).normalized();
    Eigen::Vector3d ref;
    rne.gravity_torque(q.data(), gravity, ref.data());
    worst = std::max(worst, (g.torque(q, gravity) - ref).lpNorm<Eigen::Infinity>());
    scale = std::max(scale, ref.lpNorm<Eigen::Infinity>());
  }
  if (!(worst <= 1e-9 * (1.0 + scale)) || !g.moment_.allFinite())
    return fail("gravity torques off the abduction / pitch / knee form by " + std::to_string(worst) +
                " N m (Newton-Euler's up to " + std::to_string(scale) + " N m)");
  *out = std::move(g);
  return Status::kOk;
}

// tau_j = dV/dq_j = -(dM/dq_j) . g = -sum_b (d b / d q_j) w_b with w_b = moment_b . g: the terms'
// derivatives through the kinematics' angles (q0 = sign0 q[0], p1 and p12 move with sign1 q[1],
// p12 with sign2 q[2]).
Eigen::Vector3d LegGravity::torque(const LegKinematics::Trig& t, const Eigen::Vector3d& gravity_trunk) const noexcept {
  const Eigen::Matrix<double, kTerms, 1> w = moment_ * gravity_trunk;
  const double U[5] = {1.0, t.c1, t.s1, t.c12, t.s12};
  double d0 = 0.0;  // dV/dq0 (signed angle)
  double W[5];      // w contracted with V = {1, c0, s0}
#pragma GCC unroll 5
  for (int u = 0; u < 5; ++u) {
    d0 += U[u] * (t.c0 * w[3 * u + 2] - t.s0 * w[3 * u + 1]);
    W[u] = w[3 * u] + t.c0 * w[3 * u + 1] + t.s0 * w[3 * u + 2];
  }
  const double d1 = t.c1 * W[2] - t.s1 * W[1];      // d/dp1
  const double d12 = t.c12 * W[4] - t.s12 * W[3];   // d/dp12
  const Eigen::Vector3d& sign = kinematics_.geometry().sign;
  return Eigen::Vector3d(-sign[0] * d0, -sign[1] * (d1 + d12), -sign[2] * d12);
}

Eigen::Vector3d LegGravity::torque(const Eigen::Vector3d& q, const Eigen::Vector3d& gravity_trunk) const noexcept {
  Eigen::Vector3d foot;
  Eigen::Matrix3d J;
  LegKinematics::Trig trig;
  kinematics_.foot_and_jacobian(q, &foot, &J, &trig);
  return torque(trig, gravity_trunk);
}

}  // namespace kiloloop
