"""The arm family's references: each names one compiled controller and what it follows, and
builds the C++ adapter (cpp/sil/arm_adapters.hpp) that maps the measurement y = [q; qd] and the
reference onto that controller's input every tick, in the native loop. Glue only: no control
logic, no robot constants.

    rig.run(4.5, JointTracking(controller, trajectory), observe=native.Observe("q_true", "ee"))

A reference may ask for more of the plant's sensors than [q; qd] (`extra_measurement(plant)`:
sensordata addresses appended to y, untouched by the noise models): Press reads its tool's force.
"""
from __future__ import annotations

from . import native
from . import events as ev


class JointTracking:
    """A joint controller (computed torque, PD + gravity) on a joint trajectory (quintic or
    trapezoid). Logs q, qd, q_ref, tau, status."""

    def __init__(self, controller: object, trajectory: object) -> None:
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


class Press:
    """A Cartesian torque controller (hybrid force/position, or impedance) pressing the tool on
    a table with `force` [N] while its reference slides `slide` [m] along x on a quintic after
    `settle` [s] over `slide_time` [s] (cpp/sil/press_adapter.hpp). The tool's force sensor and
    orientation (arm_scene.ToolTip) follow [q; qd] in the measurement. Logs x_ref, force (world)
    [N], tau, status, q."""

    def __init__(self, controller, tip, p0, R0, force: float, settle: float, slide: float,
                 slide_time: float):
        self.controller, self.tip = controller, tip
        self.p0, self.R0 = p0, R0
        self.force, self.settle, self.slide, self.slide_time = force, settle, slide, slide_time

    def extra_measurement(self, plant) -> list[int]:
        return self.tip.measurement_addresses(plant.model)

    def native_adapter(self):
        return native.press_adapter(self.controller, self.p0, self.R0, float(self.force),
                                    float(self.settle), float(self.slide), float(self.slide_time))

    def native_events(self) -> list:
        return []
