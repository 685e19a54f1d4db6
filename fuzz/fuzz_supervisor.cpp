// ArmSupervisor on the UR5: measurements, the controller's torque command, e-stop and reset,
// times and sizes corrupted at random. Bad command (NaN/inf, wrong size, beyond the peak trip)
// latches a stop: from then on every tick fails until reset.
#include <cmath>

#include "fuzz_models.hpp"
#include "kiloloop/safety/arm_supervisor.hpp"

namespace kiloloop::fuzz {

Tally fuzz_arm_supervisor(std::uint64_t seed, std::uint64_t inputs, volatile std::uint64_t* progress) {
  Tally tally;
  tally.target = "arm_supervisor";
  Rng r(seed * 0x27D4EB2Full + 17);
  const RobotModelPtr model = load_model("ur5/ur5.urdf");
  ArmSupervisorConfig config;
  ArmSupervisor sup;
  std::string why;
  if (failed(ArmSupervisor::configure(config, model, &sup, &why))) std::exit(5);
  const int n = sup.nq();
  const Eigen::VectorXd& effort = model->effort_limit();
  SupervisorInput in = sup.make_input();
  SupervisorOutput out = sup.make_output();
  Eigen::VectorXd tau_big = Eigen::VectorXd::Zero(n + 1);
  WrongSize wrong(n);
  StampModel stamps;
  stamps.max_age = config.max_measurement_age;
  Clock clock;
  Desc desc;
  for (std::uint64_t k = 0; k < inputs; ++k) {
    *progress = k;
    ++tally.inputs;
    desc.clear();
    if (k % 2000 == 1999 || (stamps.has_newest && stamps.newest > clock.t + 1.0)) {
      ArmSupervisor::configure(config, model, &sup, &why);  // a fresh one (the harness may allocate)
      stamps.reset();
      clock.t = r.uniform(0.0, 100.0);
    }
    // Slow, safe motion away from the limits and a moderate command.
    for (int i = 0; i < n; ++i) {
      in.q[i] = r.uniform(-1.0, 1.0);
      in.qd[i] = r.uniform(-0.05, 0.05);
      in.tau_command[i] = r.uniform(-0.5, 0.5) * effort[i];
    }
    in.estop = false;
    in.reset = r.chance(0.05);
    clock.tick(r, stamps, &in.t, &in.stamp);
    bool out_wrong = false;
    const int mutations = r.chance(0.5) ? 0 : 1 + r.below(2);
    for (int m = 0; m < mutations; ++m) {
      const bool nonfinite = r.chance(0.5);
      switch (r.below(9)) {
        case 0: poke(r, in.q.data(), static_cast<int>(in.q.size()), nonfinite, desc, "q"); break;
        case 1: poke(r, in.qd.data(), static_cast<int>(in.qd.size()), nonfinite, desc, "qd"); break;
        case 2: poke(r, in.tau_command.data(), static_cast<int>(in.tau_command.size()), nonfinite, desc, "tau_command"); break;
        case 3: case 4: mutate_time(r, stamps.max_age, stamps, &in.t, &in.stamp, desc); break;
        case 5: {
          Eigen::VectorXd* fields[] = {&in.q, &in.qd, &in.tau_command};
          static const char* names[] = {"q", "qd", "tau_command"};
          const int f = r.below(3);
          if (fields[f]->size() == n) wrong.apply(r, *fields[f], desc, names[f]);
          break;
        }
        case 6:
          out_wrong = true;
          desc.add("output tau of size %d", n + 1);
          break;
        case 7:
          in.estop = true;
          desc.add("estop");
          break;
        default:
          in.tau_command.setConstant(extreme_value(r));
          desc.add("tau_command all = %.17g", in.tau_command.size() ? in.tau_command[0] : 0.0);
          break;
      }
    }
    const bool meas_ok = in.q.size() == n && in.qd.size() == n && in.q.allFinite() &&
                         in.qd.allFinite() && stamps.fresh(in.t, in.stamp);
    bool command_bad = in.tau_command.size() != n || !in.tau_command.allFinite();
    if (!command_bad)
      for (int i = 0; i < n; ++i)
        command_bad |= std::abs(in.tau_command[i]) > config.peak_trip_ratio * effort[i];
    const bool bad = out_wrong || !meas_ok || command_bad || in.estop;
    tally.bad_inputs += bad;
    if (out_wrong) out.tau.swap(tau_big);
    const Status s = sup.step(in, out);
    if (out_wrong) out.tau.swap(tau_big);
    wrong.undo();
    if (!out_wrong && meas_ok) stamps.accept(in.stamp);
    if (s != out.status) tally.fail(k, desc, &tally.bad_outputs, "returned %s, out.status %s", to_string(s), to_string(out.status));
    if (!out_wrong) {
      if (!within_effort(out.tau, effort))
        tally.fail(k, desc, &tally.bad_outputs, "tau not finite or beyond effort (status %s)", to_string(s));
      if (!out.thermal.allFinite() || !std::isfinite(out.stop_time))
        tally.fail(k, desc, &tally.bad_outputs, "thermal or stop_time not finite");
    }
    if (bad && !failed(s)) tally.fail(k, desc, &tally.missed_status, "bad input answered %s", to_string(s));
  }
  return tally;
}

}  // namespace kiloloop::fuzz
