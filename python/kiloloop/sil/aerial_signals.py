"""What the aerial rig's two loops (native, per tick in Python) share as data: event actions
(Push at the vehicle's CoM, RotorFault), the wind (Wind: settings of the C++ WindDrag), the sensor
and motor models over the flat signal vectors (AerialSignals: the C++ SensorModel, AttitudeNoise,
MotorModel), and the reference table (one row per tick in cpp/sil/aerial_adapter.hpp's layout).
SI units; quaternions w, x, y, z."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

import kiloloop as kl

from ..errors import InputError
from . import native as native_loop
from .timing import whole_periods

CONTROL_DT = 0.001  # [s]


# Event actions and disturbances given as data: both loops understand them (the native one as
# C++ events and models, the per-tick one through the same C++ code where it draws noise).
@dataclass
class Push:
    """Event action: a constant world-frame force (3,) [N] at the vehicle's centre of mass (the
    base body's subtree CoM, as AerialPlant.apply_force(force, plant.com())) for duration [s],
    whole physics steps rounded half up."""

    force: np.ndarray
    duration: float


@dataclass
class RotorFault:
    """Event action: rotor `rotor` (robot file order) at `efficiency` (thrust and drag torque) from
    then on (AerialPlant.set_efficiency: writes the plant's model)."""

    rotor: int
    efficiency: float

    def __call__(self, plant) -> None:
        plant.set_efficiency(self.rotor, self.efficiency)


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


class AerialSignals:
    """The rig's sensor and motor models over the flat vectors both loops share:
    y = [position (3); velocity (3); gyro (3); accel (3); quat (4); q (nq); qd (nq)] (plant order),
    u = [thrust (n); tau (nq)]. One C++ SensorModel stream for the white noise (one normal per
    element of y per tick) and quantization, one AttitudeNoise stream for the attitude estimate,
    the C++ MotorModel for the transport delay (the first command held until it arrives)."""

    def __init__(self, settings, seed, n_rotors: int, nq: int):
        """settings: an AerialRigSettings (nonideal, position_sigma, velocity_sigma)."""
        ni = settings.nonideal
        ni.validate()
        if ni.enabled and ni.velocity_from_encoder_diff:
            raise InputError("aerial rig: velocity_from_encoder_diff is not modelled")
        on = ni.enabled
        self.seed = int(seed) if seed is not None else 0
        self.n, self.nq, self.size = n_rotors, nq, 16 + 2 * nq
        noise = [settings.position_sigma] * 3 + [settings.velocity_sigma] * 3 + \
            [ni.gyro_sigma] * 3 + [ni.accel_sigma] * 3 + [0.0] * (4 + 2 * nq)
        self.sigma = noise if on and any(s > 0 for s in noise) else []
        self.quantum = ([0.0] * 16 + [ni.encoder_resolution] * nq + [0.0] * nq
                        if on and ni.encoder_resolution > 0 and nq else [])
        self.quat_sigma = float(ni.quat_sigma) if on else 0.0
        # Whole ticks, half up, as nonideal.MotorDelay.
        self.motor_delay_ticks = (whole_periods(ni.motor_delay)
                                  if on else 0)

    def sensor(self):
        return native_loop._native.SensorModel(self.sigma, self.quantum, self.seed, self.size)

    def stages(self) -> list:
        # A second stream for the attitude noise keeps the white noise's stream seed-stable.
        return ([native_loop._native.AttitudeNoise(12, self.quat_sigma, self.seed + 1_000_003,
                                                   self.size)] if self.quat_sigma > 0 else [])

    def motor(self):
        return native_loop._native.MotorModel(self.motor_delay_ticks, 0.0, CONTROL_DT,
                                              self.n + self.nq, [], hold_first=True)


# The reference row of the aerial adapter (cpp/sil/aerial_adapter.hpp, Ref): name, width.
REFERENCE_FIELDS = (("position_ref", 3), ("velocity_ref", 3), ("acceleration_ref", 3),
                    ("yaw_ref", 1), ("flight_mode", 1), ("quat_ref", 4), ("arm_mode", 1),
                    ("ee_position_ref", 3), ("ee_velocity_ref", 3))
ARM_REFERENCE_FIELDS = ("q_ref", "qd_ref", "qdd_ref")
REFERENCE_WIDTH = sum(w for _, w in REFERENCE_FIELDS)  # the arm's 3 nq columns follow


def reference_table(controller, command, ticks: int) -> np.ndarray:
    """(ticks, 22 + 3 nq) the references command(t, input) sets at each tick t = k dt, sampled
    on one input as the per-tick loop did (a field a command leaves alone keeps its last value).
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


def _load_references(inp, row: np.ndarray, nq: int) -> None:
    """The per-tick loop's side of the adapter's load_references: row -> input fields."""
    inp.position_ref[:], inp.velocity_ref[:], inp.acceleration_ref[:] = row[0:3], row[3:6], row[6:9]
    inp.yaw_ref = float(row[9])
    inp.flight_mode = kl.FlightMode.ATTITUDE if row[10] != 0 else kl.FlightMode.POSITION
    inp.quat_ref[:] = row[11:15]
    inp.arm_mode = kl.ArmMode.END_EFFECTOR if row[15] != 0 else kl.ArmMode.JOINTS
    inp.ee_position_ref[:], inp.ee_velocity_ref[:] = row[16:19], row[19:22]
    if nq:
        inp.q_ref[:], inp.qd_ref[:], inp.qdd_ref[:] = (row[22:22 + nq], row[22 + nq:22 + 2 * nq],
                                                       row[22 + 2 * nq:22 + 3 * nq])


def _torque_at(point, xipos, f) -> np.ndarray:
    """(point - xipos) x f in cpp/sil/disturbance.hpp torque_at's operation order."""
    r = point - xipos
    return np.array([r[1] * f[2] - r[2] * f[1], r[2] * f[0] - r[0] * f[2],
                     r[0] * f[1] - r[1] * f[0]])
