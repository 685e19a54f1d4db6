// embed_demo: what firmware does with kiloloop, in one file and through find_package(kiloloop) only.
//
//   embed_demo <robot.urdf>           encoder replay (open loop, bit-reproducible)
//   embed_demo <robot.urdf> --plant   closed loop against a tiny in-program plant
//
// Init (may allocate, may fail with a reason): load the URDF, configure a ComputedTorqueController
// (default settings) and a QuinticTrajectory through the waypoint table below. Then 1000 ticks at
// 1 kHz: sample the reference, read the "encoders", step the controller, apply the torque.
//
// Encoders: firmware reads them from hardware. Here they are either
//   - replayed: q = q_ref + a fixed closed-form perturbation of the tick number. Every controller
//     input is then a pure function of the tick, so examples/embed/embed_twin.py reproduces the run
//     through the Python module and the torques must agree to the last bit (tests/test_embed_example.py);
//   - or (--plant) integrated from the model's own dynamics, qdd = M^-1 (tau - C qd - g), with a
//     second Dynamics workspace and Eigen's LDLT. A closed loop is what a human wants to see (the
//     tracking error), but its state depends on the linear solver, which numpy and Eigen round
//     differently, so it is not part of the bit-identity check.
//
// stdout, one line per tick:  tick tau_0 ... tau_{nq-1} status
//   torques as C99 hexadecimal floats (%a: exact, parse with Python's float.fromhex), status as
//   the signed kiloloop::Status code. stderr: one human-readable summary line.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>
#include <utility>

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "kiloloop/control/computed_torque.hpp"
#include "kiloloop/dynamics/dynamics.hpp"
#include "kiloloop/trajectory/quintic.hpp"
#include "kiloloop/urdf/urdf_loader.hpp"

namespace {

constexpr int kTicks = 1000;
constexpr double kDt = 0.001;  // [s] the 1 kHz tick

// The task, not the robot (the robot comes from the URDF): three configurations of a 6-joint arm
// and when to pass them. The last 0.1 s holds the end point, so the run ends at rest.
// embed_twin.py carries the same literals; keep both tables identical.
constexpr int kWaypointNq = 6;
constexpr int kWaypointCount = 3;
constexpr double kTimes[kWaypointCount] = {0.0, 0.4, 0.9};  // [s]
constexpr double kWaypoints[kWaypointCount][kWaypointNq] = {  // [rad]
    {0.0, -1.57, 1.57, -1.57, -1.57, 0.0},
    {0.5, -1.2, 1.2, -1.2, -1.3, 0.4},
    {1.0, -1.0, 0.8, -1.4, -1.0, 0.8},
};

// Replayed encoders: a small known error per joint, different for each joint. std::sin and
// std::cos are musl's here (kiloloop::core links kiloloop::detmath ahead of libm), as
// kl.detmath.sin/cos are in Python: embed_twin.py evaluates the same expressions in the same
// order, on doubles, with the same functions. (q and qd use different phase rates; a sin and cos
// of one argument, which GCC fuses into one sincos call, would give the same bits too.)
constexpr double kPositionNoise = 1e-3;   // [rad]
constexpr double kPositionRate = 0.01;    // [rad/tick] per joint index
constexpr double kVelocityNoise = 1e-2;   // [rad/s]
constexpr double kVelocityRate = 0.007;   // [rad/tick] per joint index

void replay_encoders(int tick, const Eigen::VectorXd& q_ref, const Eigen::VectorXd& qd_ref,
                     Eigen::VectorXd& q, Eigen::VectorXd& qd) {
  for (Eigen::Index j = 0; j < q.size(); ++j) {
    const double k = static_cast<double>(j + 1);
    q[j] = q_ref[j] + kPositionNoise * std::sin(kPositionRate * tick * k);
    qd[j] = qd_ref[j] + kVelocityNoise * std::cos(kVelocityRate * tick * k);
  }
}

int fail(const char* what, const std::string& why) {
  std::fprintf(stderr, "embed_demo: %s: %s\n", what, why.c_str());
  return 1;
}

}  // namespace

