// QuadrupedController: configure from the URDF, the step contract (no allocation, statuses,
// finite torques) and the safety reflexes. Closed-loop behaviour is tested in SIL (tests/).
#include "kiloloop/quadruped/quadruped_controller.hpp"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "alloc_counter.hpp"
#include "test_models.hpp"

namespace kiloloop {
namespace {

QuadrupedInput standing_input(const QuadrupedController& c) {
  QuadrupedInput in;
  for (int i = 0; i < 4; ++i) in.q.segment<3>(3 * i) = Eigen::Vector3d(0.0, 0.9, -1.8);
  (void)c;
  return in;
}

QuadrupedController make_controller(double actuation_delay = QuadrupedConfig().actuation_delay) {
  QuadrupedController c;
  std::string why;
  QuadrupedConfig config;
  config.body_height = 0.3308;  // the standing pose below: no height error in the first tick
  config.foot_radius = 0.02;
  config.actuation_delay = actuation_delay;
  EXPECT_EQ(QuadrupedController::configure(config, testing::load_quadruped(), &c, &why), Status::kOk)
      << why;
  return c;
}

TEST(QuadrupedController, ConfiguresFromTheUrdf) {
  QuadrupedController c = make_controller();
  EXPECT_EQ(c.joint_names()[0], "FL_hip_abd");
  EXPECT_EQ(c.joint_names()[11], "RR_knee");
  EXPECT_NEAR(c.mass(), 17.6, 1e-9);
  EXPECT_DOUBLE_EQ(c.effort_limit()[2], 45.0);
  QuadrupedConfig bad;
  bad.feet[0] = "nose";
  std::string why;
  EXPECT_FALSE(ok(QuadrupedController::configure(bad, testing::load_quadruped(), &c, &why)));
  EXPECT_NE(why.find("nose"), std::string::npos);
}

// Everything the robot file does not give is derived: the composite inertia equals the sum over
// the links (checked against a hand sum here, against Pinocchio in tests/), the standing pose
// reproduces the height, gains and thresholds scale with the model.
TEST(QuadrupedController, DerivesStandPoseInertiaAndThresholds) {
  QuadrupedController c;
  std::string why;
  QuadrupedConfig config;
  config.foot_radius = 0.02;
  ASSERT_EQ(QuadrupedController::configure(config, testing::load_quadruped(), &c, &why), Status::kOk) << why;
  const QuadrupedConfig& d = c.config();
  EXPECT_GT(d.body_height, 0.2);
  for (int i = 0; i < 4; ++i) {
    const Eigen::Vector3d foot = c.leg(i).foot_position(c.stand_pose().segment<3>(3 * i));
    EXPECT_NEAR(foot.z(), -(d.body_height - d.foot_radius), 1e-9);
    EXPECT_EQ(d.knees[i], KneeDirection::kBackward);
  }
  EXPECT_NEAR(d.contact.force_on, d.contact_force_on * 17.6 * 9.81, 1e-9);
  EXPECT_TRUE((d.swing_kp.array() > 0).all());
  EXPECT_TRUE((d.swing_kd.array() > 0).all());
  // A symmetric robot standing symmetric: the composite inertia is nearly diagonal, roll < pitch.
  EXPECT_LT(c.inertia()(0, 0), c.inertia()(1, 1));
  EXPECT_LT(std::abs(c.inertia()(0, 1)), 1e-6);
}

// The swing joints' damping ratio: swing_damping where the joint predictor is off (10 ms),
// swing_damping_predicted where it is on (35 ms). A negative one is refused.
double swing_damping_ratio(double delay, bool* predicted) {
  QuadrupedController c;
  std::string why;
  QuadrupedConfig config;
  config.foot_radius = 0.02;
  config.actuation_delay = delay;
  EXPECT_EQ(QuadrupedController::configure(config, testing::load_quadruped(), &c, &why), Status::kOk) << why;
  const QuadrupedConfig& d = c.config();
  *predicted = d.predict_swing;
  // kd / kp = 2 zeta / w, w = sqrt(kp / I): the swing frequency where the delay does not cap it
  // (on this model: 50 rad/s at 10 ms, 48 at 35 ms with the predictor, both above 30).
  return d.swing_kd[2] / (2.0 * d.swing_kp[2]) * d.swing_frequency;
}

TEST(QuadrupedController, SwingDampingIsCriticalWhereTheJointPredictorRuns) {
  bool predicted = true;
  EXPECT_NEAR(swing_damping_ratio(0.010, &predicted), QuadrupedConfig().swing_damping, 1e-9);
  EXPECT_FALSE(predicted);
  EXPECT_NEAR(swing_damping_ratio(0.035, &predicted), QuadrupedConfig().swing_damping_predicted, 1e-9);
  EXPECT_TRUE(predicted);
  QuadrupedConfig bad;
  bad.swing_damping_predicted = -1.0;
  std::string why;
  EXPECT_EQ(validate(bad, &why), Status::kInvalidConfig);
  EXPECT_NE(why.find("swing_damping_predicted"), std::string::npos) << why;
}

TEST(QuadrupedController, RefusesSwappedFeetWithAClearReason) {
  QuadrupedController c;
  std::string why;
  QuadrupedConfig config;
  config.feet = {"FR_foot", "FL_foot", "RL_foot", "RR_foot"};
  EXPECT_EQ(QuadrupedController::configure(config, testing::load_quadruped(), &c, &why), Status::kModelError);
  EXPECT_NE(why.find("'FR_foot' is listed as front-left"), std::string::npos) << why;
}

TEST(QuadrupedController, StandingStepSupportsTheWeight) {
  QuadrupedController c = make_controller();
  QuadrupedInput in = standing_input(c);
  QuadrupedOutput out;
  ASSERT_TRUE(ok(c.step(in, out))) << to_string(out.status);
  double fz = 0;
  for (int i = 0; i < 4; ++i) fz += out.foot_force[3 * i + 2];
  EXPECT_GT(fz, 0.8 * 17.6 * 9.81);
  EXPECT_TRUE(out.tau.allFinite());
}

// At the default delay and at 35 ms, where the joint predictor runs (the in-flight joint
// accelerations and the swing legs' H(q) at their landing pose).
TEST(QuadrupedController, TrotStepsAreAllocationFree) {
  for (const double delay : {QuadrupedConfig().actuation_delay, 0.035}) {
    QuadrupedController c = make_controller(delay);
    ASSERT_EQ(c.config().predict_swing, delay > 0.02) << delay;
    QuadrupedInput in = standing_input(c);
    in.gait = Gait::kTrot;
    in.velocity_command << 0.5, 0.0, 0.0;
    QuadrupedOutput out;
    c.step(in, out);
    testing::AllocationScope scope;
    for (int k = 1; k <= 10000; ++k) {
      in.t = in.stamp = k * 0.001;
      in.q[1] = 0.9 + 0.05 * std::sin(0.01 * k);  // keep the legs moving a little
      if (k % 500 == 0) in.gyro[0] = std::numeric_limits<double>::quiet_NaN();
      else in.gyro[0] = 0.0;
      c.step(in, out);
    }
    EXPECT_EQ(scope.count(), 0u) << delay;
  }
}

TEST(QuadrupedController, NonFiniteSensorsHoldTheLastCommand) {
  QuadrupedController c = make_controller();
  QuadrupedInput in = standing_input(c);
  QuadrupedOutput out;
  c.step(in, out);
  const Vector12d last = out.tau;
  in.t = in.stamp = 0.001;
  in.accel[2] = std::numeric_limits<double>::infinity();
  EXPECT_EQ(c.step(in, out), Status::kNonFiniteMeasurement);
  EXPECT_EQ(out.tau, last);
  in.accel[2] = 9.81;
  in.t = 1.0;  // stamp 0.001: a stale measurement
  EXPECT_EQ(c.step(in, out), Status::kStaleMeasurement);
  EXPECT_TRUE(out.tau.allFinite());
  EXPECT_EQ(c.counters().ticks, 3u);
  EXPECT_EQ(c.counters().count(Status::kNonFiniteMeasurement), 1u);
  EXPECT_EQ(c.counters().count(Status::kStaleMeasurement), 1u);
}

// A finite value beyond the sanity bound (control/sane_range.hpp) is a fault like NaN: refused
// with a status and the last command held, and nothing of it reaches the estimate (fuzzing:
// 1e308 in the accelerometer overflowed the wrench, t = 1e308 the gait phase).
TEST(QuadrupedController, InsaneInputsAndGroundTruthAreRefused) {
  QuadrupedController c = make_controller();
  QuadrupedInput in = standing_input(c);
  QuadrupedOutput out;
  c.step(in, out);
  const Vector12d last = out.tau;
  int k = 1;
  auto step_with = [&](auto poke) {
    QuadrupedInput bad = in;
    bad.t = bad.stamp = 0.001 * k++;
    poke(bad);
    const Status s = c.step(bad, out);
    EXPECT_EQ(out.tau, last);
    EXPECT_TRUE(out.position.allFinite() && out.wrench.allFinite());
    return s;
  };
  EXPECT_EQ(step_with([](QuadrupedInput& b) { b.accel.setConstant(1e308); }), Status::kNonFiniteMeasurement);
  EXPECT_EQ(step_with([](QuadrupedInput& b) { b.gyro[1] = -2e6; }), Status::kNonFiniteMeasurement);
  EXPECT_EQ(step_with([](QuadrupedInput& b) { b.q[4] = 1e300; }), Status::kNonFiniteMeasurement);
  EXPECT_EQ(step_with([](QuadrupedInput& b) { b.t = b.stamp = 1e308; }), Status::kNonFiniteMeasurement);
  EXPECT_EQ(step_with([](QuadrupedInput& b) {
              b.use_ground_truth = true;
              b.true_position << 0.0, 0.0, std::numeric_limits<double>::quiet_NaN();
            }),
            Status::kNonFiniteMeasurement);
  EXPECT_EQ(step_with([](QuadrupedInput& b) {
              b.use_ground_truth = true;
              b.true_velocity.setConstant(1e307);
            }),
            Status::kNonFiniteMeasurement);
  // The refused ticks did not count for the order rule: the next good tick is accepted.
  in.t = in.stamp = 0.001 * k;
  EXPECT_FALSE(failed(c.step(in, out)));
  EXPECT_TRUE(out.position.allFinite());
}

// Every setting of the estimator is checked at configure, with the reason.
TEST(QuadrupedController, EstimatorConfigIsValidatedWithAClearReason) {
  EXPECT_EQ(validate(EstimatorConfig{}, nullptr), Status::kOk);
  struct Case { void (*poke)(EstimatorConfig&); const char* word; };
  const Case cases[] = {
      {[](EstimatorConfig& e) { e.dt = 0.0; }, "dt"},
      {[](EstimatorConfig& e) { e.attitude_gain = 1.5; }, "attitude_gain"},
      {[](EstimatorConfig& e) { e.attitude_gain = std::nan(""); }, "attitude_gain"},
      {[](EstimatorConfig& e) { e.accel_noise = 0.0; }, "accel_noise"},
      {[](EstimatorConfig& e) { e.leg_velocity_noise = -1.0; }, "leg_velocity_noise"},
      {[](EstimatorConfig& e) { e.foothold_noise = std::numeric_limits<double>::infinity(); }, "foothold_noise"},
      {[](EstimatorConfig& e) { e.ground_filter = -0.1; }, "ground_filter"},
      {[](EstimatorConfig& e) { e.velocity_gate = -1.0; }, "velocity_gate"},
      {[](EstimatorConfig& e) { e.attitude.gyro_noise_density = 0.0; }, "gyro_noise_density"},
      {[](EstimatorConfig& e) { e.attitude.max_gyro_bias = -1.0; }, "max_gyro_bias"},
      {[](EstimatorConfig& e) { e.attitude.gyro_bias_random_walk = -1.0; }, "gyro_bias_random_walk"},
      {[](EstimatorConfig& e) { e.attitude.gyro_turn_on_bias = std::numeric_limits<double>::quiet_NaN(); }, "gyro_turn_on_bias"},
  };
  for (const Case& k : cases) {
    EstimatorConfig e;
    k.poke(e);
    std::string why;
    EXPECT_EQ(validate(e, &why), Status::kInvalidConfig) << k.word;
    EXPECT_NE(why.find(k.word), std::string::npos) << why;
    // The controller refuses it too, with the same reason.
    QuadrupedConfig config;
    config.estimator = e;
    QuadrupedController c;
    why.clear();
    if (std::string(k.word) != "dt") {  // the controller's dt is the estimator's
      EXPECT_EQ(QuadrupedController::configure(config, testing::load_quadruped(), &c, &why), Status::kInvalidConfig);
      EXPECT_NE(why.find(k.word), std::string::npos) << why;
    }
  }
}

// The AHRS quaternion is an input only with estimator.external_attitude; then it is checked.
TEST(QuadrupedController, QuaternionCountsOnlyWhenAnExternalAhrsIsUsed) {
  QuadrupedController own = make_controller();
  QuadrupedInput in = standing_input(own);
  QuadrupedOutput out;
  in.quat.setConstant(std::numeric_limits<double>::quiet_NaN());
  EXPECT_TRUE(ok(own.step(in, out)));
  QuadrupedController ahrs;
  QuadrupedConfig config;
  config.body_height = 0.3308;
  config.estimator.external_attitude = true;
  std::string why;
  ASSERT_EQ(QuadrupedController::configure(config, testing::load_quadruped(), &ahrs, &why), Status::kOk) << why;
  EXPECT_EQ(ahrs.step(in, out), Status::kNonFiniteMeasurement);
}

// Time going backwards (a stamp older than one already used) is stale: control/rules.hpp's
// order rule; reset() forgets the order.
TEST(QuadrupedController, TimeGoingBackwardsIsStaleUntilReset) {
  QuadrupedController c = make_controller();
  QuadrupedInput in = standing_input(c);
  QuadrupedOutput out;
  in.t = in.stamp = 0.010;
  EXPECT_FALSE(failed(c.step(in, out)));
  in.t = in.stamp = 0.005;
  EXPECT_EQ(c.step(in, out), Status::kStaleMeasurement);
  EXPECT_TRUE(out.tau.allFinite());
  c.reset();
  EXPECT_FALSE(failed(c.step(in, out)));
}

TEST(QuadrupedController, TiltBeyondTheLimitTripsTheSafeStopInTheSameTick) {
  QuadrupedController c = make_controller();
  QuadrupedInput in = standing_input(c);
  QuadrupedOutput out;
  c.step(in, out);
  // Roll 20 deg: the first tick's attitude comes from the accelerometer's gravity direction.
  const double a = 20.0 * M_PI / 180.0;
  QuadrupedController fresh = make_controller();
  in.accel << 0.0, 9.81 * std::sin(a), 9.81 * std::cos(a);
  EXPECT_EQ(fresh.step(in, out), Status::kSafeStop);
  EXPECT_TRUE(out.safe_stop);
  EXPECT_TRUE(out.tau.allFinite());
  // Latched: level again (the attitude filter, just started, averages the gravity directions it
  // has seen: 20 deg -> about 0.1 deg in 0.3 s), still stopped until reset.
  in.accel << 0.0, 0.0, 9.81;
  for (int k = 1; k <= 300; ++k) {
    in.t = in.stamp = k * 0.001;
    EXPECT_EQ(fresh.step(in, out), Status::kSafeStop);
  }
  EXPECT_LT(out.tilt, QuadrupedConfig{}.max_tilt);
  fresh.reset();
  in.t = in.stamp = 0.301;
  EXPECT_NE(fresh.step(in, out), Status::kSafeStop);
}

}  // namespace
}  // namespace kiloloop
