// Cartesian torque controllers (impedance, hybrid force/position) on the UR5.
#include <cmath>

#include <Eigen/Geometry>

#include "fuzz_models.hpp"
#include "kiloloop/control/cartesian_impedance.hpp"
#include "kiloloop/control/hybrid_force_position.hpp"
#include "kiloloop/kinematics/rigid_check.hpp"

namespace kiloloop::fuzz {
namespace {

Eigen::Matrix3d random_rotation(Rng& r) {
  Eigen::Quaterniond q(r.uniform(-1, 1), r.uniform(-1, 1), r.uniform(-1, 1), r.uniform(-1, 1));
  if (q.norm() < 1e-3) q = Eigen::Quaterniond::Identity();
  return q.normalized().toRotationMatrix();
}

template <class Controller, class Config>
Tally run(const char* name, bool uses_measured_wrench, std::uint64_t seed, std::uint64_t inputs,
          volatile std::uint64_t* progress) {
  Tally tally;
  tally.target = name;
  Rng r(seed * 0xC2B2AE35ull + 11);
  const RobotModelPtr model = load_model("ur5/ur5.urdf");
  Controller ctrl;
  std::string why;
  Config config;
  if (failed(Controller::configure(config, model, &ctrl, &why))) std::exit(5);
  const int n = ctrl.nq();
  const Eigen::VectorXd& effort = model->effort_limit();
  CartesianControlInput in = ctrl.make_input();
  CartesianControlOutput out = ctrl.make_output();
  Eigen::VectorXd tau_small = Eigen::VectorXd::Zero(n + 1);
  WrongSize wrong(n);
  StampModel stamps;
  stamps.max_age = config.common.max_measurement_age;
  Clock clock;
  Desc desc;
  for (std::uint64_t k = 0; k < inputs; ++k) {
    *progress = k;
    ++tally.inputs;
    desc.clear();
    if (k % 5000 == 4999 || (stamps.has_newest && stamps.newest > clock.t + 1.0)) {
      ctrl.reset();
      stamps.reset();
      clock.t = r.uniform(0.0, 100.0);
    }
    for (int i = 0; i < n; ++i) in.q[i] = r.uniform(-3.0, 3.0), in.qd[i] = r.uniform(-2.0, 2.0);
    for (int i = 0; i < 3; ++i) in.p_ref[i] = r.uniform(-0.8, 0.8);
    in.R_ref = random_rotation(r);
    for (int i = 0; i < 6; ++i) {
      in.twist_ref[i] = r.uniform(-0.5, 0.5);
      in.accel_ref[i] = r.uniform(-2.0, 2.0);
      in.wrench_ref[i] = r.uniform(-20.0, 20.0);
      in.wrench_measured[i] = r.uniform(-20.0, 20.0);
    }
    clock.tick(r, stamps, &in.t, &in.stamp);
    bool out_wrong = false;
    const int mutations = r.chance(0.3) ? 0 : 1 + r.below(3);
    for (int m = 0; m < mutations; ++m) {
      const bool nonfinite = r.chance(0.5);
      switch (r.below(13)) {
        case 0: poke(r, in.q.data(), static_cast<int>(in.q.size()), nonfinite, desc, "q"); break;
        case 1: poke(r, in.qd.data(), static_cast<int>(in.qd.size()), nonfinite, desc, "qd"); break;
        case 2: poke(r, in.p_ref.data(), 3, nonfinite, desc, "p_ref"); break;
        case 3: poke(r, in.R_ref.data(), 9, nonfinite, desc, "R_ref"); break;
        case 4: poke(r, in.twist_ref.data(), 6, nonfinite, desc, "twist_ref"); break;
        case 5: poke(r, in.accel_ref.data(), 6, nonfinite, desc, "accel_ref"); break;
        case 6: poke(r, in.wrench_ref.data(), 6, nonfinite, desc, "wrench_ref"); break;
        case 7: poke(r, in.wrench_measured.data(), 6, nonfinite, desc, "wrench_measured"); break;
        case 8: case 9: mutate_time(r, stamps.max_age, stamps, &in.t, &in.stamp, desc); break;
        case 10:
          if (r.chance(0.7)) {
            Eigen::VectorXd* f = r.chance(0.5) ? &in.q : &in.qd;
            if (f->size() == n) wrong.apply(r, *f, desc, f == &in.q ? "q" : "qd");
          } else {
            out_wrong = true;
            desc.add("output tau of size %d", n + 1);
          }
          break;
        case 11:  // huge but finite references
          in.p_ref.setConstant(r.chance(0.5) ? 1e300 : -1e300);
          in.accel_ref.setConstant(1e300);
          desc.add("p_ref, accel_ref ~ 1e300");
          break;
        default:
          in.wrench_ref.setConstant(extreme_value(r));
          desc.add("wrench_ref all = %.17g", in.wrench_ref[0]);
          break;
      }
    }
    const bool meas_ok = in.q.size() == n && in.qd.size() == n && in.q.allFinite() &&
                         in.qd.allFinite() && stamps.fresh(in.t, in.stamp);
    const bool ref_ok = in.p_ref.allFinite() && is_rotation(in.R_ref) && in.twist_ref.allFinite() &&
                        in.accel_ref.allFinite() && in.wrench_ref.allFinite();
    const bool wrench_ok = !uses_measured_wrench || in.wrench_measured.allFinite();
    const bool bad = out_wrong || !meas_ok || !ref_ok || !wrench_ok;
    tally.bad_inputs += bad;
    if (out_wrong) out.tau.swap(tau_small);
    const Status s = ctrl.step(in, out);
    if (out_wrong) out.tau.swap(tau_small);
    wrong.undo();
    if (!out_wrong && meas_ok) stamps.accept(in.stamp);
    if (s != out.status) tally.fail(k, desc, &tally.bad_outputs, "returned %s, out.status %s", to_string(s), to_string(out.status));
    if (!out_wrong && !within_effort(out.tau, effort))
      tally.fail(k, desc, &tally.bad_outputs, "tau not finite or beyond effort (status %s)", to_string(s));
    if (!out.pose_error.allFinite() || !out.wrench_command.allFinite())
      tally.fail(k, desc, &tally.bad_outputs, "pose_error or wrench_command not finite");
    if (bad && !failed(s)) tally.fail(k, desc, &tally.missed_status, "bad input answered %s", to_string(s));
  }
  return tally;
}

}  // namespace

Tally fuzz_cartesian_impedance(std::uint64_t seed, std::uint64_t inputs, volatile std::uint64_t* progress) {
  return run<CartesianImpedanceController, CartesianImpedanceConfig>("cartesian_impedance", false,
                                                                       seed, inputs, progress);
}

Tally fuzz_hybrid_force_position(std::uint64_t seed, std::uint64_t inputs, volatile std::uint64_t* progress) {
  return run<HybridForcePositionController, HybridForcePositionConfig>("hybrid_force_position",
                                                                         true, seed, inputs, progress);
}

}  // namespace kiloloop::fuzz
