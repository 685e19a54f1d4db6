// Joint torque controllers (computed torque, PD + gravity) on the UR5: measurements, references,
// times and sizes corrupted at random over a stream of good ticks.
#include <cmath>

#include "fuzz_models.hpp"
#include "kiloloop/control/computed_torque.hpp"
#include "kiloloop/control/joint_pd_gravity.hpp"

namespace kiloloop::fuzz {
namespace {

template <class Controller, class Config>
Tally run(const char* name, std::uint64_t seed, std::uint64_t inputs, volatile std::uint64_t* progress) {
  Tally tally;
  tally.target = name;
  Rng r(seed * 0x9E3779B1ull + 7);
  const RobotModelPtr model = load_model("ur5/ur5.urdf");
  Controller ctrl;
  std::string why;
  Config config;
  if (failed(Controller::configure(config, model, &ctrl, &why))) std::exit(5);
  const int n = ctrl.nq();
  const Eigen::VectorXd& effort = model->effort_limit();
  JointControlInput in = ctrl.make_input();
  JointControlOutput out = ctrl.make_output();
  Eigen::VectorXd tau_small = Eigen::VectorXd::Zero(n - 1);
  WrongSize wrong(n);
  StampModel stamps;
  stamps.max_age = config.max_measurement_age;
  Clock clock;
  Desc desc;
  for (std::uint64_t k = 0; k < inputs; ++k) {
    *progress = k;
    ++tally.inputs;
    desc.clear();
    if (k % 5000 == 4999 || (stamps.has_newest && stamps.newest > clock.t + 1.0)) {
      ctrl.reset();  // a new run (also after a clock glitch was accepted)
      stamps.reset();
      clock.t = r.uniform(0.0, 100.0);
    }
    // A good tick: a posture within the limits, a reference near it.
    for (int i = 0; i < n; ++i) {
      in.q[i] = r.uniform(-3.0, 3.0);
      in.qd[i] = r.uniform(-2.0, 2.0);
      in.q_ref[i] = in.q[i] + r.uniform(-0.1, 0.1);
      in.qd_ref[i] = r.uniform(-1.0, 1.0);
      in.qdd_ref[i] = r.uniform(-5.0, 5.0);
    }
    clock.tick(r, stamps, &in.t, &in.stamp);
    bool out_wrong = false;
    const int mutations = r.chance(0.3) ? 0 : 1 + r.below(3);
    for (int m = 0; m < mutations; ++m) {
      const int what = r.below(12);
      const bool nonfinite = r.chance(0.5);
      switch (what) {
        case 0: poke(r, in.q.data(), static_cast<int>(in.q.size()), nonfinite, desc, "q"); break;
        case 1: poke(r, in.qd.data(), static_cast<int>(in.qd.size()), nonfinite, desc, "qd"); break;
        case 2: poke(r, in.q_ref.data(), static_cast<int>(in.q_ref.size()), nonfinite, desc, "q_ref"); break;
        case 3: poke(r, in.qd_ref.data(), static_cast<int>(in.qd_ref.size()), nonfinite, desc, "qd_ref"); break;
        case 4: poke(r, in.qdd_ref.data(), static_cast<int>(in.qdd_ref.size()), nonfinite, desc, "qdd_ref"); break;
        case 5: case 6: mutate_time(r, stamps.max_age, stamps, &in.t, &in.stamp, desc); break;
        case 7: {
          Eigen::VectorXd* fields[] = {&in.q, &in.qd, &in.q_ref, &in.qd_ref, &in.qdd_ref};
          static const char* names[] = {"q", "qd", "q_ref", "qd_ref", "qdd_ref"};
          const int f = r.below(5);
          if (fields[f]->size() == n) wrong.apply(r, *fields[f], desc, names[f]);
          break;
        }
        case 8:
          out_wrong = true;
          desc.add("output tau of size %d", n - 1);
          break;
        case 9:  // a good posture with huge references (size-agnostic: qd_ref may be resized)
          in.qd_ref.setConstant(r.uniform(-1.0, 1.0) * 1e300);
          desc.add("qd_ref all = %.17g", in.qd_ref.size() ? in.qd_ref[0] : 0.0);
          break;
        default:  // extreme everywhere in one vector
          in.q_ref.setConstant(extreme_value(r));
          desc.add("q_ref all = %.17g", in.q_ref.size() ? in.q_ref[0] : 0.0);
          break;
      }
    }
    // The contract's view of this input.
    const bool meas_ok = in.q.size() == n && in.qd.size() == n && in.q.allFinite() &&
                         in.qd.allFinite() && stamps.fresh(in.t, in.stamp);
    const bool ref_ok = in.q_ref.size() == n && in.qd_ref.size() == n && in.qdd_ref.size() == n &&
                        in.q_ref.allFinite() && in.qd_ref.allFinite() && in.qdd_ref.allFinite();
    const bool bad = out_wrong || !meas_ok || !ref_ok;
    tally.bad_inputs += bad;
    JointControlOutput* o = &out;
    if (out_wrong) out.tau.swap(tau_small);
    const Status s = ctrl.step(in, *o);
    if (out_wrong) out.tau.swap(tau_small);
    wrong.undo();
    if (!out_wrong && meas_ok) stamps.accept(in.stamp);
    if (s != out.status) tally.fail(k, desc, &tally.bad_outputs, "returned %s, out.status %s", to_string(s), to_string(out.status));
    if (!out_wrong && !within_effort(out.tau, effort))
      tally.fail(k, desc, &tally.bad_outputs, "tau not finite or beyond effort (status %s)", to_string(s));
    if (bad && !failed(s)) tally.fail(k, desc, &tally.missed_status, "bad input answered %s", to_string(s));
  }
  return tally;
}

}  // namespace

Tally fuzz_computed_torque(std::uint64_t seed, std::uint64_t inputs, volatile std::uint64_t* progress) {
  return run<ComputedTorqueController, ComputedTorqueConfig>("computed_torque", seed, inputs, progress);
}

Tally fuzz_joint_pd_gravity(std::uint64_t seed, std::uint64_t inputs, volatile std::uint64_t* progress) {
  return run<JointPdGravityController, JointPdGravityConfig>("joint_pd_gravity", seed, inputs, progress);
}

}  // namespace kiloloop::fuzz
