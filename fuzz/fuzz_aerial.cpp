// AerialController through its public API only (cpp/include/kiloloop/aerial), on the aerial
// manipulator of models/: hovering near its references in both flight modes and both arm modes,
// with corruptions mixed in (NaN/Inf and extreme values in the state and every reference, wrong
// sizes, stale/future/out-of-order stamps, mode values outside their enums).
#include <cmath>

#include "fuzz_models.hpp"
#include "kiloloop/aerial/aerial_controller.hpp"

namespace kiloloop::fuzz {
namespace {

// Every output field finite; thrusts within [thrust_min, thrust_max_i]; arm torques within effort.
bool outputs_ok(const AerialOutput& out, double thrust_min, const Eigen::VectorXd& thrust_max,
                const Eigen::VectorXd& effort, const char** why) {
  if (out.thrust.size() != thrust_max.size() || !out.thrust.allFinite()) return *why = "thrust not finite", false;
  for (Eigen::Index i = 0; i < out.thrust.size(); ++i)
    if (out.thrust[i] < thrust_min || out.thrust[i] > thrust_max[i]) return *why = "thrust beyond its limits", false;
  if (!within_effort(out.tau, effort)) return *why = "tau not finite or beyond effort", false;
  const bool finite = out.wrench.allFinite() && out.wrench_achieved.allFinite() &&
                      out.reaction.allFinite() && out.acceleration_des.allFinite() &&
                      out.quat_des.allFinite() && out.attitude_error.allFinite() &&
                      out.q_ref.allFinite() && out.ee_position.allFinite() && std::isfinite(out.tilt);
  if (!finite) return *why = "a diagnostic output is not finite", false;
  return true;
}

}  // namespace

Tally fuzz_aerial(std::uint64_t seed, std::uint64_t inputs, volatile std::uint64_t* progress) {
  Tally tally;
  tally.target = "aerial";
  Rng r(seed * 0xC2B2AE35ull + 23);
  const RobotModelPtr model = load_model("aerial_manipulator/aerial_manipulator.urdf", "ee_link");
  const AerialConfig config;
  AerialController ctrl;
  std::string why;
  if (failed(AerialController::configure(config, model, &ctrl, &why))) {
    std::fprintf(stderr, "aerial configure: %s\n", why.c_str());
    std::exit(5);
  }
  const int nq = ctrl.nq();
  const Eigen::VectorXd effort = model->effort_limit();
  const Eigen::VectorXd lower = model->lower(), upper = model->upper();
  const Eigen::VectorXd thrust_max = ctrl.allocation().thrust_max();
  const double thrust_min = config.rotors.thrust_min;
  AerialInput in = ctrl.make_input();
  AerialOutput out = ctrl.make_output();
  WrongSize sizes(nq);
  StampModel stamps;
  stamps.max_age = config.max_measurement_age;
  Clock clock;
  Desc desc;
  for (std::uint64_t k = 0; k < inputs; ++k) {
    *progress = k;
    ++tally.inputs;
    desc.clear();
    // A new run now and then, after a latched safe stop, and after a glitch stamp far ahead.
    if (k % 3000 == 2999 || out.safe_stop || (stamps.has_newest && stamps.newest > clock.t + 1.0)) {
      ctrl.reset();
      stamps.reset();
      clock.t = r.uniform(0.0, 100.0);
    }
    // A good input: near hover at 1 m, small rates, the arm inside its limits.
    for (int i = 0; i < 3; ++i) {
      in.position[i] = (i == 2 ? 1.0 : 0.0) + r.uniform(-0.2, 0.2);
      in.velocity[i] = r.uniform(-0.5, 0.5);
      in.gyro[i] = r.uniform(-0.5, 0.5);
      in.accel[i] = (i == 2 ? 9.81 : 0.0) + r.uniform(-1.0, 1.0);
      in.position_ref[i] = (i == 2 ? 1.0 : 0.0) + r.uniform(-0.3, 0.3);
      in.velocity_ref[i] = r.uniform(-0.3, 0.3);
      in.acceleration_ref[i] = r.uniform(-0.5, 0.5);
      in.ee_position_ref[i] = in.position[i] + (i == 2 ? -0.25 : 0.1) + r.uniform(-0.1, 0.1);
      in.ee_velocity_ref[i] = r.uniform(-0.2, 0.2);
    }
    in.quat = Eigen::Vector4d(1.0, r.uniform(-0.1, 0.1), r.uniform(-0.1, 0.1), r.uniform(-0.3, 0.3)).normalized();
    in.quat_ref = Eigen::Vector4d(1.0, r.uniform(-0.1, 0.1), r.uniform(-0.1, 0.1), r.uniform(-0.3, 0.3)).normalized();
    in.yaw_ref = r.uniform(-1.0, 1.0);
    for (int j = 0; j < nq; ++j) {
      const double lo = std::isfinite(lower[j]) ? lower[j] : -3.0, hi = std::isfinite(upper[j]) ? upper[j] : 3.0;
      in.q[j] = r.uniform(lo, hi);
      in.qd[j] = r.uniform(-1.0, 1.0);
      in.q_ref[j] = r.uniform(lo, hi);
      in.qd_ref[j] = r.uniform(-0.5, 0.5);
      in.qdd_ref[j] = r.uniform(-2.0, 2.0);
    }
    in.flight_mode = r.chance(0.8) ? FlightMode::kPosition : FlightMode::kAttitude;
    in.arm_mode = r.chance(0.7) ? ArmMode::kJoints : ArmMode::kEndEffector;
    clock.tick(r, stamps, &in.t, &in.stamp);

    bool meas_bad = false, ref_bad = false, bad_mode = false;
    int resize = -1;
    const int mutations = r.chance(0.4) ? 0 : 1 + r.below(2);
    for (int m = 0; m < mutations; ++m) {
      const bool nonfinite = r.chance(0.5);
      const bool joints = in.arm_mode == ArmMode::kJoints;
      const bool attitude = in.flight_mode == FlightMode::kAttitude;
      switch (r.below(16)) {
        case 0: meas_bad |= poke(r, in.position.data(), 3, nonfinite, desc, "position"); break;
        case 1: meas_bad |= poke(r, in.velocity.data(), 3, nonfinite, desc, "velocity"); break;
        case 2: meas_bad |= poke(r, in.quat.data(), 4, nonfinite, desc, "quat"); break;
        case 3: meas_bad |= poke(r, in.gyro.data(), 3, nonfinite, desc, "gyro"); break;
        case 4: meas_bad |= poke(r, in.accel.data(), 3, nonfinite, desc, "accel"); break;
        case 5: meas_bad |= poke(r, in.q.data(), nq, nonfinite, desc, "q"); break;
        case 6: meas_bad |= poke(r, in.qd.data(), nq, nonfinite, desc, "qd"); break;
        case 7: ref_bad |= poke(r, in.position_ref.data(), 3, nonfinite, desc, "position_ref"); break;
        case 8:
          ref_bad |= r.chance(0.5) ? poke(r, in.velocity_ref.data(), 3, nonfinite, desc, "velocity_ref")
                                   : poke(r, &in.yaw_ref, 1, nonfinite, desc, "yaw_ref");
          break;
        case 9: ref_bad |= poke(r, in.acceleration_ref.data(), 3, nonfinite, desc, "acceleration_ref"); break;
        case 10: {  // the reference of the arm's current mode (and of the attitude mode)
          const bool hit = joints ? poke(r, (r.chance(0.5) ? in.q_ref : r.chance(0.5) ? in.qd_ref : in.qdd_ref).data(),
                                         nq, nonfinite, desc, "q_ref|qd_ref|qdd_ref")
                                  : poke(r, (r.chance(0.5) ? in.ee_position_ref : in.ee_velocity_ref).data(),
                                         3, nonfinite, desc, "ee_position_ref|ee_velocity_ref");
          ref_bad |= hit;
          break;
        }
        case 11: ref_bad |= attitude && poke(r, in.quat_ref.data(), 4, nonfinite, desc, "quat_ref"); break;
        case 12: case 13: mutate_time(r, stamps.max_age, stamps, &in.t, &in.stamp, desc); break;
        case 14: {  // a wrong size: a measurement always matters, a joint reference in joint mode
          const int which = r.below(5);
          resize = which;  // applied after the value mutations (a poke needs nq entries)
          break;
        }
        default: {  // a mode outside its enum
          static const int kBad[] = {-1, 2, 7, 1 << 30};
          const int v = kBad[r.below(4)];
          if (r.chance(0.5)) {
            in.flight_mode = static_cast<FlightMode>(v);
            desc.add("flight_mode=%d", v);
          } else {
            in.arm_mode = static_cast<ArmMode>(v);
            desc.add("arm_mode=%d", v);
          }
          bad_mode = true;
          break;
        }
      }
    }
    // What the input finally holds decides: a second poke into the same entry may overwrite the
    // first one's NaN with a finite value (measured: 5 clean inputs in 20,000 counted as bad).
    meas_bad = !(in.position.allFinite() && in.velocity.allFinite() && in.quat.allFinite() &&
                 in.gyro.allFinite() && in.accel.allFinite() && in.q.allFinite() && in.qd.allFinite());
    ref_bad = bad_mode ||
              !(in.position_ref.allFinite() && in.velocity_ref.allFinite() && std::isfinite(in.yaw_ref) &&
                in.acceleration_ref.allFinite() && in.q_ref.allFinite() && in.qd_ref.allFinite() &&
                in.qdd_ref.allFinite() && in.ee_position_ref.allFinite() &&
                in.ee_velocity_ref.allFinite() && in.quat_ref.allFinite());
    if (resize >= 0) {
      Eigen::VectorXd* fields[] = {&in.q, &in.qd, &in.q_ref, &in.qd_ref, &in.qdd_ref};
      static const char* names[] = {"q", "qd", "q_ref", "qd_ref", "qdd_ref"};
      sizes.apply(r, *fields[resize], desc, names[resize]);
      if (fields[resize]->size() != nq)
        (resize < 2 ? meas_bad : ref_bad) |= resize < 2 || in.arm_mode == ArmMode::kJoints;
    }
    meas_bad |= !stamps.fresh(in.t, in.stamp);
    const bool bad = meas_bad || ref_bad;
    tally.bad_inputs += bad;
    const Status s = ctrl.step(in, out);
    sizes.undo();
    // The controller accepts the stamp once the state passed its checks (the references are
    // checked after: a bad one does not undo it); an extreme state (beyond 1e6) or a tilt past
    // the limit fails those checks without being "bad" here.
    if (!meas_bad && s != Status::kNonFiniteMeasurement && s != Status::kSafeStop)
      stamps.accept(in.stamp);
    if (s != out.status)
      tally.fail(k, desc, &tally.bad_outputs, "returned %s, out.status %s", to_string(s), to_string(out.status));
    const char* what = "";
    if (!outputs_ok(out, thrust_min, thrust_max, effort, &what)) {
      tally.fail(k, desc, &tally.bad_outputs, "%s (status %s)", what, to_string(s));
      AerialController::configure(config, model, &ctrl, &why);  // count each break once
      stamps.reset();
      out = ctrl.make_output();
    }
    if (bad && !failed(s)) tally.fail(k, desc, &tally.missed_status, "bad input answered %s", to_string(s));
  }
  return tally;
}

}  // namespace kiloloop::fuzz
