"""The operating point a loop is analysed at: a scenario's rig (its robot, settings and
controller, sil/rig.py) holding still (an arm at its start pose, a quadruped standing, a
multirotor hovering), with the signal chain's noise and quantization off and its delays, lags,
stages and saturation kept. Noise is no part of a loop's linear response; quantization would
swallow the small perturbations the linearization differences.

Every experiment (an injection run, each differenced controller step) starts from the same plant
state with a fresh controller of the same configuration and runs `settle` [s] in the native loop
first, so each reaches the same operating point bit for bit (the loop is deterministic).
"""
from __future__ import annotations

import dataclasses

import mujoco
import numpy as np

import kiloloop as kl

from ..errors import InputError
from ..sil.family import CONTROL_DT
from ..sil.timing import whole_periods

# The Signals fields that are noise or quantization (zeroed here), and the legged sensor stages'.
NOISE_FIELDS = ("q_sigma", "qd_sigma", "encoder_resolution", "gyro_sigma", "accel_sigma",
                "quat_sigma", "position_sigma", "velocity_sigma")
LEGGED_NOISE_FIELDS = ("gyro_noise_density", "gyro_bias_random_walk", "gyro_turn_on_bias",
                       "accel_noise_density", "accel_bias_random_walk", "accel_turn_on_bias",
                       "velocity_resolution")
SETTLE = 2.0  # [s] closed loop before an experiment: stood up, hovering, holding (measured: < 1 s)
MEMORY = 2.0  # [s] the controller chain's impulse response (margins/linearization.py)
# A quadruped with the realistic IMU estimates its attitude with a Kalman filter whose gains
# settle over seconds after the start and whose bias state decays over seconds: measured on
# quadruped-stand pitch, 2 s / 2 s left the linearization 1.2 dB and 7 deg off the injection
# below 10 rad/s; 10 s / 6 s: 0.17 dB, 1.1 deg (as with ideal sensors at 2 s / 2 s).
QUADRUPED_SETTLE, QUADRUPED_MEMORY = 10.0, 6.0


@dataclasses.dataclass
class OperatingPoint:
    """rig: the scenario's Rig, noise off; fresh(): a (reference, adapter) pair on a new
    controller of the rig's configuration; settle [s]; memory [s] of the controller chain's
    impulse response."""

    rig: object
    fresh: object
    settle: float = SETTLE
    memory: float = MEMORY

    @property
    def settle_ticks(self) -> int:
        return whole_periods(self.settle, CONTROL_DT)

    def rollout(self, ticks: int, probes=()):
        """A native Rollout of settle + `ticks` ticks from the plant's start state on its own
        MjData (returned with it), a fresh controller, the rig's (noise-free) signal chain."""
        reference, adapter = self.fresh()
        data = mujoco.MjData(self.rig.plant.model)
        total = (self.settle_ticks + int(ticks)) * CONTROL_DT
        r = self.rig.rollout(total, reference, data=data, probes=list(probes), adapter=adapter)
        return r, data


def quiet(signals) -> None:
    """Noise and quantization off in place; delays, lags, stages and limits kept."""
    for name in NOISE_FIELDS:
        setattr(signals, name, 0.0)
    if signals.legged_sensors is not None:
        signals.legged_sensors = dataclasses.replace(
            signals.legged_sensors, **{k: 0.0 for k in LEGGED_NOISE_FIELDS})


def _arm(robot, settings, seed):
    from ..scenarios.arm_controllers import controller
    from ..scenarios.arm_targets import work_pose
    from ..sil.arm_adapters import JointTracking
    from ..sil.rig import Rig
    from ..sil.signals import Signals

    plant_only = {k: None if settings.get(k) in (None, "", "none") else float(settings[k])
                  for k in ("damping", "frictionloss", "armature")}
    delay = float(settings.get("measurement_delay", 0.0))
    signals = Signals(measurement_delay=delay, motor_delay=float(settings.get("motor_delay", 0.0)),
                      motor_time_constant=float(settings.get("motor_time_constant", 0.0)))
    rig = Rig(robot, signals, seed=seed, physics_dt=settings.get("physics_dt", 0.001), **plant_only)
    q0 = (np.asarray(settings["q_start"], float) if len(settings.get("q_start", []))
          else work_pose(robot, rig.model, rig.plant))
    rig.plant.q0 = q0
    rig.plant.reset()
    law = settings.get("controller", "computed_torque")
    hold = kl.QuinticTrajectory(np.vstack([q0, q0]), np.array([0.0, 1.0]))

    def fresh():
        reference = JointTracking(controller(robot, rig.model, law, q0, measurement_delay=delay),
                                  hold)
        return reference, reference.native_adapter()
    return OperatingPoint(rig, fresh)


def _quadruped(robot, settings, seed):
    from ..robot.quadruped import controller_config
    from ..scenarios.quadruped_settings import design_delay, rig_from_settings
    from ..sil.quadruped_family import stand_command

    config = controller_config(robot, actuation_delay=design_delay(settings))
    if float(settings.get("body_height", 0.0)) > 0:
        config.body_height = float(settings["body_height"])
    rig = rig_from_settings(settings, seed, config=config, robot=robot)
    parts = rig.parts

    def fresh():
        command = stand_command()
        return command, rig.adapter(command, kl.QuadrupedController(parts.model, parts.config))
    return OperatingPoint(rig, fresh, QUADRUPED_SETTLE, QUADRUPED_MEMORY)


def _aerial(robot, settings, seed):
    from ..scenarios.aerial_metrics import hold
    from ..scenarios.aerial_settings import rig_from_settings

    rig = rig_from_settings(settings, seed, robot=robot)
    parts = rig.parts

    def fresh():
        reference = hold(rig)
        return reference, rig.adapter(reference, kl.AerialController(parts.model, parts.config))
    return OperatingPoint(rig, fresh)


BUILDERS = {"arm": _arm, "quadruped": _quadruped, "aerial": _aerial}


def operating_point(robot, settings: dict, seed: int = 0) -> OperatingPoint:
    """The operating point of a scenario's settings on `robot` (a loaded kl.Robot)."""
    if robot.kind not in BUILDERS:
        raise InputError(f"no loops for a robot of kind {robot.kind!r}")
    op = BUILDERS[robot.kind](robot, dict(settings), int(seed))
    quiet(op.rig.signals)
    return op
