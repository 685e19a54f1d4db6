#pragma once
// Scheduled events of a native SIL run, given as data: at the first tick whose time t >= time,
// the event fires (before that tick's controller step, as a scenario's per-tick Python check
// `t >= t_event` would). Kinds:
//   kEstop      payload {1 or 0}: the e-stop input pressed / released (adapters with a supervisor)
//   kReference  payload: an offset added to the reference from then on (joint adapters: (nq) [rad];
//               Cartesian: (3) [m] on the position), replacing any earlier offset; a quadruped:
//               the new command {gait, vx, vy, yaw rate} [-, m/s, m/s, rad/s]
//   kForce      payload {body id, fx, fy, fz, tx, ty, tz, duration [s]}: a wrench [N, N m] in the
//               world frame on that body's centre of mass (MuJoCo xfrc_applied) for duration,
//               rounded to whole physics steps (half up), from the tick it fires (as
//               FloatingBasePlant.apply_push: impulse = force x steps x timestep); an optional
//               9th entry 1 applies the force at the body's subtree centre of mass instead (a
//               vehicle's CoM: torque (CoM - body CoM) x f added, as AerialPlant.apply_force)
//   kGain       payload {actuator id, gain}: the actuator's gain (gainprm[0]) from then on (a
//               rotor's efficiency: thrust and drag torque). It writes the mjModel: rollouts
//               running at the same time need their own model copies.
#include <vector>

namespace kiloloop::sil {

enum class EventKind : int { kEstop = 0, kReference = 1, kForce = 2, kGain = 3 };

struct Event {
  double time = 0.0;  // [s]
  EventKind kind = EventKind::kEstop;
  std::vector<double> payload;
};

}  // namespace kiloloop::sil
