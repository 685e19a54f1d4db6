// QuadrupedController through its public API only (cpp/include/kiloloop/quadruped), standing and
// trotting on good sensor data with corruptions mixed in. Fixed-size vectors: no size mutations.
// Each run (between reconfigures) uses the controller's own attitude filter or, at random, an
// external AHRS (estimator.external_attitude): the quaternion input counts only in the latter.
#include <cmath>
#include <cstring>

#include "fuzz_models.hpp"
#include "kiloloop/quadruped/quadruped_controller.hpp"

namespace kiloloop::fuzz {

Tally fuzz_quadruped(std::uint64_t seed, std::uint64_t inputs, volatile std::uint64_t* progress) {
  Tally tally;
  tally.target = "quadruped";
  Rng r(seed * 0x85EBCA77ull + 19);
  const RobotModelPtr model = load_model("quadruped/quadruped.urdf");
  QuadrupedConfig config;
  config.body_height = 0.3308;  // the standing pose below
  QuadrupedController ctrl;
  std::string why;
  if (failed(QuadrupedController::configure(config, model, &ctrl, &why))) {
    std::fprintf(stderr, "quadruped configure: %s\n", why.c_str());
    std::exit(5);
  }
  const Eigen::Matrix<double, 12, 1> effort = ctrl.effort_limit();
  QuadrupedInput in;
  QuadrupedOutput out;
  StampModel stamps;
  stamps.max_age = config.max_measurement_age;
  Clock clock;
  Desc desc;
  int gait = 0;
  for (std::uint64_t k = 0; k < inputs; ++k) {
    *progress = k;
    ++tally.inputs;
    desc.clear();
    if (k % 3000 == 2999 || (stamps.has_newest && stamps.newest > clock.t + 1.0)) {
      config.estimator.external_attitude = r.chance(0.5);
      QuadrupedController::configure(config, model, &ctrl, &why);  // a new run
      out = QuadrupedOutput{};
      stamps.reset();
      clock.t = r.uniform(0.0, 100.0);
      gait = r.below(2);
    }
    for (int leg = 0; leg < 4; ++leg)
      in.q.segment<3>(3 * leg) = Eigen::Vector3d(0.0, 0.9, -1.8) +
                                 Eigen::Vector3d(r.uniform(-0.05, 0.05), r.uniform(-0.1, 0.1), r.uniform(-0.1, 0.1));
    for (int i = 0; i < 12; ++i) in.qd[i] = r.uniform(-1.0, 1.0);
    for (int i = 0; i < 3; ++i) {
      in.gyro[i] = r.uniform(-0.2, 0.2);
      in.accel[i] = (i == 2 ? 9.81 : 0.0) + r.uniform(-0.5, 0.5);
      in.velocity_command[i] = r.uniform(-0.3, 0.3);
    }
    Eigen::Vector4d quat(1.0, r.uniform(-0.02, 0.02), r.uniform(-0.02, 0.02), r.uniform(-0.05, 0.05));
    in.quat = quat.normalized();
    in.gait = static_cast<decltype(in.gait)>(gait);
    in.use_ground_truth = false;
    in.true_position = Eigen::Vector3d(0.0, 0.0, 0.33);
    in.true_velocity.setZero();
    in.true_quat = in.quat;
    clock.tick(r, stamps, &in.t, &in.stamp);
    bool gait_bad = false;
    const int mutations = r.chance(0.4) ? 0 : 1 + r.below(2);
    for (int m = 0; m < mutations; ++m) {
      const bool nonfinite = r.chance(0.5);
      switch (r.below(12)) {
        case 0: poke(r, in.q.data(), 12, nonfinite, desc, "q"); break;
        case 1: poke(r, in.qd.data(), 12, nonfinite, desc, "qd"); break;
        case 2: poke(r, in.gyro.data(), 3, nonfinite, desc, "gyro"); break;
        case 3: poke(r, in.accel.data(), 3, nonfinite, desc, "accel"); break;
        case 4: poke(r, in.quat.data(), 4, nonfinite, desc, "quat"); break;
        case 5: poke(r, in.velocity_command.data(), 3, nonfinite, desc, "velocity_command"); break;
        case 6: case 7: mutate_time(r, stamps.max_age, stamps, &in.t, &in.stamp, desc); break;
        case 8: {
          static const int kBadGaits[] = {-1, 2, 7, 1 << 30};
          const int g = kBadGaits[r.below(4)];
          in.gait = static_cast<decltype(in.gait)>(g);
          gait_bad = true;
          desc.add("gait=%d", g);
          break;
        }
        case 9:
          in.use_ground_truth = true;
          poke(r, r.chance(0.5) ? in.true_position.data() : in.true_velocity.data(), 3, nonfinite,
               desc, "true_position|true_velocity (use_ground_truth)");
          break;
        case 10:
          in.velocity_command.setConstant(r.chance(0.5) ? 1e300 : -1e300);
          desc.add("velocity_command ~ 1e300");
          break;
        default:
          in.accel.setConstant(extreme_value(r));
          desc.add("accel all = %.17g", in.accel[0]);
          break;
      }
    }
    const bool external = config.estimator.external_attitude;
    const bool meas_ok = in.q.allFinite() && in.qd.allFinite() && in.gyro.allFinite() &&
                         in.accel.allFinite() && (!external || in.quat.allFinite()) &&
                         stamps.fresh(in.t, in.stamp);
    const bool cmd_ok = in.velocity_command.allFinite() && !gait_bad &&
                        (!in.use_ground_truth ||
                         (in.true_position.allFinite() && in.true_velocity.allFinite() && in.true_quat.allFinite()));
    const bool bad = !meas_ok || !cmd_ok;
    tally.bad_inputs += bad;
    const Status s = ctrl.step(in, out);
    // A measurement the controller must not use does not count for the order rule: one beyond
    // the sanity bound (|x| > 1e6, a clock beyond 1e9 s: control/sane_range.hpp), a quaternion
    // far from unit norm (external attitude only), unusable ground truth.
    auto sane = [](const auto& v) { return v.allFinite() && v.cwiseAbs().maxCoeff() <= 1e6; };
    const bool used = meas_ok && std::abs(in.t) <= 1e9 && sane(in.q) && sane(in.qd) && sane(in.gyro) &&
                      sane(in.accel) && (!external || (sane(in.quat) && in.quat.norm() > 0.5)) &&
                      (!in.use_ground_truth || (sane(in.true_position) && sane(in.true_velocity) &&
                                                sane(in.true_quat) && in.true_quat.norm() > 0.5));
    if (used) stamps.accept(in.stamp);
    if (s != out.status) tally.fail(k, desc, &tally.bad_outputs, "returned %s, out.status %s", to_string(s), to_string(out.status));
    bool finite = out.foot_force.allFinite() && out.contact.allFinite() && out.scheduled.allFinite() &&
                  out.foot_clearance.allFinite() && out.position.allFinite() && out.velocity.allFinite() &&
                  out.quat.allFinite() && out.ground_normal.allFinite() && out.wrench.allFinite() &&
                  std::isfinite(out.tilt);
    if (!within_effort(out.tau, effort))
      tally.fail(k, desc, &tally.bad_outputs, "tau not finite or beyond effort (status %s)", to_string(s));
    if (!finite) {
      char which[160] = "";
      const struct { const char* name; bool ok; } fields[] = {
          {"foot_force", out.foot_force.allFinite()}, {"contact", out.contact.allFinite()},
          {"scheduled", out.scheduled.allFinite()}, {"foot_clearance", out.foot_clearance.allFinite()},
          {"position", out.position.allFinite()}, {"velocity", out.velocity.allFinite()},
          {"quat", out.quat.allFinite()}, {"ground_normal", out.ground_normal.allFinite()},
          {"wrench", out.wrench.allFinite()}, {"tilt", std::isfinite(out.tilt)}};
      for (const auto& f : fields)
        if (!f.ok) std::snprintf(which + std::strlen(which), sizeof(which) - std::strlen(which), " %s", f.name);
      tally.fail(k, desc, &tally.bad_outputs, "non-finite output:%s (status %s, %s attitude)", which,
                 to_string(s), external ? "external" : "own");
    }
    // A defect that persists would be counted on every later input: start a new run instead, so
    // that each count is one input that broke the controller.
    if (!finite || !within_effort(out.tau, effort)) {
      QuadrupedController::configure(config, model, &ctrl, &why);
      out = QuadrupedOutput{};
      stamps.reset();
    }
    if (bad && !failed(s)) tally.fail(k, desc, &tally.missed_status, "bad input answered %s", to_string(s));
  }
  return tally;
}

}  // namespace kiloloop::fuzz
