"""Adapters for the arm family: each maps the plant's measurement (and the scenario's reference)
onto one compiled controller's Input and its Output back onto the motors. Glue only: no control
logic, no robot constants. Shared by the arm scenarios (one SIL shape: plant / rig / adapter /
scenario).

A tick with `native_adapter()` also runs in the native loop (sil/native.py): its C++ twin
(cpp/sil/arm_adapters.cpp) makes the same calls on the same controller and reference objects and
logs the same signals; `native_events()` gives what the tick decides from time (the e-stop).
arm-press has no per-tick tick: its adapter is C++ only (cpp/sil/press_adapter.hpp,
native.press_adapter).
"""
from __future__ import annotations

import numpy as np

from . import native
from .log import SignalLog
from .loop import Measurement


class JointTrackingTick:
    """Maps a measurement and the trajectory sample onto the compiled controller (glue only)."""

    def __init__(self, controller, trajectory):
        self.controller, self.trajectory = controller, trajectory
        self.input, self.output = controller.make_input(), controller.make_output()

    def __call__(self, m: Measurement, log: SignalLog) -> np.ndarray:
        inp = self.input
        inp.t, inp.stamp = m.t, m.stamp
        inp.q[:], inp.qd[:] = m.q, m.qd
        self.trajectory.sample_into(m.t, inp.q_ref, inp.qd_ref, inp.qdd_ref)
        status = self.controller.step(inp, self.output)
        log.record("q", m.q)
        log.record("qd", m.qd)
        log.record("q_ref", inp.q_ref)
        log.record("tau", self.output.tau)
        log.record("status", int(status))
        return self.output.tau.copy()

    def native_adapter(self):
        return native.joint_tracking_adapter(self.controller, self.trajectory)

    def native_events(self) -> list:
        return []


class CartesianTick:
    """Maps a measurement and the line sample onto the compiled controller (glue only)."""

    def __init__(self, controller, line):
        self.controller, self.line = controller, line
        self.input, self.output = controller.make_input(), controller.make_output()

    def __call__(self, m: Measurement, log: SignalLog) -> np.ndarray:
        inp = self.input
        inp.t, inp.stamp = m.t, m.stamp
        inp.q[:], inp.qd[:] = m.q, m.qd
        self.line.sample_into(m.t, inp)
        status = self.controller.step(inp, self.output)
        log.record("q", m.q)
        log.record("q_ref", self.output.q_ref)
        log.record("tau", self.output.tau)
        log.record("pose_ref", inp.pose_ref)
        log.record("ik_error", self.output.task_error)
        log.record("status", int(status))
        return self.output.tau.copy()

    def native_adapter(self):
        return native.cartesian_adapter(self.controller, self.line)

    def native_events(self) -> list:
        return []


class SupervisedTick:
    """Trajectory -> computed torque -> supervisor -> motors (glue only)."""

    def __init__(self, controller, supervisor, trajectory, t_estop):
        self.c, self.s, self.traj, self.t_estop = controller, supervisor, trajectory, t_estop
        self.cin, self.cout = controller.make_input(), controller.make_output()
        self.sin, self.sout = supervisor.make_input(), supervisor.make_output()

    def __call__(self, m: Measurement, log: SignalLog) -> np.ndarray:
        cin, sin = self.cin, self.sin
        cin.t, cin.stamp = m.t, m.stamp
        cin.q[:], cin.qd[:] = m.q, m.qd
        self.traj.sample_into(m.t, cin.q_ref, cin.qd_ref, cin.qdd_ref)
        self.c.step(cin, self.cout)
        sin.t, sin.stamp = m.t, m.stamp
        sin.q[:], sin.qd[:] = m.q, m.qd
        sin.tau_command[:] = self.cout.tau
        sin.estop = m.t >= self.t_estop
        status = self.s.step(sin, self.sout)
        log.record("q", m.q)
        log.record("qd", m.qd)
        log.record("q_ref", cin.q_ref)
        log.record("tau", self.sout.tau)
        log.record("mode", int(self.sout.mode))
        log.record("status", int(status))
        log.record("manipulability", self.sout.singularity.manipulability)
        return self.sout.tau.copy()

    def native_adapter(self):
        return native.supervised_adapter(self.c, self.s, self.traj)

    def native_events(self) -> list:
        return [native.estop(self.t_estop)]
