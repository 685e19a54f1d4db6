// ArmSupervisor through a measurement outage, closed loop on the UR5 (exact dynamics): a short
// outage passes, a long one latches a stop that brakes the arm; a stop in progress keeps braking
// when the measurement goes bad, instead of coasting under gravity compensation (the behaviour
// before max_bad_ticks: no stop ever latched, and the arm kept its speed).
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "arm_sim.hpp"
#include "kiloloop/safety/arm_supervisor.hpp"
#include "test_models.hpp"

namespace kiloloop {
namespace {


const Eigen::VectorXd& qd_cmd() {
  static const Eigen::VectorXd v = (Eigen::VectorXd(6) << 1.0, -0.6, 0.8, 0.5, -1.0, 1.2).finished();
  return v;
}

// The "arm controller": a computed-torque velocity servo toward qd_cmd.
struct Rig {
  RobotModelPtr model = testing::load_ur5();
  ArmSupervisor sup;
  Dynamics dyn;
  testing::ArmSim sim{model, testing::ur5_home()};
  SupervisorInput in;
  SupervisorOutput out;

  explicit Rig(int max_bad_ticks) {
    ArmSupervisorConfig cfg;
    cfg.max_bad_ticks = max_bad_ticks;
    std::string why;
    EXPECT_EQ(ArmSupervisor::configure(cfg, model, &sup, &why), Status::kOk) << why;
    Dynamics::configure(model, {0, 0, -9.81}, &dyn, &why);
    in = sup.make_input();
    out = sup.make_output();
  }
  // One tick at time t; `good` false: the sensor repeats its last sample with an old stamp, or
  // sends NaN (`nan`).
  Status tick(double t, bool good, bool nan = false) {
    in.t = t;
    if (good) {
      in.stamp = t;
      in.q = sim.q;
      in.qd = sim.qd;
    } else if (nan) {
      in.stamp = t;
      in.q.setConstant(NAN);
    } else {
      in.stamp = t - 1.0;  // the last sample, a second old
    }
    dyn.inverse_dynamics(sim.q, sim.qd, 10.0 * (qd_cmd() - sim.qd), in.tau_command);
    const Status s = sup.step(in, out);
    sim.step(out.tau, 1e-3);
    return s;
  }
};

TEST(ArmSupervisorOutage, ShortOutagePassesLongOneLatchesAStopThatBrakes) {
  const int n_bad = 20;
  Rig rig(n_bad);
  int k = 0;
  for (; k < 300; ++k) ASSERT_FALSE(failed(rig.tick(k * 1e-3, true))) << k;
  // n_bad - 1 stale ticks, then fresh again: still NORMAL.
  for (int i = 0; i < n_bad - 1; ++i, ++k)
    EXPECT_EQ(rig.tick(k * 1e-3, false), Status::kStaleMeasurement);
  EXPECT_EQ(rig.out.mode, SupervisorMode::kNormal);
  for (int i = 0; i < 100; ++i, ++k) rig.tick(k * 1e-3, true);
  ASSERT_EQ(rig.out.mode, SupervisorMode::kNormal);
  const double speed = rig.sim.qd.cwiseAbs().maxCoeff();
  ASSERT_GT(speed, 0.5);

  // The sensor freezes for good: the n_bad-th stale tick latches the stop.
  for (int i = 1; i <= n_bad; ++i, ++k) {
    rig.tick(k * 1e-3, false);
    ASSERT_EQ(rig.out.mode, i < n_bad ? SupervisorMode::kNormal : SupervisorMode::kStopping) << i;
  }
  EXPECT_EQ(rig.out.trip, Status::kStaleMeasurement);
  EXPECT_EQ(rig.sup.counters().measurement_trips, 1u);
  const double planned = rig.out.stop_time, t_latch = (k - 1) * 1e-3;
  EXPECT_NEAR(planned, speed / 4.0, 0.05);  // from the last valid qd at the default a_stop
  // Open loop the stop brakes as planned; afterwards the hold drifts (gravity on a pose that is
  // off the planned one is a negative stiffness, and nothing measures it): the slowest point
  // is at the end of the planned stop.
  double slowest = INFINITY;
  for (; k * 1e-3 < t_latch + planned + 0.1; ++k) {
    rig.tick(k * 1e-3, false);
    ASSERT_TRUE(rig.out.tau.allFinite());
    if (k * 1e-3 > t_latch + planned - 0.05) slowest = std::fmin(slowest, rig.sim.qd.cwiseAbs().maxCoeff());
  }
  std::printf("outage at %.2f rad/s: latched after %d ticks, planned stop %.3f s, slowest %.3f rad/s\n",
              speed, n_bad, planned, slowest);
  EXPECT_EQ(rig.out.mode, SupervisorMode::kHolding);
  EXPECT_LT(slowest, 0.1 * speed);
}

TEST(ArmSupervisorOutage, AStopInProgressKeepsBrakingWithoutAMeasurement) {
  Rig rig(1000000);  // the outage never latches: only the stop already in progress brakes
  int k = 0;
  for (; k < 400; ++k) rig.tick(k * 1e-3, true);
  const double speed = rig.sim.qd.cwiseAbs().maxCoeff();
  ASSERT_GT(speed, 0.5);
  rig.in.estop = true;
  rig.tick(k++ * 1e-3, true);
  ASSERT_EQ(rig.out.mode, SupervisorMode::kStopping);
  const double planned = rig.out.stop_time, t_estop = (k - 1) * 1e-3;
  // 20 ms into the stop the measurement turns to NaN for good.
  for (int i = 0; i < 20; ++i, ++k) rig.tick(k * 1e-3, true);
  for (; k * 1e-3 < t_estop + planned + 0.3; ++k) {
    EXPECT_EQ(rig.tick(k * 1e-3, false, true), Status::kNonFiniteMeasurement);
    ASSERT_TRUE(rig.out.tau.allFinite());
  }
  const double residual = rig.sim.qd.cwiseAbs().maxCoeff();
  std::printf("stop through an outage: %.2f rad/s, planned %.3f s, residual %.4f rad/s\n", speed, planned,
              residual);
  EXPECT_EQ(rig.out.mode, SupervisorMode::kHolding);
  EXPECT_EQ(rig.out.trip, Status::kEmergencyStop);
  EXPECT_LT(residual, 0.05 * speed);
}

}  // namespace
}  // namespace kiloloop
