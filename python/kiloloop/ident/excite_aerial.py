"""A multirotor's excitation run: hover with steps of the position (so of the attitude: a
horizontal step tilts the vehicle), of the height (the collective thrust) and of the yaw (the
rotors' drag torques), drawn from the seed, the arm held at its start pose; the robot file's
plant (rotors' thrust scale in [sim.rotors] efficiency, their lags, the arm's joints) and its
declared delay in the motor model.

Logged as a vehicle's logger has it: the commanded thrusts and arm torques, the IMU (gyro,
accelerometer, orientation) and motion capture (position, velocity), the arm's encoders. The
IMU is the plant's sensors without noise (the white-noise models are the scenarios' business;
the identification does not rely on their absence: they enter its target, not its regressor).
"""
from __future__ import annotations

import numpy as np

from ..sil import native
from ..sil.aerial_signals import reference_row
from ..sil.rig import Rig
from ..sil.signals import Signals
from .logged import keep

STEP_EVERY = 1.2     # [s] between steps
HORIZONTAL = 0.15    # [m] largest horizontal offset of a step
VERTICAL = 0.1      # [m] largest height offset
YAW = 0.3           # [rad] largest yaw (steps twice these tumble the aerial manipulator at 35 ms)

LOGGED = {"t": ("s", "time"), "thrust_cmd": ("N", "commanded rotor thrusts"),
          "tau": ("N m", "commanded arm torques"), "gyro": ("rad/s", "IMU angular velocity"),
          "accel": ("m/s^2", "IMU specific force"), "imu_quat": ("", "IMU orientation (w, x, y, z)"),
          "base_pos": ("m", "motion-capture position"), "base_vel": ("m/s", "motion-capture velocity"),
          "q": ("rad", "arm joint positions"), "qd": ("rad/s", "arm joint velocities")}


class Steps:
    """The reference: the hover point plus a seeded offset and yaw held for STEP_EVERY each."""

    def __init__(self, hover, q0, duration: float, seed: int):
        rng = np.random.default_rng(seed)
        n = int(np.ceil(duration / STEP_EVERY)) + 1
        self.hover, self.q0 = np.asarray(hover, float), np.asarray(q0, float)
        self.offsets = rng.uniform(-1, 1, size=(n, 3)) * [HORIZONTAL, HORIZONTAL, VERTICAL]
        self.yaws = rng.uniform(-YAW, YAW, size=n)
        self.offsets[0], self.yaws[0] = 0.0, 0.0

    def __call__(self, t, inp) -> None:
        i = min(int(t / STEP_EVERY), len(self.yaws) - 1)
        inp.position_ref[:] = self.hover + self.offsets[i]
        inp.yaw_ref = float(self.yaws[i])
        inp.q_ref[:] = self.q0

    def table(self, controller, ticks: int) -> np.ndarray:
        inp = controller.make_input()
        rows = []
        for k in range(ticks):
            self(k * 0.001, inp)
            rows.append(reference_row(inp, controller.nq))
        return np.array(rows)


def run(robot, duration: float, seed: int, delay: float, motor_lag: float):
    if motor_lag:
        from ..errors import InputError

        raise InputError("excite: a multirotor's rotor lags are its [[rotors]] time_constant")
    rig = Rig(robot, Signals(motor_delay=delay), seed=seed)
    p = rig.plant
    a = p._imu_adr
    probes = [("gyro", native._SENSOR, list(range(a["gyro"], a["gyro"] + 3))),
              ("accel", native._SENSOR, list(range(a["accel"], a["accel"] + 3))),
              ("imu_quat", native._SENSOR, list(range(a["quat"], a["quat"] + 4))),
              ("qd", native._SENSOR, [int(p._vel_sens[i]) for i in rig.to_ctrl])]
    command = Steps(rig.hover_pos.copy(), p.q0.copy()[rig.to_ctrl], duration, seed)
    log = rig.run(duration, command, probes=probes)
    if "diverged" in log:
        raise RuntimeError("excite: the vehicle diverged during the excitation")
    return keep(log, {k: v for k, v in LOGGED.items() if k in log})
