// Cartesian tracking (differential IK + computed torque) on the UR5.
#include <cmath>

#include <Eigen/Geometry>

#include "fuzz_models.hpp"
#include "kiloloop/arm/cartesian_tracking.hpp"
#include "kiloloop/kinematics/rigid_check.hpp"

namespace kiloloop::fuzz {

Tally fuzz_cartesian_tracking(std::uint64_t seed, std::uint64_t inputs, volatile std::uint64_t* progress) {
  Tally tally;
  tally.target = "cartesian_tracking";
  Rng r(seed * 0x165667B1ull + 13);
  const RobotModelPtr model = load_model("ur5/ur5.urdf");
  CartesianTrackingController ctrl;
  std::string why;
  CartesianTrackingConfig config;
  if (failed(CartesianTrackingController::configure(config, model, &ctrl, &why))) std::exit(5);
  const int n = ctrl.nq();
  const Eigen::VectorXd& effort = model->effort_limit();
  CartesianTrackingInput in = ctrl.make_input();
  CartesianTrackingOutput out = ctrl.make_output();
  Eigen::VectorXd small = Eigen::VectorXd::Zero(n - 2);
  WrongSize wrong(n);
  StampModel stamps;
  stamps.max_age = config.joint.max_measurement_age;
  Clock clock;
  Desc desc;
  Eigen::Vector3d p_ref(0.4, 0.1, 0.4);
  for (std::uint64_t k = 0; k < inputs; ++k) {
    *progress = k;
    ++tally.inputs;
    desc.clear();
    if (k % 5000 == 4999 || (stamps.has_newest && stamps.newest > clock.t + 1.0)) {
      ctrl.reset();
      stamps.reset();
      clock.t = r.uniform(0.0, 100.0);
    }
    // A reference that wanders slowly; the measurement is anywhere (the plant is not simulated).
    for (int i = 0; i < 3; ++i) p_ref[i] = std::fmin(std::fmax(p_ref[i] + r.uniform(-0.002, 0.002), -0.7), 0.7);
    for (int i = 0; i < n; ++i) in.q[i] = r.uniform(-3.0, 3.0), in.qd[i] = r.uniform(-1.0, 1.0);
    in.pose_ref.setIdentity();
    in.pose_ref.topRightCorner<3, 1>() = p_ref;
    for (int i = 0; i < 6; ++i) in.twist_ref[i] = r.uniform(-0.1, 0.1);
    clock.tick(r, stamps, &in.t, &in.stamp);
    bool out_wrong = false;
    const int mutations = r.chance(0.3) ? 0 : 1 + r.below(3);
    for (int m = 0; m < mutations; ++m) {
      const bool nonfinite = r.chance(0.5);
      switch (r.below(9)) {
        case 0: poke(r, in.q.data(), static_cast<int>(in.q.size()), nonfinite, desc, "q"); break;
        case 1: poke(r, in.qd.data(), static_cast<int>(in.qd.size()), nonfinite, desc, "qd"); break;
        case 2: poke(r, in.pose_ref.data(), 16, nonfinite, desc, "pose_ref"); break;
        case 3: poke(r, in.twist_ref.data(), 6, nonfinite, desc, "twist_ref"); break;
        case 4: case 5: mutate_time(r, stamps.max_age, stamps, &in.t, &in.stamp, desc); break;
        case 6:
          if (r.chance(0.7)) {
            Eigen::VectorXd* f = r.chance(0.5) ? &in.q : &in.qd;
            if (f->size() == n) wrong.apply(r, *f, desc, f == &in.q ? "q" : "qd");
          } else {
            out_wrong = true;
            desc.add("output qd_ref of size %d", n - 2);
          }
          break;
        case 7:  // huge but finite references
          in.pose_ref.topRightCorner<3, 1>().setConstant(r.chance(0.5) ? 1e300 : -1e300);
          desc.add("pose_ref translation ~ 1e300");
          break;
        default:
          in.twist_ref.setConstant(extreme_value(r));
          desc.add("twist_ref all = %.17g", in.twist_ref[0]);
          break;
      }
    }
    const bool meas_ok = in.q.size() == n && in.qd.size() == n && in.q.allFinite() &&
                         in.qd.allFinite() && stamps.fresh(in.t, in.stamp);
    const bool ref_ok = is_rigid_transform(in.pose_ref) && in.twist_ref.allFinite();
    const bool bad = out_wrong || !meas_ok || !ref_ok;
    tally.bad_inputs += bad;
    if (out_wrong) out.qd_ref.swap(small);
    const Status s = ctrl.step(in, out);
    if (out_wrong) out.qd_ref.swap(small);
    wrong.undo();
    if (!out_wrong && meas_ok) stamps.accept(in.stamp);
    if (s != out.status) tally.fail(k, desc, &tally.bad_outputs, "returned %s, out.status %s", to_string(s), to_string(out.status));
    if (!out_wrong) {
      if (!within_effort(out.tau, effort))
        tally.fail(k, desc, &tally.bad_outputs, "tau not finite or beyond effort (status %s)", to_string(s));
      if (!out.q_ref.allFinite() || !out.qd_ref.allFinite() || !out.qdd_ref.allFinite() ||
          !out.task_error.allFinite() || !std::isfinite(out.manipulability))
        tally.fail(k, desc, &tally.bad_outputs, "a reference output is not finite (status %s)", to_string(s));
    }
    if (bad && !failed(s)) tally.fail(k, desc, &tally.missed_status, "bad input answered %s", to_string(s));
  }
  return tally;
}

}  // namespace kiloloop::fuzz
