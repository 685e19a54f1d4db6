// ArmSupervisor and SingularityMonitor on the UR5 (exact dynamics): e-stop -> controlled stop
// within the planned time and distance, then hold; each limit trips; I^2 t trips on sustained but
// not on brief overload; the singularity warning comes before the singular configuration;
// bad inputs, zero allocations.
#include <cmath>
#include <cstring>

#include <gtest/gtest.h>

#include "alloc_counter.hpp"
#include "arm_sim.hpp"
#include "kiloloop/safety/arm_supervisor.hpp"
#include "test_models.hpp"

namespace kiloloop {
namespace {


ArmSupervisor make_supervisor(RobotModelPtr model, ArmSupervisorConfig cfg = {}) {
  ArmSupervisor s;
  std::string why;
  EXPECT_EQ(ArmSupervisor::configure(cfg, model, &s, &why), Status::kOk) << why;
  return s;
}

// A computed-torque velocity servo toward qd_cmd (error rate 10 1/s): the "arm controller" here.
Eigen::VectorXd velocity_servo(Dynamics& dyn, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                               const Eigen::VectorXd& qd_cmd) {
  Eigen::VectorXd tau(6);
  dyn.inverse_dynamics(q, qd, 10.0 * (qd_cmd - qd), tau);
  return tau;
}

TEST(ArmSupervisor, EstopStopsWithinPlannedTimeAndDistanceThenHolds) {
  const RobotModelPtr model = testing::load_ur5();
  ArmSupervisorConfig cfg;
  cfg.stop_deceleration = Eigen::VectorXd::Constant(1, 4.0);
  ArmSupervisor sup = make_supervisor(model, cfg);
  Dynamics dyn;
  std::string why;
  Dynamics::configure(model, {0, 0, -9.81}, &dyn, &why);
  testing::ArmSim sim(model, testing::ur5_home());
  SupervisorInput in = sup.make_input();
  SupervisorOutput out = sup.make_output();
  const Eigen::VectorXd qd_cmd = (Eigen::VectorXd(6) << 1.0, -0.6, 0.8, 0.5, -1.0, 1.2).finished();
  Eigen::VectorXd q_at_estop, qd_at_estop;
  double t_estop = 0.6, t_stopped = -1.0, planned = 0.0;
  double worst_hold_drift = 0.0;
  Eigen::VectorXd q_stopped;
  for (int tick = 0; tick < 2600; ++tick) {
    const double t = tick * 1e-3;
    in.t = in.stamp = t;
    in.q = sim.q;
    in.qd = sim.qd;
    in.tau_command = velocity_servo(dyn, sim.q, sim.qd, qd_cmd);
    in.estop = t >= t_estop;
    const Status s = sup.step(in, out);
    if (t < t_estop) {
      ASSERT_EQ(out.mode, SupervisorMode::kNormal) << to_string(s) << " t " << t;
    }
    if (tick == static_cast<int>(t_estop * 1000)) {
      q_at_estop = sim.q;
      qd_at_estop = sim.qd;
      planned = out.stop_time;
      EXPECT_EQ(s, Status::kEmergencyStop);
    }
    if (t > t_estop && t_stopped < 0.0 && sim.qd.cwiseAbs().maxCoeff() < 0.01) {
      t_stopped = t;
      q_stopped = sim.q;
    }
    if (t_stopped > 0.0) worst_hold_drift = std::max(worst_hold_drift, (sim.q - q_stopped).cwiseAbs().maxCoeff());
    sim.step(out.tau, 1e-3);
  }
  ASSERT_GT(t_stopped, 0.0) << "never stopped";
  const double stop_time = t_stopped - t_estop;
  // Planned: max |qd| / a_stop; distance per joint qd^2 / (2 a_stop).
  EXPECT_NEAR(planned, qd_at_estop.cwiseAbs().maxCoeff() / 4.0, 1e-12);
  EXPECT_LT(stop_time, planned + 0.05);
  const Eigen::VectorXd dist = (q_stopped - q_at_estop).cwiseAbs();
  const Eigen::VectorXd bound = qd_at_estop.cwiseAbs2() / (2.0 * 4.0);
  std::printf("e-stop: planned %.3f s, stopped after %.3f s, max distance %.4f rad (bound %.4f), hold drift %.2e rad\n",
              planned, stop_time, dist.maxCoeff(), bound.maxCoeff(), worst_hold_drift);
  EXPECT_TRUE((dist.array() <= bound.array() + 0.01).all());
  EXPECT_LT(worst_hold_drift, 0.01);
  EXPECT_EQ(out.mode, SupervisorMode::kHolding);
  EXPECT_EQ(sup.counters().estops, 1u);
  // Reset is refused while the e-stop is pressed, accepted after release.
  in.reset = true;
  sup.step(in, out);
  EXPECT_EQ(out.mode, SupervisorMode::kHolding);
  in.estop = false;
  in.t = in.stamp = in.t + 1e-3;
  in.tau_command.setZero();
  sup.step(in, out);
  EXPECT_EQ(out.mode, SupervisorMode::kNormal);
  EXPECT_EQ(sup.counters().resets, 1u);
}

// Drives the supervisor with a synthetic measured trajectory q(t), qd(t) and command tau.
template <class Fn>
Status run_synthetic(ArmSupervisor& sup, int ticks, Fn&& fill) {
  SupervisorInput in = sup.make_input();
  SupervisorOutput out = sup.make_output();
  for (int k = 0; k < ticks && out.mode == SupervisorMode::kNormal; ++k) {
    in.t = in.stamp = k * 1e-3;
    fill(in.t, in);
    sup.step(in, out);
  }
  return out.trip;
}

TEST(ArmSupervisor, EachLimitTrips) {
  const RobotModelPtr model = testing::load_ur5();
  {  // velocity
    ArmSupervisor sup = make_supervisor(model);
    EXPECT_EQ(run_synthetic(sup, 100, [](double, SupervisorInput& in) {
                in.q = testing::ur5_home();
                in.qd.setZero();
                in.qd[1] = 3.5;  // > 3.15 rad/s
              }), Status::kLimitViolation);
    EXPECT_EQ(sup.counters().velocity_trips, 1u);
  }
  {  // position: trips while approaching, before the limit, as soon as braking needs the room
    ArmSupervisorConfig cfg;
    cfg.upper = model->upper();
    cfg.upper[0] = 1.0;
    ArmSupervisor sup = make_supervisor(model, cfg);
    double q_trip = 0.0;
    run_synthetic(sup, 2000, [&](double t, SupervisorInput& in) {
      in.q = testing::ur5_home();
      in.qd.setZero();
      in.q[0] = 0.5 * t;  // toward 1.0 at 0.5 rad/s; braking distance 0.25^2/8 = 0.031 rad
      in.qd[0] = 0.5;
      q_trip = in.q[0];
    });
    EXPECT_EQ(sup.counters().position_trips, 1u);
    EXPECT_LT(q_trip, 1.0);
    EXPECT_GT(q_trip + 0.5 * 0.5 / 8.0, 1.0 - 1e-3);
  }
  {  // acceleration
    ArmSupervisor sup = make_supervisor(model);
    EXPECT_EQ(run_synthetic(sup, 200, [](double t, SupervisorInput& in) {
                in.q = testing::ur5_home();
                in.qd.setZero();
                in.qd[2] = 30.0 * t;  // 30 rad/s^2 > 20
              }), Status::kLimitViolation);
    EXPECT_EQ(sup.counters().acceleration_trips, 1u);
  }
  {  // a NaN command from the controller stops the arm
    ArmSupervisor sup = make_supervisor(model);
    EXPECT_EQ(run_synthetic(sup, 10, [](double, SupervisorInput& in) {
                in.q = testing::ur5_home();
                in.tau_command[3] = std::nan("");
              }), Status::kNonFiniteReference);
  }
}

TEST(ArmSupervisor, SustainedOverloadTripsBriefOverloadDoesNot) {
  const RobotModelPtr model = testing::load_ur5();
  ArmSupervisorConfig cfg;  // rated = 0.5 effort, T = 2 s
  {  // 100 ms at the full effort limit (4x the rated I^2): clipped, no trip
    ArmSupervisor sup = make_supervisor(model, cfg);
    EXPECT_EQ(run_synthetic(sup, 1000, [](double t, SupervisorInput& in) {
                in.q = testing::ur5_home();
                in.tau_command.setZero();
                if (t < 0.1) in.tau_command[1] = 200.0;  // above 150: clipped
              }), Status::kOk);
    EXPECT_GT(sup.counters().clipped, 0u);
    EXPECT_GT(sup.counters().count(Status::kSaturated), 0u);
  }
  {  // a command beyond 1.5x the effort limit trips at once
    ArmSupervisor sup = make_supervisor(model, cfg);
    double t_trip = -1.0;
    EXPECT_EQ(run_synthetic(sup, 100, [&](double t, SupervisorInput& in) {
                in.q = testing::ur5_home();
                in.tau_command.setZero();
                if (t >= 0.05) in.tau_command[4] = -50.0;  // wrist: 28 N m effort
                t_trip = t;
              }), Status::kTorqueOverload);
    EXPECT_NEAR(t_trip, 0.05, 1e-9);
    EXPECT_EQ(sup.counters().overload_trips, 1u);
  }
  {  // 0.8 effort held: theta -> 2.56, crosses 1 at t = -T ln(1 - 1/2.56) = 0.99 s
    ArmSupervisor sup = make_supervisor(model, cfg);
    double t_trip = 0.0;
    EXPECT_EQ(run_synthetic(sup, 3000, [&](double t, SupervisorInput& in) {
                in.q = testing::ur5_home();
                in.tau_command.setZero();
                in.tau_command[1] = 120.0;
                t_trip = t;
              }), Status::kTorqueOverload);
    EXPECT_NEAR(t_trip, -2.0 * std::log(1.0 - 1.0 / 2.56), 0.01);
  }
}

TEST(SingularityMonitor, WarnsBeforeTheElbowStraightens) {
  const RobotModelPtr model = testing::load_ur5();
  ArmSupervisor sup = make_supervisor(model);
  SupervisorInput in = sup.make_input();
  SupervisorOutput out = sup.make_output();
  // The elbow opens from 1.6 rad to 0 (arm straight: singular) at 0.8 rad/s.
  double q_warn = NAN, w_at_warn = NAN, w_singular = NAN;
  for (int k = 0; k <= 2000; ++k) {
    const double t = k * 1e-3;
    in.t = in.stamp = t;
    in.q = testing::ur5_home();
    in.q[2] = 1.6 - 0.8 * t;
    in.qd.setZero();
    in.qd[2] = -0.8;
    in.tau_command.setZero();
    sup.step(in, out);
    if (std::isnan(q_warn) && out.singularity.warning) q_warn = in.q[2], w_at_warn = out.singularity.manipulability;
    if (k == 2000) w_singular = out.singularity.manipulability;
  }
  std::printf("singularity: warning at elbow %.3f rad (w = %.4f); w at the singularity %.2e\n", q_warn,
              w_at_warn, w_singular);
  ASSERT_FALSE(std::isnan(q_warn));
  EXPECT_GT(q_warn, 0.15) << "must warn well before the elbow is straight";
  EXPECT_LT(w_singular, 1e-6);
  EXPECT_GT(sup.counters().singularity_warnings, 0u);
  // At the default home pose: no warning.
  SingularityMonitor mon;
  mon.configure({});
  Dynamics dyn;
  std::string why;
  Dynamics::configure(model, {0, 0, -9.81}, &dyn, &why);
  Eigen::MatrixXd J(6, 6);
  dyn.jacobian(testing::ur5_home(), J);
  SingularityState st;
  EXPECT_EQ(mon.update(J, 0.0, &st), Status::kOk);
  EXPECT_GT(st.manipulability, 0.005);
}

// The rate test looks ahead: moving toward the singularity, it warns earlier than the
// manipulability threshold alone, by about speed x horizon.
TEST(SingularityMonitor, RateTestWarnsEarlierWhenApproachingFast) {
  const RobotModelPtr model = testing::load_ur5();
  Dynamics dyn;
  std::string why;
  Dynamics::configure(model, {0, 0, -9.81}, &dyn, &why);
  auto warn_at = [&](double horizon) {
    SingularityMonitorConfig cfg;
    cfg.condition_warn = 1e12;  // manipulability only
    cfg.manipulability_warn = 0.05;
    cfg.horizon = horizon;
    SingularityMonitor mon;
    mon.configure(cfg);
    Eigen::MatrixXd J(6, 6);
    SingularityState st;
    for (int k = 0; k <= 2000; ++k) {
      Eigen::VectorXd q = testing::ur5_home();
      q[2] = 1.6 - 0.8 * k * 1e-3;  // elbow opening at 0.8 rad/s
      dyn.jacobian(q, J);
      if (mon.update(J, 1e-3, &st) == Status::kNearSingularity) return q[2];
    }
    return -1.0;
  };
  const double q_static = warn_at(0.0), q_ahead = warn_at(0.3);
  std::printf("singularity: w < 0.05 warns at elbow %.3f rad; with a 0.3 s look-ahead at %.3f rad\n",
              q_static, q_ahead);
  EXPECT_GT(q_static, 0.0);
  EXPECT_GT(q_ahead, q_static + 0.1);  // 0.8 rad/s x 0.3 s = 0.24 rad earlier, roughly
}

TEST(ArmSupervisor, BadInputsAndZeroAllocations) {
  const RobotModelPtr model = testing::load_ur5();
  ArmSupervisor sup = make_supervisor(model);
  SupervisorInput in = sup.make_input();
  SupervisorOutput out = sup.make_output();
  in.q = testing::ur5_home();
  ASSERT_TRUE(ok(sup.step(in, out)));
  SupervisorInput bad = in;
  bad.q[0] = NAN;
  EXPECT_EQ(sup.step(bad, out), Status::kNonFiniteMeasurement);
  EXPECT_TRUE(out.tau.allFinite());
  bad = in;
  bad.qd.resize(3);
  EXPECT_EQ(sup.step(bad, out), Status::kBadSize);
  bad = in;
  bad.t = 2.0;
  EXPECT_EQ(sup.step(bad, out), Status::kStaleMeasurement);
  SupervisorOutput small;
  EXPECT_EQ(sup.step(in, small), Status::kBadSize);
  ArmSupervisorConfig cfg;
  cfg.stop_deceleration = Eigen::VectorXd::Constant(2, 1.0);
  ArmSupervisor rejected;
  std::string why;
  EXPECT_EQ(ArmSupervisor::configure(cfg, model, &rejected, &why), Status::kInvalidConfig);
  EXPECT_EQ(rejected.step(in, out), Status::kNotConfigured);

  ArmSupervisor a = make_supervisor(model);
  in.tau_command.setConstant(1.0);
  a.step(in, out);
  testing::AllocationScope scope;
  for (int k = 0; k < 5000; ++k) {
    in.t = in.stamp = k * 1e-3;
    in.q[0] = 0.1 * std::sin(k * 1e-3);
    in.estop = k > 2500;  // normal, then stopping, then holding
    a.step(k % 500 == 7 ? bad : in, out);
  }
  EXPECT_EQ(scope.count(), 0u);
  EXPECT_EQ(a.mode(), SupervisorMode::kHolding);
}

}  // namespace
}  // namespace kiloloop

namespace kiloloop {
namespace {

TEST(ArmSupervisor, SameInputsGiveBitIdenticalOutputs) {
  const RobotModelPtr model = testing::load_ur5();
  ArmSupervisor a = make_supervisor(model), b = make_supervisor(model);
  SupervisorInput in = a.make_input();
  SupervisorOutput oa = a.make_output(), ob = b.make_output();
  for (int k = 0; k < 1500; ++k) {
    in.t = in.stamp = k * 1e-3;
    in.q = testing::ur5_home();
    in.q[0] = 0.3 * std::sin(2.0 * in.t);
    in.qd.setZero();
    in.qd[0] = 0.6 * std::cos(2.0 * in.t);
    in.tau_command.setConstant(20.0 * std::sin(in.t));
    in.estop = k >= 700;
    a.step(in, oa);
    b.step(in, ob);
    ASSERT_EQ(std::memcmp(oa.tau.data(), ob.tau.data(), 6 * sizeof(double)), 0) << "tick " << k;
    ASSERT_EQ(oa.mode, ob.mode);
  }
  EXPECT_NE(a.mode(), SupervisorMode::kNormal);
}

}  // namespace
}  // namespace kiloloop
