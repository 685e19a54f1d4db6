// Cartesian impedance and hybrid force/position control on the UR5 (exact dynamics): the spring
// law at rest, force regulation against a stiff wall while tracking along it, the bad-input
// policy, zero allocations and determinism.
#include <algorithm>
#include "test_values.hpp"
#include <cmath>
#include <cstring>
#include <random>

#include <gtest/gtest.h>

#include "alloc_counter.hpp"
#include "arm_sim.hpp"
#include "kiloloop/control/cartesian_impedance.hpp"
#include "kiloloop/control/hybrid_force_position.hpp"
#include "test_models.hpp"

namespace kiloloop {
namespace {


Eigen::VectorXd tool_down_q() {
  return (Eigen::VectorXd(6) << 0.0, -1.2, 1.6, -1.97, -1.57, 0.0).finished();
}

CartesianImpedanceController make_impedance(RobotModelPtr model, CartesianImpedanceConfig cfg = {}) {
  CartesianImpedanceController c;
  std::string why;
  EXPECT_EQ(CartesianImpedanceController::configure(cfg, model, &c, &why), Status::kOk) << why;
  return c;
}

HybridForcePositionController make_hybrid(RobotModelPtr model, HybridForcePositionConfig cfg = {}) {
  HybridForcePositionController c;
  std::string why;
  EXPECT_EQ(HybridForcePositionController::configure(cfg, model, &c, &why), Status::kOk) << why;
  return c;
}

// Reference = the pose at q.
void set_reference_at(const RobotModelPtr& model, const Eigen::VectorXd& q, CartesianControlInput* in) {
  Dynamics dyn;
  std::string why;
  Dynamics::configure(model, {0, 0, -9.81}, &dyn, &why);
  Eigen::Matrix4d T;
  dyn.forward_kinematics(q, T);
  in->p_ref = T.block<3, 1>(0, 3);
  in->R_ref = T.block<3, 3>(0, 0);
}

TEST(CartesianImpedance, ExternalForceDeflectsTheTipByForceOverStiffness) {
  const RobotModelPtr model = testing::load_ur5();
  CartesianImpedanceController c = make_impedance(model);
  testing::ArmSim sim(model, tool_down_q());
  CartesianControlInput in = c.make_input();
  CartesianControlOutput out = c.make_output();
  set_reference_at(model, sim.q, &in);
  Eigen::Matrix<double, 6, 1> f_ext;
  f_ext << 6.0, -4.0, 5.0, 0.0, 0.0, 0.0;  // [N] pushes the tip
  for (int tick = 0; tick < 3000; ++tick) {
    in.t = in.stamp = tick * 1e-3;
    in.q = sim.q;
    in.qd = sim.qd;
    ASSERT_TRUE(ok(c.step(in, out))) << to_string(out.status);
    sim.step(out.tau, 1e-3, 10, f_ext);
  }
  const Eigen::Vector3d dp = sim.pose().block<3, 1>(0, 3) - in.p_ref;
  const Eigen::Vector3d expected = f_ext.head<3>().cwiseQuotient(CartesianImpedanceConfig{}.stiffness.head<3>());
  std::printf("impedance: deflection %.4f %.4f %.4f mm, spring law %.4f %.4f %.4f mm\n", dp.x() * 1e3,
              dp.y() * 1e3, dp.z() * 1e3, expected.x() * 1e3, expected.y() * 1e3, expected.z() * 1e3);
  EXPECT_LT((dp - expected).norm(), 0.02 * expected.norm());
  EXPECT_LT(sim.qd.norm(), 1e-3);  // settled (damped)
}

TEST(CartesianImpedance, StepResponseIsDampedNotOscillating) {
  const RobotModelPtr model = testing::load_ur5();
  CartesianImpedanceController c = make_impedance(model);
  testing::ArmSim sim(model, tool_down_q());
  CartesianControlInput in = c.make_input();
  CartesianControlOutput out = c.make_output();
  set_reference_at(model, sim.q, &in);
  const Eigen::Vector3d p0 = in.p_ref;
  in.p_ref.x() += 0.02;  // a 2 cm step
  double overshoot = 0.0;
  for (int tick = 0; tick < 1500; ++tick) {
    in.t = in.stamp = tick * 1e-3;
    in.q = sim.q;
    in.qd = sim.qd;
    c.step(in, out);
    sim.step(out.tau, 1e-3);
    overshoot = std::max(overshoot, sim.pose()(0, 3) - p0.x() - 0.02);
  }
  EXPECT_NEAR(sim.pose()(0, 3), p0.x() + 0.02, 2e-4);
  EXPECT_LT(overshoot, 0.1 * 0.02) << "critically damped per axis: little overshoot";
}

// A stiff frictionless wall below the tool: z <= z_wall pushes back with k (z_wall - z) - b zdot.
class HybridOnWall : public ::testing::TestWithParam<bool> {};

TEST_P(HybridOnWall, RegulatesContactForceWhileTrackingAlongTheWall) {
  const RobotModelPtr model = testing::load_ur5();
  HybridForcePositionConfig cfg;
  cfg.project_motion_wrench = GetParam();
  HybridForcePositionController c = make_hybrid(model, cfg);
  testing::ArmSim sim(model, tool_down_q());
  CartesianControlInput in = c.make_input();
  CartesianControlOutput out = c.make_output();
  set_reference_at(model, sim.q, &in);
  const double z_wall = in.p_ref.z() - 0.002, k_wall = 2e4, b_wall = 50.0;
  const double x0 = in.p_ref.x();
  in.wrench_ref << 0, 0, -10.0, 0, 0, 0;  // press down with 10 N
  double worst_force = 0.0, worst_x = 0.0;
  Eigen::Matrix<double, 6, 1> f_env = Eigen::Matrix<double, 6, 1>::Zero();
  for (int tick = 0; tick < 3000; ++tick) {
    const double t = tick * 1e-3;
    in.t = in.stamp = t;
    in.q = sim.q;
    in.qd = sim.qd;
    // Slide 5 cm along x between 1 s and 2 s (smooth cosine ramp).
    const double s = std::clamp(t - 1.0, 0.0, 1.0);
    in.p_ref.x() = x0 + 0.05 * 0.5 * (1 - std::cos(M_PI * s));
    in.twist_ref[0] = (s > 0.0 && s < 1.0) ? 0.05 * 0.5 * M_PI * std::sin(M_PI * s) : 0.0;
    in.accel_ref[0] = (s > 0.0 && s < 1.0) ? 0.05 * 0.5 * M_PI * M_PI * std::cos(M_PI * s) : 0.0;
    in.wrench_measured = -f_env;  // the tip applies the opposite of what the wall applies
    ASSERT_TRUE(ok(c.step(in, out))) << to_string(out.status);
    // Wall force over the substeps (stiff: integrate it inside the plant's substeps).
    for (int sub = 0; sub < 10; ++sub) {
      const Eigen::Matrix4d T = sim.pose();
      const double pen = z_wall - T(2, 3);
      f_env.setZero();
      if (pen > 0.0) f_env[2] = std::max(k_wall * pen, 0.0);
      sim.step(out.tau, 1e-4, 1, f_env);
    }
    // Settled before the slide starts; the slide itself must not disturb the force.
    if (t > 0.8) {
      worst_force = std::max(worst_force, std::fabs(f_env[2] - 10.0));
      worst_x = std::max(worst_x, std::fabs(sim.pose()(0, 3) - in.p_ref.x()));
    }
  }
  (void)b_wall;
  std::printf("hybrid (project_motion_wrench %d): worst |F_z - 10 N| %.3f N, worst x error %.3f mm\n",
              int(GetParam()), worst_force, worst_x * 1e3);
  EXPECT_LT(worst_force, 0.5);
  EXPECT_LT(worst_x, 1e-3);
}

INSTANTIATE_TEST_SUITE_P(BothMotionWrenches, HybridOnWall, ::testing::Bool());

template <class Controller>
void expect_cartesian_bad_input_policy(Controller& c, const RobotModelPtr& model) {
  Dynamics dyn;
  std::string why;
  ASSERT_EQ(Dynamics::configure(model, {0, 0, -9.81}, &dyn, &why), Status::kOk);
  CartesianControlInput good = c.make_input();
  good.q = tool_down_q();
  set_reference_at(model, good.q, &good);
  CartesianControlOutput out = c.make_output();
  ASSERT_TRUE(ok(c.step(good, out)));
  Eigen::VectorXd g(6);
  dyn.gravity(good.q, g);
  CartesianControlInput bad = good;
  bad.q[2] = kNaN;
  EXPECT_EQ(c.step(bad, out), Status::kNonFiniteMeasurement);
  EXPECT_LT((out.tau - g).cwiseAbs().maxCoeff(), 1e-12);  // hold: gravity at the last valid q
  bad = good;
  bad.t = 1.0, bad.stamp = 0.5;
  EXPECT_EQ(c.step(bad, out), Status::kStaleMeasurement);
  bad = good;
  bad.qd.resize(4);
  EXPECT_EQ(c.step(bad, out), Status::kBadSize);
  EXPECT_TRUE(out.tau.allFinite());
  bad = good;
  bad.p_ref[0] = kNaN;
  EXPECT_EQ(c.step(bad, out), Status::kNonFiniteReference);
  EXPECT_TRUE(out.tau.allFinite());
  bad = good;
  bad.R_ref(0, 0) = 3.0;  // not a rotation
  EXPECT_EQ(c.step(bad, out), Status::kNonFiniteReference);
  bad = good;
  bad.twist_ref[4] = INFINITY;
  EXPECT_EQ(c.step(bad, out), Status::kNonFiniteReference);
  CartesianControlOutput small;
  small.tau.resize(2);
  EXPECT_EQ(c.step(good, small), Status::kBadSize);
  bad = good;
  bad.p_ref.x() += 5.0;  // far away: the spring asks for more than the motors have
  EXPECT_EQ(c.step(bad, out), Status::kSaturated);
  EXPECT_TRUE(((out.tau.cwiseAbs() - model->effort_limit()).array() <= 0.0).all());
  EXPECT_GT(c.counters().count(Status::kNonFiniteMeasurement), 0u);
  EXPECT_GT(c.counters().count(Status::kNonFiniteReference), 0u);
}

TEST(CartesianControllers, BadInputPolicy) {
  const RobotModelPtr model = testing::load_ur5();
  CartesianImpedanceController imp = make_impedance(model);
  expect_cartesian_bad_input_policy(imp, model);
  HybridForcePositionController hyb = make_hybrid(model);
  expect_cartesian_bad_input_policy(hyb, model);
  // The measured wrench is a measurement: NaN -> hold.
  CartesianControlInput in = hyb.make_input();
  in.q = tool_down_q();
  set_reference_at(model, in.q, &in);
  in.wrench_measured[2] = kNaN;
  CartesianControlOutput out = hyb.make_output();
  EXPECT_EQ(hyb.step(in, out), Status::kNonFiniteMeasurement);
  EXPECT_TRUE(out.tau.allFinite());
}

TEST(CartesianControllers, RejectBadConfigAndUnconfiguredSteps) {
  const RobotModelPtr model = testing::load_ur5();
  std::string why;
  CartesianImpedanceConfig ic;
  ic.stiffness[0] = -1.0;
  CartesianImpedanceController imp;
  EXPECT_EQ(CartesianImpedanceController::configure(ic, model, &imp, &why), Status::kInvalidConfig);
  EXPECT_NE(why.find("stiffness"), std::string::npos);
  CartesianControlOutput out = make_cartesian_output(6);
  EXPECT_EQ(imp.step(make_cartesian_input(6), out), Status::kNotConfigured);
  HybridForcePositionConfig hc;
  hc.selection[2] = 0.5;
  HybridForcePositionController hyb;
  EXPECT_EQ(HybridForcePositionController::configure(hc, model, &hyb, &why), Status::kInvalidConfig);
  EXPECT_NE(why.find("selection"), std::string::npos);
}

TEST(CartesianControllers, StepsAreAllocationFreeAndDeterministic) {
  const RobotModelPtr model = testing::load_ur5();
  CartesianImpedanceController imp = make_impedance(model), imp2 = make_impedance(model);
  HybridForcePositionController hyb = make_hybrid(model), hyb2 = make_hybrid(model);
  CartesianControlInput in = imp.make_input(), nan_in;
  in.q = tool_down_q();
  set_reference_at(model, in.q, &in);
  in.p_ref.x() += 0.01;
  in.wrench_ref[2] = -10.0;
  nan_in = in;
  nan_in.q[0] = kNaN;
  CartesianControlOutput out = imp.make_output(), out2 = imp.make_output();
  imp.step(in, out);
  hyb.step(in, out);
  {
    testing::AllocationScope scope;
    for (int k = 0; k < 10000; ++k) {
      in.t = in.stamp = k * 1e-3;
      in.q[k % 6] += 1e-6;
      imp.step(k % 100 == 0 ? nan_in : in, out);
      hyb.step(k % 100 == 0 ? nan_in : in, out);
    }
    EXPECT_EQ(scope.count(), 0u);
  }
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-0.3, 0.3);
  for (int k = 0; k < 50; ++k) {
    in.t = in.stamp = 20.0 + k * 1e-3;
    for (int j = 0; j < 6; ++j) in.q[j] = tool_down_q()[j] + u(rng), in.qd[j] = u(rng);
    in.wrench_measured[2] = u(rng);
    imp.step(in, out);
    imp2.step(in, out2);
    ASSERT_EQ(std::memcmp(out.tau.data(), out2.tau.data(), 6 * sizeof(double)), 0);
  }
  // The hybrid controller has state (the force integral): two instances fed the same sequence
  // stay bit-identical.
  HybridForcePositionController h1 = make_hybrid(model);
  for (int k = 0; k < 200; ++k) {
    in.t = in.stamp = 30.0 + k * 1e-3;
    for (int j = 0; j < 6; ++j) in.q[j] = tool_down_q()[j] + 0.1 * u(rng), in.qd[j] = u(rng);
    in.wrench_measured[2] = -10.0 + u(rng);
    h1.step(in, out);
    hyb2.step(in, out2);
    ASSERT_EQ(std::memcmp(out.tau.data(), out2.tau.data(), 6 * sizeof(double)), 0) << "tick " << k;
  }
  EXPECT_NE(h1.force_integral()[2], 0.0);
}

}  // namespace
}  // namespace kiloloop
