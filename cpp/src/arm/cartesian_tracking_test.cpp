// Cartesian line + differential-IK tracking on the UR5: the line's geometry, closed-loop tracking
// against the exact rigid-body dynamics, zero allocations, determinism, bad input.
#include <cmath>
#include "test_values.hpp"
#include <cstring>

#include <Eigen/Cholesky>
#include <gtest/gtest.h>

#include "alloc_counter.hpp"
#include "kiloloop/arm/cartesian_tracking.hpp"
#include "kiloloop/trajectory/cartesian_line.hpp"
#include "test_models.hpp"

namespace kiloloop {
namespace {


Eigen::VectorXd q_start() {
  Eigen::VectorXd q(6);
  q << 0.0, -kPi / 2, kPi / 2, -kPi / 2, -kPi / 2, 0.0;
  return q;
}

CartesianLine make_line(const RobotModel& model, double t0, double duration) {
  ChainKinematics kin;
  std::string why;
  EXPECT_EQ(ChainKinematics::configure(model, &kin, &why), Status::kOk);
  Eigen::Isometry3d a, b;
  kin.forward(q_start(), a);
  b = a;
  b.translation() += Eigen::Vector3d(0.15, 0.2, -0.15);
  b.linear() = Eigen::AngleAxisd(0.6, Eigen::Vector3d(0, 0.6, 0.8)).toRotationMatrix() * a.linear();
  CartesianLine line;
  EXPECT_EQ(CartesianLine::configure(a, b, t0, duration, &line, &why), Status::kOk) << why;
  return line;
}

TEST(CartesianLine, EndsAtRestOnTheTargetAndTwistIsTheDerivative) {
  const RobotModelPtr model = testing::load_ur5();
  const CartesianLine line = make_line(*model, 0.5, 2.0);
  Eigen::Isometry3d T, Tn;
  Vector6d v, a, vn, an;
  line.sample(-1.0, T, v, a);
  EXPECT_EQ(v.norm(), 0.0);
  // Numerical derivative of the pose equals the twist (central differences, h = 1e-6).
  for (double t = 0.6; t < 2.5; t += 0.1) {
    const double h = 1e-6;
    line.sample(t - h, T, v, a);
    line.sample(t + h, Tn, vn, an);
    const Vector6d fd = pose_error(Tn, T) / (2 * h);
    line.sample(t, T, v, a);
    EXPECT_LT((fd - v).norm(), 1e-6) << "t " << t;
    EXPECT_LT(((vn - v) / h - a).norm(), 1e-3 * (1 + a.norm())) << "t " << t;
  }
  line.sample(3.0, T, v, a);
  EXPECT_EQ(v.norm(), 0.0);
  EXPECT_EQ(line.sample(NAN, T, v, a), Status::kNonFiniteReference);
  EXPECT_TRUE(T.matrix().allFinite());
  CartesianLine bad;
  std::string why;
  EXPECT_EQ(CartesianLine::configure(T, T, 0.0, 0.0, &bad, &why), Status::kInvalidConfig);
}

// Closed loop on the exact rigid-body model (semi-implicit Euler at 1 kHz).
struct Sim {
  Dynamics dyn;
  Eigen::VectorXd q, qd;
  Eigen::MatrixXd M;
  Eigen::VectorXd bias, zero;
  explicit Sim(RobotModelPtr model) : q(q_start()), qd(Eigen::VectorXd::Zero(6)), M(6, 6), bias(6),
                                      zero(Eigen::VectorXd::Zero(6)) {
    std::string why;
    Dynamics::configure(model, {0, 0, -9.81}, &dyn, &why);
  }
  void step(const Eigen::VectorXd& tau, double dt) {
    dyn.mass_matrix(q, M);
    dyn.inverse_dynamics(q, qd, zero, bias);
    qd += dt * M.ldlt().solve(tau - bias);
    q += dt * qd;
  }
};

TEST(CartesianTracking, FollowsTheLineInClosedLoopWithoutAllocating) {
  const RobotModelPtr model = testing::load_ur5();
  const CartesianLine line = make_line(*model, 0.2, 2.0);
  CartesianTrackingController c;
  std::string why;
  ASSERT_EQ(CartesianTrackingController::configure(CartesianTrackingConfig{}, model, &c, &why),
            Status::kOk) << why;
  ChainKinematics kin;
  ASSERT_EQ(ChainKinematics::configure(*model, &kin, &why), Status::kOk);
  Sim sim(model);
  CartesianTrackingInput in = c.make_input();
  CartesianTrackingOutput out = c.make_output();
  double max_err = 0.0;
  std::size_t allocations = 0;
  for (int k = 0; k < 3000; ++k) {
    in.t = in.stamp = k * 1e-3;
    in.q = sim.q;
    in.qd = sim.qd;
    Eigen::Isometry3d T_ref, T;
    Vector6d a;
    {
      // Sampling and the step: the whole 1 kHz path.
      testing::AllocationScope scope;
      line.sample(in.t, T_ref, in.twist_ref, a);
      in.pose_ref = T_ref.matrix();
      ASSERT_EQ(c.step(in, out), Status::kOk) << "tick " << k;
      allocations += scope.count();
    }
    kin.forward(sim.q, T);
    max_err = std::max(max_err, (T.translation() - T_ref.translation()).norm());
    sim.step(out.tau, 1e-3);
  }
  EXPECT_EQ(allocations, 0u);
  EXPECT_LT(max_err, 1e-3);
  EXPECT_LT(out.task_error.norm(), 1e-9);  // at rest at the end, the reference is exact
}

// A straight line whose ends lie on either side of the wrist singularity (q5 = -0.4 -> +0.4):
// exact tracking would need unbounded wrist speed. The reference stays within the velocity
// limits (status kSaturated while it cannot keep up), never NaN, and reaches the end pose
// (on the other wrist branch) once the line has ended.
TEST(CartesianTracking, ThroughTheWristSingularityStaysBoundedAndArrives) {
  const RobotModelPtr model = testing::load_ur5();
  ChainKinematics kin;
  std::string why;
  ASSERT_EQ(ChainKinematics::configure(*model, &kin, &why), Status::kOk);
  Eigen::VectorXd qa(6), qb(6);
  qa << 0.0, -1.2, 1.5, -1.9, -0.4, 0.3;
  qb = qa;
  qb[0] = 0.1;
  qb[4] = 0.4;
  Eigen::Isometry3d Ta, Tb;
  kin.forward(qa, Ta);
  kin.forward(qb, Tb);
  CartesianLine line;
  ASSERT_EQ(CartesianLine::configure(Ta, Tb, 0.0, 1.0, &line, &why), Status::kOk);
  CartesianTrackingController c;
  ASSERT_EQ(CartesianTrackingController::configure(CartesianTrackingConfig{}, model, &c, &why), Status::kOk);
  CartesianTrackingInput in = c.make_input();
  CartesianTrackingOutput out = c.make_output();
  in.q = qa;
  int saturated = 0;
  double min_w = 1e9;
  for (int k = 0; k < 6000; ++k) {
    in.t = in.stamp = k * 1e-3;
    Eigen::Isometry3d T;
    Vector6d a;
    line.sample(in.t, T, in.twist_ref, a);
    in.pose_ref = T.matrix();
    const Status s = c.step(in, out);
    ASSERT_TRUE(ok(s)) << "tick " << k;
    saturated += s == Status::kSaturated;
    ASSERT_TRUE(out.tau.allFinite() && out.q_ref.allFinite());
    ASSERT_TRUE((out.qd_ref.cwiseAbs().array() <= model->velocity_limit().array() + 1e-12).all());
    min_w = std::min(min_w, out.manipulability);
    in.q = out.q_ref;  // an arm that follows its reference exactly
    in.qd = out.qd_ref;
  }
  EXPECT_GT(saturated, 100);       // it could not keep up near the singularity
  EXPECT_LT(min_w, 1e-3);          // and went close to it (damped there)
  EXPECT_LT(out.task_error.norm(), 1e-9);  // then arrived
}

TEST(CartesianTracking, DeterministicAndSafeOnBadInput) {
  const RobotModelPtr model = testing::load_ur5();
  const CartesianLine line = make_line(*model, 0.0, 1.0);
  CartesianTrackingController c1, c2;
  std::string why;
  ASSERT_EQ(CartesianTrackingController::configure(CartesianTrackingConfig{}, model, &c1, &why), Status::kOk);
  ASSERT_EQ(CartesianTrackingController::configure(CartesianTrackingConfig{}, model, &c2, &why), Status::kOk);
  CartesianTrackingInput in = c1.make_input();
  CartesianTrackingOutput o1 = c1.make_output(), o2 = c2.make_output();
  in.q = q_start();
  for (int k = 0; k < 500; ++k) {
    in.t = in.stamp = k * 1e-3;
    Eigen::Isometry3d T;
    Vector6d a;
    line.sample(in.t, T, in.twist_ref, a);
    in.pose_ref = T.matrix();
    in.q += 1e-3 * Eigen::VectorXd::Constant(6, std::sin(k * 0.01));
    c1.step(in, o1);
    c2.step(in, o2);
    ASSERT_EQ(std::memcmp(o1.tau.data(), o2.tau.data(), 6 * sizeof(double)), 0) << "tick " << k;
  }
  // Non-finite reference: the joint reference holds still, torque finite.
  in.pose_ref(0, 3) = NAN;
  EXPECT_EQ(c1.step(in, o1), Status::kNonFiniteReference);
  EXPECT_TRUE(o1.tau.allFinite());
  EXPECT_EQ(o1.qd_ref.norm(), 0.0);
  EXPECT_EQ(o1.qdd_ref.norm(), 0.0);
  // Non-finite and wrong-size measurements: the joint controller's hold fallback.
  in.pose_ref(0, 3) = 0.3;
  in.q[2] = NAN;
  EXPECT_EQ(c1.step(in, o1), Status::kNonFiniteMeasurement);
  EXPECT_TRUE(o1.tau.allFinite());
  in.q = Eigen::VectorXd::Zero(5);
  EXPECT_TRUE(failed(c1.step(in, o1)));
  EXPECT_TRUE(o1.tau.allFinite());
  CartesianTrackingOutput small;
  EXPECT_EQ(c1.step(in, small), Status::kBadSize);
  CartesianTrackingConfig cfg;
  cfg.dt = 0.0;
  EXPECT_EQ(CartesianTrackingController::configure(cfg, model, &c1, &why), Status::kInvalidConfig);
}

TEST(CartesianTracking, NonRigidPoseReferenceHoldsTheJointReference) {
  const RobotModelPtr model = testing::load_ur5();
  const CartesianLine line = make_line(*model, 0.0, 1.0);
  CartesianTrackingController c;
  std::string why;
  ASSERT_EQ(CartesianTrackingController::configure(CartesianTrackingConfig{}, model, &c, &why), Status::kOk);
  CartesianTrackingInput in = c.make_input();
  CartesianTrackingOutput out = c.make_output();
  in.q = q_start();
  Eigen::Isometry3d T;
  Vector6d a;
  for (int k = 0; k < 200; ++k) {  // moving along the line, so qd_ref is not zero
    in.t = in.stamp = k * 1e-3;
    line.sample(in.t, T, in.twist_ref, a);
    in.pose_ref = T.matrix();
    ASSERT_FALSE(failed(c.step(in, out))) << "tick " << k;
  }
  ASSERT_GT(out.qd_ref.norm(), 1e-3);
  const Eigen::Matrix4d good = in.pose_ref;
  Eigen::Matrix4d bottom = good, scaled = good, mirrored = good;
  bottom(3, 0) = 0.2;                         // finite, but not a homogeneous transform
  scaled.topLeftCorner<3, 3>() *= 1.05;        // not orthonormal
  mirrored.col(2).head<3>() *= -1.0;           // orthonormal, det -1
  for (const Eigen::Matrix4d* bad : {&bottom, &scaled, &mirrored}) {
    in.pose_ref = *bad;
    Eigen::VectorXd q_ref_first;
    for (int tick = 0; tick < 2; ++tick) {
      in.t = in.stamp = in.t + 1e-3;
      EXPECT_EQ(c.step(in, out), Status::kNonFiniteReference);
      EXPECT_TRUE(out.tau.allFinite());
      EXPECT_EQ(out.qd_ref.norm(), 0.0);
      EXPECT_EQ(out.qdd_ref.norm(), 0.0);
      EXPECT_EQ(out.task_error.norm(), 0.0);
      if (tick == 0) q_ref_first = out.q_ref;
    }
    EXPECT_EQ(out.q_ref, q_ref_first);  // q_r holds still
  }
  // A valid reference again: tracking resumes.
  in.t = in.stamp = in.t + 1e-3;
  in.pose_ref = good;
  EXPECT_FALSE(failed(c.step(in, out)));
}

}  // namespace
}  // namespace kiloloop
