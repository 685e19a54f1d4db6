"""The arm family's references: each names one compiled controller and what it follows, and
builds the C++ adapter (cpp/sil/arm_adapters.hpp) that maps the measurement y = [q; qd] and the
reference onto that controller's input every tick, in the native loop. Glue only: no control
logic, no robot constants.

    rig.run(4.5, JointTracking(controller, trajectory), observe=native.Observe("q_true", "ee"))
"""
from __future__ import annotations

from . import arm_scene, native
from . import events as ev


class JointTracking:
    """A joint controller (computed torque, PD + gravity) on a joint trajectory (quintic or
    trapezoid). Logs q, qd, q_ref, tau, status."""

    def __init__(self, controller, trajectory):
        self.controller, self.trajectory = controller, trajectory

    def native_adapter(self):
        return native.joint_tracking_adapter(self.controller, self.trajectory)

    def native_events(self) -> list:
        return []


class CartesianTracking:
    """The Cartesian tracking controller (differential IK + computed torque) on a CartesianLine.
    Logs q, q_ref, tau, pose_ref, ik_error, status."""

    def __init__(self, controller, line):
        self.controller, self.line = controller, line

    def native_adapter(self):
        return native.cartesian_adapter(self.controller, self.line)

    def native_events(self) -> list:
        return []


class Supervised:
    """Trajectory -> computed torque -> the arm supervisor -> motors, the e-stop pressed at
    t_estop [s]. Logs q, qd, q_ref, tau, mode, status, manipulability."""

    def __init__(self, controller, supervisor, trajectory, t_estop):
        self.c, self.s, self.traj, self.t_estop = controller, supervisor, trajectory, t_estop

    def native_adapter(self):
        return native.supervised_adapter(self.c, self.s, self.traj)

    def native_events(self) -> list:
        return [(float(self.t_estop), ev.ESTOP, [1.0])]


def _quintic(s):
    """Rest-to-rest blend on s in [0, 1]: value, first and second derivative w.r.t. s."""
    s = min(max(s, 0.0), 1.0)
    return (10 * s**3 - 15 * s**4 + 6 * s**5, 30 * s**2 - 60 * s**3 + 30 * s**4,
            60 * s - 180 * s**2 + 120 * s**3)


class PressTick:
    """Maps measurement, force sensor and the slide reference onto the controller (glue only)."""

    def __init__(self, controller, plant, tip, p0, R0, settings):
        self.c, self.plant, self.tip, self.settings = controller, plant, tip, settings
        self.input, self.output = controller.make_input(), controller.make_output()
        self.p0 = p0
        self.input.R_ref = R0
        self.input.wrench_ref = np.array([0.0, 0.0, -settings["force"], 0.0, 0.0, 0.0])

    def reference(self, t):
        st = self.settings
        s, ds, dds = _quintic((t - st["settle"]) / st["slide_time"])
        T = st["slide_time"]
        return (self.p0[0] + st["slide"] * s, st["slide"] * ds / T, st["slide"] * dds / T**2)

    def __call__(self, m: Measurement, log: SignalLog) -> np.ndarray:
        inp = self.input
        inp.t, inp.stamp = m.t, m.stamp
        inp.q[:], inp.qd[:] = m.q, m.qd
        x, xd, xdd = self.reference(m.t)
        inp.p_ref[:] = [x, self.p0[1], self.p0[2]]
        inp.twist_ref[0], inp.accel_ref[0] = xd, xdd
        force = arm_scene.tip_force_world(self.plant, self.tip)  # sampled with q (same stamp)
        inp.wrench_measured[:3] = force
        status = self.c.step(inp, self.output)
        log.record("x_ref", x)
        log.record("force", force)
        log.record("tau", self.output.tau)
        log.record("status", int(status))
        return self.output.tau.copy()
