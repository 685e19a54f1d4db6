"""A multirotor run's data beyond the rig's: the wind (Wind: settings of the C++ WindDrag
disturbance) and the reference table (one row per tick in cpp/sil/aerial_adapter.hpp's layout).
SI units; quaternions w, x, y, z."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from . import native as native_loop
from .timing import CONTROL_DT


@dataclass
class Wind:
    """Disturbance: steady wind plus seeded first-order gusts through quadratic drag at the
    vehicle's CoM (cpp/sil/wind_drag.hpp: the formula, the gust recursion, the seeded stream)."""

    steady: np.ndarray           # [m/s] world
    ramp: float                  # [s]
    gust_sigma: float            # [m/s]
    gust_tau: float              # [s]
    drag_area: float             # [m^2] CdA
    seed: int
    vertical_scale: float = 0.5  # vertical gusts are weaker near the ground
    air_density: float = 1.225   # [kg/m^3] sea level

    def model(self, plant):
        """A fresh C++ WindDrag for one run on this plant (it carries the gust state)."""
        return native_loop._native.WindDrag(
            plant._base_id, plant._free_d, np.asarray(self.steady, float), float(self.ramp),
            float(self.gust_sigma), float(self.gust_tau), float(self.vertical_scale),
            float(self.drag_area), float(self.air_density), CONTROL_DT, int(self.seed))


# The reference row of the aerial adapter (cpp/sil/aerial_adapter.hpp, Ref): name, width.
REFERENCE_FIELDS = (("position_ref", 3), ("velocity_ref", 3), ("acceleration_ref", 3),
                    ("yaw_ref", 1), ("flight_mode", 1), ("quat_ref", 4), ("arm_mode", 1),
                    ("ee_position_ref", 3), ("ee_velocity_ref", 3))
ARM_REFERENCE_FIELDS = ("q_ref", "qd_ref", "qdd_ref")
REFERENCE_WIDTH = sum(w for _, w in REFERENCE_FIELDS)  # the arm's 3 nq columns follow


def reference_table(controller, command, ticks: int) -> np.ndarray:
    """(ticks, 22 + 3 nq) the references command(t, input) sets at each tick t = k dt, sampled
    on one input (a field a command leaves alone keeps its last value).
    command must depend on t only (every scenario's does). A command with a `table(controller,
    ticks)` method gives the table itself (no per-tick Python)."""
    if hasattr(command, "table"):
        return np.ascontiguousarray(command.table(controller, ticks), dtype=float)
    inp = controller.make_input()
    nq = controller.nq
    table = np.empty((ticks, REFERENCE_WIDTH + 3 * nq))
    for k in range(ticks):
        command(k * CONTROL_DT, inp)
        table[k] = reference_row(inp, nq)
    return table


def reference_row(inp, nq: int) -> np.ndarray:
    """The input's references as one row of the adapter's table (AerialAdapter::Ref layout)."""
    return np.concatenate([np.asarray(inp.position_ref, float), inp.velocity_ref,
                           inp.acceleration_ref, [inp.yaw_ref, int(inp.flight_mode)],
                           inp.quat_ref, [int(inp.arm_mode)], inp.ee_position_ref,
                           inp.ee_velocity_ref, inp.q_ref, inp.qd_ref, inp.qdd_ref])