int main(int argc, char** argv) {
  const bool plant_mode = argc == 3 && std::strcmp(argv[2], "--plant") == 0;
  if (argc != 2 && !plant_mode) {
    std::fprintf(stderr, "usage: %s <robot.urdf> [--plant]\n", argv[0]);
    return 2;
  }

  // --- init: everything that allocates or can fail happens here, once -------------------------
  std::string why;
  auto loaded = std::make_shared<kiloloop::RobotModel>();
  if (kiloloop::failed(kiloloop::model_from_urdf_file(argv[1], "", "", loaded.get(), &why)))
    return fail("cannot load the model", why);
  const kiloloop::RobotModelPtr model = std::move(loaded);
  const int nq = model->nq();
  if (nq != kWaypointNq)
    return fail("waypoint table", "written for 6 joints, the model has " + std::to_string(nq));

  const kiloloop::ComputedTorqueConfig config;  // the library's defaults
  kiloloop::ComputedTorqueController controller;
  if (kiloloop::failed(kiloloop::ComputedTorqueController::configure(config, model, &controller, &why)))
    return fail("cannot configure the controller", why);

  Eigen::MatrixXd waypoints(nq, kWaypointCount);  // columns are configurations
  Eigen::VectorXd times(kWaypointCount);
  for (int k = 0; k < kWaypointCount; ++k) {
    times[k] = kTimes[k];
    for (int j = 0; j < nq; ++j) waypoints(j, k) = kWaypoints[k][j];
  }
  kiloloop::QuinticTrajectory trajectory;
  if (kiloloop::failed(kiloloop::QuinticTrajectory::configure(waypoints, times, &trajectory, &why)))
    return fail("cannot configure the trajectory", why);

  kiloloop::JointControlInput in = controller.make_input();
  kiloloop::JointControlOutput out = controller.make_output();

  // The plant: its own Dynamics workspace over the same const model (one model, many workspaces).
  kiloloop::Dynamics plant;
  if (kiloloop::failed(kiloloop::Dynamics::configure(model, config.gravity, &plant, &why)))
    return fail("cannot configure the plant", why);
  Eigen::VectorXd q = waypoints.col(0), qd = Eigen::VectorXd::Zero(nq);  // starts at rest on the path
  Eigen::MatrixXd M(nq, nq);
  Eigen::VectorXd bias(nq), qdd(nq);
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(nq);
  Eigen::LDLT<Eigen::MatrixXd> ldlt(nq);  // sized here, so compute/solve below do not allocate

  // --- the 1 kHz loop ------------------------------------------------------------------------
  double max_error = 0.0, max_abs_tau = 0.0;
  int not_ok = 0, failures = 0;
  for (int tick = 0; tick < kTicks; ++tick) {
    // Time comes in the input (step never reads a clock); the encoders were sampled this tick.
    in.t = tick * kDt;
    in.stamp = in.t;
    trajectory.sample(in.t, in.q_ref, in.qd_ref, in.qdd_ref);
    if (plant_mode) {
      in.q = q;
      in.qd = qd;
    } else {
      replay_encoders(tick, in.q_ref, in.qd_ref, in.q, in.qd);
    }
    const kiloloop::Status status = controller.step(in, out);

    std::printf("%d", tick);
    for (int j = 0; j < nq; ++j) std::printf(" %a", out.tau[j]);
    std::printf(" %d\n", static_cast<int>(status));
    max_error = std::max(max_error, (in.q_ref - in.q).cwiseAbs().maxCoeff());
    max_abs_tau = std::max(max_abs_tau, out.tau.cwiseAbs().maxCoeff());
    not_ok += status != kiloloop::Status::kOk;
    failures += kiloloop::failed(status);

    if (plant_mode) {
      // Semi-implicit Euler on M qdd = tau - (C qd + g); C qd + g is one RNE pass with qdd = 0.
      plant.mass_matrix(q, M);
      plant.inverse_dynamics(q, qd, zero, bias);
      ldlt.compute(M);
      qdd.noalias() = ldlt.solve(out.tau - bias);
      qd += kDt * qdd;
      q += kDt * qd;
    }
  }

  std::fprintf(stderr,
               "embed_demo: %d ticks (%s), max tracking error %.3e rad, max |tau| %.2f N m, "
               "%d ticks not ok (%d failed)\n",
               kTicks, plant_mode ? "closed loop on the model plant" : "encoder replay", max_error,
               max_abs_tau, not_ok, failures);
  return failures == 0 && std::isfinite(max_abs_tau) ? 0 : 3;
}
