// The composed aerial controller: hover equilibrium, what the reaction feed-forward adds, the
// safety policy (tilt, NaN/Inf, stale, sizes), determinism and zero allocations per step.
#include <cmath>
#include "test_values.hpp"
#include <cstdio>
#include <cstring>
#include <random>

#include <gtest/gtest.h>

#include "aerial_model.hpp"
#include "alloc_counter.hpp"
#include "kiloloop/aerial/aerial_controller.hpp"

namespace kiloloop {
namespace {


AerialController make(const AerialConfig& config = {}) {
  AerialController c;
  std::string why;
  EXPECT_EQ(AerialController::configure(config, testing::load_aerial(), &c, &why), Status::kOk)
      << why;
  return c;
}

AerialInput hover_input(const AerialController& c) {
  AerialInput in = c.make_input();
  in.position << 0.0, 0.0, 1.0;
  in.position_ref = in.position;
  return in;
}

TEST(AerialController, ModelMassesSurviveUrdfLoading) {
  AerialController c = make();
  EXPECT_NEAR(c.body_mass(), 1.5, 1e-12);
  EXPECT_NEAR(c.total_mass(), 1.8, 1e-12);
  EXPECT_NEAR(c.body_inertia()(0, 0), 0.015, 1e-12);
  EXPECT_NEAR(c.body_inertia()(2, 2), 0.027, 1e-12);
  // The hanging arm adds inertia about x and y (parallel axis), little about z.
  EXPECT_GT(c.rigid_inertia()(0, 0), 0.015 + 0.01);
}

TEST(AerialController, HoverEquilibriumSharesTheWeight) {
  for (bool ff : {true, false}) {
    AerialConfig config;
    config.reaction_feedforward = ff;
    AerialController c = make(config);
    AerialInput in = hover_input(c);
    AerialOutput out = c.make_output();
    ASSERT_EQ(c.step(in, out), Status::kOk);
    for (int i = 0; i < 4; ++i) EXPECT_NEAR(out.thrust[i], 1.8 * 9.81 / 4, 1e-9) << "ff " << ff;
    EXPECT_LT(out.tau.norm(), 1e-9);
    EXPECT_LT(out.wrench.tail<3>().norm(), 1e-9);
  }
}

TEST(AerialController, FeedForwardCancelsAStaticArmOffset) {
  // Arm held out to the side: the reaction carries its weight torque, so the commanded body
  // torque (before any attitude error) already balances it; without it the torque is zero.
  AerialConfig on, off;
  on.hold_com = false;  // the body stays the position loop's target: no attitude command
  off.reaction_feedforward = false;
  off.hold_com = false;
  AerialController a = make(on), b = make(off);
  AerialInput in = hover_input(a);
  in.q << 0.0, 1.0, 0.0;
  in.q_ref = in.q;
  AerialOutput oa = a.make_output(), ob = b.make_output();
  a.step(in, oa);
  b.step(in, ob);
  // Positive shoulder swings the arm towards -x: its CoM at x_com < 0 pulls the body's torque
  // about y by x_com m g, so the body holds the arm with -x_com m g (body -> arm, about y).
  const double x_com = -(0.15 * 0.09 + 0.08 * 0.255 + 0.02 * 0.33) * std::sin(1.0) / 0.30;
  EXPECT_NEAR(oa.reaction[4], -0.30 * 9.81 * x_com, 1e-9);
  EXPECT_NEAR(oa.reaction[2], 0.30 * 9.81, 1e-9);
  EXPECT_NEAR(oa.wrench[2], oa.reaction[4], 1e-9);
  EXPECT_LT(std::abs(ob.wrench[2]), 1e-9);
  // The arm's own gravity torque is compensated in both (computed torque with the body's motion).
  EXPECT_GT(std::abs(oa.tau[1]), 0.1);
  EXPECT_NEAR(oa.tau[1], ob.tau[1], 1e-12);
}

TEST(AerialController, HoldComLetsTheBodyGiveWayToTheArm) {
  // Arm raised towards -x at the reference: holding the CoM puts the body's target towards +x
  // by m_arm x_com / m_total; holding the body origin leaves it where it is.
  AerialConfig com, origin;
  origin.hold_com = false;
  AerialController a = make(com), b = make(origin);
  AerialInput in = hover_input(a);
  in.q << 0.0, M_PI / 2, 0.0;
  in.q_ref = in.q;
  AerialOutput oa = a.make_output(), ob = b.make_output();
  a.step(in, oa);
  b.step(in, ob);
  const double shift = (0.15 * 0.09 + 0.08 * 0.255 + 0.02 * 0.33) / 1.8;  // [m] towards +x
  // kp_x * shift plus the first tick of the integral, ki_x * dt * shift.
  EXPECT_NEAR(oa.acceleration_des.x(), (16.0 + 4.0 * 0.001) * shift, 1e-9);
  EXPECT_NEAR(ob.acceleration_des.x(), 0.0, 1e-12);
}

TEST(AerialController, TiltBeyondLimitStopsMotorsAndLatches) {
  AerialController c = make();
  AerialInput in = hover_input(c);
  AerialOutput out = c.make_output();
  const double a = 65.0 * M_PI / 180.0;
  in.quat << std::cos(a / 2), std::sin(a / 2), 0.0, 0.0;
  EXPECT_EQ(c.step(in, out), Status::kSafeStop);
  EXPECT_TRUE(out.safe_stop);
  EXPECT_EQ(out.thrust, Eigen::VectorXd::Zero(4));
  in.quat << 1, 0, 0, 0;
  EXPECT_EQ(c.step(in, out), Status::kSafeStop);  // latched
  c.reset();
  EXPECT_EQ(c.step(in, out), Status::kOk);
}

TEST(AerialController, BadMeasurementsGiveTheFailsafe) {
  AerialController c = make();
  AerialOutput out = c.make_output();
  const double failsafe = 0.9 * 1.8 * 9.81 / 4;
  auto check = [&](AerialInput in, Status expected) {
    EXPECT_EQ(c.step(in, out), expected);
    EXPECT_TRUE(out.thrust.allFinite() && out.tau.allFinite());
    for (int i = 0; i < 4; ++i) EXPECT_NEAR(out.thrust[i], failsafe, 1e-12);
    EXPECT_EQ(out.tau.norm(), 0.0);
  };
  AerialInput in = hover_input(c);
  in.gyro.x() = kNaN;
  check(in, Status::kNonFiniteMeasurement);
  in = hover_input(c);
  in.q[2] = INFINITY;
  check(in, Status::kNonFiniteMeasurement);
  in = hover_input(c);
  in.quat.setZero();
  check(in, Status::kNonFiniteMeasurement);
  in = hover_input(c);
  in.t = 1.0;
  in.stamp = 0.9;
  check(in, Status::kStaleMeasurement);
  in = hover_input(c);
  in.qd.resize(2);
  check(in, Status::kBadSize);
}

// The shared measurement rule (control/rules.hpp): a stamp older than one already used is stale,
// every step is counted by its status, and reset() forgets the order.
TEST(AerialController, TimeGoingBackwardsIsStaleCountedAndForgottenByReset) {
  AerialController c = make();
  AerialOutput out = c.make_output();
  AerialInput in = hover_input(c);
  in.t = in.stamp = 0.010;
  EXPECT_EQ(c.step(in, out), Status::kOk);
  in.t = in.stamp = 0.005;
  EXPECT_EQ(c.step(in, out), Status::kStaleMeasurement);
  EXPECT_EQ(c.counters().ticks, 2u);
  EXPECT_EQ(c.counters().count(Status::kOk), 1u);
  EXPECT_EQ(c.counters().count(Status::kStaleMeasurement), 1u);
  c.reset();
  EXPECT_EQ(c.step(in, out), Status::kOk);
  EXPECT_EQ(c.counters().ticks, 3u);  // kept by reset()
}

TEST(AerialController, BadReferenceHoldsTheLastValidOne) {
  AerialController c = make();
  AerialInput in = hover_input(c);
  AerialOutput out = c.make_output(), ref_out = c.make_output();
  c.step(in, ref_out);
  AerialInput bad = in;
  bad.position_ref.x() = kNaN;
  AerialController d = make();
  d.step(in, out);
  EXPECT_EQ(d.step(bad, out), Status::kNonFiniteReference);
  c.step(in, ref_out);
  EXPECT_EQ(std::memcmp(out.thrust.data(), ref_out.thrust.data(), sizeof(double) * 4), 0);
  bad = in;
  bad.q_ref.resize(1);
  EXPECT_EQ(d.step(bad, out), Status::kBadSize);
  EXPECT_TRUE(out.thrust.allFinite());
}

TEST(AerialController, TiltBeyondTheLimitStopsTheMotorsEvenWithAnotherBadSignal) {
  // Upside down with a NaN gyro: the tilt still trips the latched motor stop (not the
  // hover-thrust failsafe of a bad measurement).
  AerialController c = make();
  AerialInput in = hover_input(c);
  AerialOutput out = c.make_output();
  in.quat << 0.0, 1.0, 0.0, 0.0;
  in.gyro.x() = kNaN;
  EXPECT_EQ(c.step(in, out), Status::kSafeStop);
  EXPECT_EQ(out.thrust.norm(), 0.0);
  EXPECT_EQ(c.step(hover_input(c), out), Status::kSafeStop);  // latched
}

TEST(AerialController, EndEffectorModeReachesATargetBelow) {
  AerialController c = make();
  AerialInput in = hover_input(c);
  in.arm_mode = ArmMode::kEndEffector;
  in.ee_position_ref << 0.15, 0.05, 0.70;  // body at z = 1: 0.30 m below, ahead, left
  AerialOutput out = c.make_output();
  for (int k = 0; k < 20; ++k) EXPECT_GE(static_cast<int>(c.step(in, out)), 0);
  // Put the arm at the solution: the FK of the measured joints meets the target.
  in.q = out.q_ref;
  c.step(in, out);
  EXPECT_LT((out.ee_position - in.ee_position_ref).norm(), 1e-6);
}

TEST(AerialController, SameInputsGiveBitIdenticalOutputs) {
  AerialController a = make(), b = make();
  AerialInput in = hover_input(a);
  in.q << 0.2, -0.4, 0.6;
  in.qd << 0.1, 0.2, -0.3;
  in.gyro << 0.01, -0.02, 0.03;
  in.position_ref.x() += 0.1;
  AerialOutput oa = a.make_output(), ob = b.make_output();
  for (int k = 0; k < 100; ++k) {
    in.t = in.stamp = 0.001 * k;
    a.step(in, oa);
    b.step(in, ob);
    ASSERT_EQ(std::memcmp(oa.thrust.data(), ob.thrust.data(), sizeof(double) * 4), 0);
    ASSERT_EQ(std::memcmp(oa.tau.data(), ob.tau.data(), sizeof(double) * 3), 0);
  }
}

TEST(AerialController, StepIsAllocationFreeInEveryMode) {
  AerialConfig config;
  config.attitude.gains.ki << 50, 50, 10;
  config.rotors.lag_compensation = true;
  config.arm_coulomb = Eigen::VectorXd::Constant(1, 0.01);
  config.arm_viscous = Eigen::VectorXd::Constant(1, 0.01);
  config.reaction_lead = 0.03;
  // Every branch: with and without the reaction feed-forward and the CoM hold.
  for (const bool ff : {true, false}) {
    for (const bool hold : {true, false}) {
      config.reaction_feedforward = ff;
      config.hold_com = hold;
      AerialController c = make(config);
      AerialInput in = hover_input(c), nan_in = in, ee_in = in, att_in = in;
      nan_in.gyro.x() = kNaN;
      ee_in.arm_mode = ArmMode::kEndEffector;
      ee_in.ee_position_ref << 0.1, 0.0, 0.65;
      att_in.flight_mode = FlightMode::kAttitude;
      att_in.quat_ref << std::cos(0.087), std::sin(0.087), 0.0, 0.0;
      AerialOutput out = c.make_output();
      c.step(in, out);
      c.step(ee_in, out);
      testing::AllocationScope scope;
      for (int k = 0; k < 10000; ++k) {
        AerialInput& x = k % 100 == 0 ? nan_in : (k % 3 == 0 ? ee_in : (k % 3 == 1 ? att_in : in));
        x.t = x.stamp = 0.001 * k;
        x.q[k % 3] = 1e-3 * (k % 17);
        c.step(x, out);
      }
      EXPECT_EQ(scope.count(), 0u) << "feed-forward " << ff << ", hold_com " << hold;
    }
  }
}

TEST(AerialController, FrictionCompensationPushesPastBreakawayOutsideTheDeadband) {
  AerialConfig plain, comp;
  comp.arm_coulomb = Eigen::VectorXd::Constant(1, 0.01);
  AerialController a = make(plain), b = make(comp);
  AerialInput in = hover_input(a);
  AerialOutput oa = a.make_output(), ob = b.make_output();
  in.q_ref << 0.05, 0.0, 0.002;  // yaw well outside the deadband, elbow inside it
  a.step(in, oa);
  b.step(in, ob);
  // tanh(10 * 0.045 / 0.05) = tanh(9): the full Coulomb torque towards the target.
  EXPECT_NEAR(ob.tau[0] - oa.tau[0], 0.01 * std::tanh(9.0), 1e-9);
  EXPECT_NEAR(ob.tau[2] - oa.tau[2], 0.0, 1e-15);
}

TEST(AerialController, ReactionLeadAddsTheRateOfTheFedForwardTorque) {
  AerialConfig lead;
  lead.reaction_lead = 0.03;
  lead.reaction_lead_filter = 0.0;  // the raw one-tick rate
  AerialController a = make(), b = make(lead);
  AerialInput in = hover_input(a);
  AerialOutput oa = a.make_output(), ob = b.make_output();
  in.q << 0.0, 0.5, 0.0;
  in.q_ref = in.q;
  a.step(in, oa);
  b.step(in, ob);
  const double first = ob.reaction[4];
  in.q[1] = 0.51;
  in.q_ref = in.q;
  a.step(in, oa);
  b.step(in, ob);
  const double rate = (ob.reaction[4] - first) / 0.001;
  EXPECT_GT(std::abs(rate), 0.1);
  EXPECT_NEAR(ob.wrench[2] - oa.wrench[2], 0.03 * rate, 1e-9);
}

TEST(AerialController, RejectsBadConfigWithAReason) {
  AerialConfig config;
  config.arm_kp = Eigen::VectorXd::Ones(2);
  AerialController c;
  std::string why;
  EXPECT_EQ(AerialController::configure(config, testing::load_aerial(), &c, &why),
            Status::kInvalidConfig);
  EXPECT_NE(why.find("arm_kp"), std::string::npos);
  config = AerialConfig{};
  config.rotors.thrust_max = Eigen::VectorXd::Constant(1, 4.0);  // 16 N < 17.7 N weight
  EXPECT_EQ(AerialController::configure(config, testing::load_aerial(), &c, &why),
            Status::kInvalidConfig);
  EXPECT_NE(why.find("lift"), std::string::npos);
}

// --- any multirotor: n rotors, body CoM off its origin, arm of 0..n joints ----------------------

AerialController make_multirotor(int joints, const Eigen::Vector3d& com, int rotors,
                                 double tilt = 0.0, bool ff = true) {
  AerialConfig config;
  config.rotors = testing::ring_rotors(rotors, 0.3, tilt);
  config.reaction_feedforward = ff;
  AerialController c;
  std::string why;
  EXPECT_EQ(AerialController::configure(config, testing::load_multirotor(joints, com), &c, &why),
            Status::kOk)
      << why;
  return c;
}

TEST(AerialController, HoldsTheWeightAboutTheVehicleCoMForAnyLayout) {
  // Hovering level and at rest, the rotors' wrench about the body CoM must carry the weight and
  // cancel the moment of the weight acting at the vehicle CoM: (c_v - c_b) x m g z.
  const Eigen::Vector3d com(0.03, -0.02, 0.01);
  for (int joints : {0, 2, 3, 6}) {
    for (int rotors : {4, 6, 8}) {
      for (bool ff : {true, false}) {
        AerialController c = make_multirotor(joints, com, rotors, 0.0, ff);
        EXPECT_EQ(c.has_arm(), joints > 0);
        EXPECT_EQ(c.nq(), joints);
        EXPECT_LT((c.body_com() - com).norm(), 1e-12);
        const double m = 1.2 + 0.1 * joints + (joints ? 0.02 : 0.0);
        EXPECT_NEAR(c.total_mass(), m, 1e-12);
        AerialInput in = hover_input(c);
        AerialOutput out = c.make_output();
        ASSERT_EQ(out.thrust.size(), rotors);
        ASSERT_EQ(c.step(in, out), Status::kOk);
        const Eigen::Vector3d need =
            (c.vehicle_com() - c.body_com()).cross(Eigen::Vector3d(0, 0, m * 9.81));
        EXPECT_NEAR(out.wrench_achieved[0], m * 9.81, 1e-9) << joints << " " << rotors;
        EXPECT_LT((out.wrench_achieved.tail<3>() - need).norm(), 1e-9)
            << joints << " arm joints, " << rotors << " rotors, ff " << ff << ": "
            << out.wrench_achieved.tail<3>().transpose() << " vs " << need.transpose();
        EXPECT_TRUE(out.tau.allFinite());
      }
    }
  }
}

TEST(AerialController, TiltedHexarotorKeepsTheLateralForceAtZero) {
  AerialController c = make_multirotor(2, Eigen::Vector3d(0.0, 0.0, 0.02), 6, 0.35);
  EXPECT_TRUE(c.allocation().uses_lateral_rows());
  AerialInput in = hover_input(c);
  in.gyro << 0.2, -0.1, 0.3;
  in.position_ref.x() += 0.2;
  AerialOutput out = c.make_output();
  EXPECT_GE(static_cast<int>(c.step(in, out)), 0);
  EXPECT_LT((c.allocation().effectiveness().topRows<2>() * out.thrust).norm(), 1e-9);
}

TEST(AerialController, ArmTorquesAreNeverNaN) {
  // Issue 12's fuzzing: NaN arm torques with BAD_SIZE or NON_FINITE_REFERENCE. Outputs start
  // full of NaN; references are NaN, Inf, 1e308, wrong sizes; the state is fine.
  AerialController c = make_multirotor(2, Eigen::Vector3d(0.03, 0.0, 0.0), 6);
  const double bad[] = {kNaN, INFINITY, -INFINITY, 1e308, -1e308, 4.9e-324};
  std::mt19937 rng(12);
  std::printf("seed 12\n");
  for (int k = 0; k < 2000; ++k) {
    AerialInput in = hover_input(c);
    in.t = in.stamp = 0.001 * k;
    AerialOutput out = c.make_output();
    out.thrust.setConstant(kNaN);
    out.tau.setConstant(kNaN);
    const double x = bad[rng() % 6];
    switch (rng() % 8) {
      case 0: in.q_ref[rng() % 2] = x; break;
      case 1: in.qd_ref[rng() % 2] = x; break;
      case 2: in.qdd_ref[rng() % 2] = x; break;
      case 3: in.position_ref[rng() % 3] = x; break;
      case 4: in.acceleration_ref[rng() % 3] = x; break;
      case 5: in.q_ref.resize(1); break;
      case 6: out.tau.resize(3); out.tau.setConstant(kNaN); break;
      default: in.q[rng() % 2] = x; break;
    }
    const Status s = c.step(in, out);
    EXPECT_TRUE(out.tau.allFinite()) << k << " status " << to_string(s);
    EXPECT_TRUE(out.thrust.allFinite()) << k;
    if (out.thrust.size() == 6) {
      EXPECT_TRUE((out.thrust.array() <= 8.0).all());
    }
    if (out.tau.size() == 2) {
      EXPECT_TRUE((out.tau.cwiseAbs().array() <= 2.0).all());
    }
  }
}

TEST(AerialController, StepIsAllocationFreeForEveryRotorCount) {
  for (int rotors : {4, 6, 8}) {
    for (int joints : {0, 2}) {
      AerialController c = make_multirotor(joints, Eigen::Vector3d(0.02, 0.0, 0.0), rotors,
                                           rotors == 6 ? 0.35 : 0.0);
      AerialInput in = hover_input(c), att = in;
      att.flight_mode = FlightMode::kAttitude;
      att.quat_ref << std::cos(0.1), std::sin(0.1), 0.0, 0.0;
      AerialOutput out = c.make_output();
      c.step(in, out);
      testing::AllocationScope scope;
      for (int k = 0; k < 3000; ++k) {
        AerialInput& x = k % 2 ? att : in;
        x.t = x.stamp = 0.001 * k;
        if (joints) x.q_ref[k % 2] = 1e-3 * (k % 13);
        x.position_ref.x() = 1e-3 * (k % 29);
        c.step(x, out);
      }
      EXPECT_EQ(scope.count(), 0u) << rotors << " rotors, " << joints << " joints";
    }
  }
}

}  // namespace
}  // namespace kiloloop
