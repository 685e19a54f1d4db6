"""SIL rig for arms: the MuJoCo plant built from a robot file + the 1 kHz loop + video.

One shape for every family (plant / rig / adapter / scenario): this file builds the plant from
the robot (only the controlled chain actuated, everything else welded, meshes resolved) and runs
the loop (what the scenarios derive from the plant's geometry: scenarios/arm_targets.py); the
adapters (sil/arm_adapters.py) map measurements onto one compiled controller; the scenarios
script the motion and judge the log. No control logic here.
"""
from __future__ import annotations

import numpy as np

import kiloloop as kl

from ..errors import InputError, configuring
from ..robot import arm as arm_defaults
from . import native as native_loop
from .log import SignalLog
from .loop import LoopSettings, run_loop
from .plant import MujocoPlant
from .video import maybe_recorder


def build_plant(robot, *, scene=None, visual: bool = False, timestep=None, damping=None,
                frictionloss=None, armature=None) -> MujocoPlant:
    """The MuJoCo plant of an arm's robot file, resting at the derived start pose."""
    model = robot.model()
    sim = robot.sim
    sim.setdefault("ee", {}).setdefault("body", robot.section("chain")["tip"])
    plant = MujocoPlant(robot.urdf, sim, timestep=timestep, damping=damping,
                        frictionloss=frictionloss, armature=armature, scene=scene,
                        joints=list(model.joint_names),
                        locked=robot.section("chain").get("locked", {}),
                        package_dirs=robot.package_dirs, visual=visual)
    plant.q0 = arm_defaults.start_pose(robot, model)
    plant.reset()
    return plant


class ArmRig:
    """Plant + model + loop for one arm robot file."""

    def __init__(self, robot, *, scene=None, video: str | None = None, **plant_kwargs):
        self.robot = robot
        self.model = robot.model()
        self.plant = build_plant(robot, scene=scene, visual=bool(video), **plant_kwargs)
        self.video_path = video
        # Both loops step whole physics steps per 1 ms tick: refuse any other timestep now.
        LoopSettings().substeps(self.plant.model.opt.timestep)

    def T_world_root(self) -> np.ndarray:
        """(4, 4) pose of the chain's root link in MuJoCo's world (fixed base: constant)."""
        m, d = self.plant.model, self.plant.data
        b = m.body(self.model.root_name).id
        T = np.eye(4)
        T[:3, :3], T[:3, 3] = d.xmat[b].reshape(3, 3), d.xpos[b]
        return T

    def _camera_body(self) -> int:
        """The body the video's camera follows: the chain's root link."""
        return self.plant.model.body(self.model.root_name).id if self.model.root_name else 1

    def runs_natively(self, tick, observe=None, native: bool | None = True) -> bool:
        """Whether run() takes the native loop: asked for (native not False), built in
        (native.available()), a tick with a C++ twin and ground truth given as an Observe (or
        none); a video's frames are captured between its ticks."""
        return (native is not False and native_loop.available()
                and hasattr(tick, "native_adapter")
                and (observe is None or isinstance(observe, native_loop.Observe)))

    def run(self, tick, duration: float, *, delay_ticks: int = 0, observe=None,
            log: SignalLog | None = None, native: bool | None = True,
            nonideal: native_loop.NonIdeal | None = None) -> SignalLog:
        """The closed loop for `duration` [s]: natively when runs_natively(), else per tick in
        Python; both give the same log (tests/test_native_arm.py). nonideal: joint sensor and
        motor models (sil/native.py), the same C++ code in either loop."""
        if self.runs_natively(tick, observe, native):
            return native_loop.run(self.plant, tick.native_adapter(), duration, log,
                                   delay_ticks=delay_ticks, nonideal=nonideal,
                                   events=tick.native_events(), observe=observe,
                                   video=self.video_path, camera_body=self._camera_body())
        plant, step = self.plant, tick
        if nonideal is not None:
            # The same C++ sensor/motor models and streams as the native loop, called per tick.
            plant = native_loop.noisy_plant(self.plant, nonideal)
            motor = nonideal.motor(self.plant.nq)

            def step(m, lg):
                return motor.push(tick(m, lg))
        recorder = maybe_recorder(self.video_path, self.plant.model, body=self._camera_body())

        def watch(_p, lg):
            # Ground truth from the plant itself, never through the sensor model.
            if observe is not None:
                observe(self.plant, lg)
            if recorder is not None:
                recorder.capture(self.plant.data)

        try:
            return run_loop(plant, step, LoopSettings(duration=duration,
                                                      delay_ticks=delay_ticks),
                            log=log, observe=watch)
        finally:
            if recorder is not None:
                recorder.close()


def joint_config(robot, model, q, delay_ticks: int = 0, config=None,
                 law: str = "computed_torque"):
    """The joint controller's config from the robot file: gains (bandwidth; on M(q) for
    pd_gravity), measurement age (plus the measurement delay), compensated friction."""
    c = config or (kl.ComputedTorqueConfig() if law == "computed_torque"
                   else kl.JointPdGravityConfig())
    c.kp, c.kd = arm_defaults.joint_gains(robot, model, law, q)
    age = float(arm_defaults.controller_settings(robot)["max_measurement_age"])
    c.max_measurement_age = age + delay_ticks * 0.001
    c.friction = arm_defaults.joint_friction(robot, model)
    return c


def controller(robot, model, law: str, q, *, delay_ticks: int = 0, config=None):
    """A compiled joint controller with gains derived from the robot file (robot/arm.py)."""
    classes = {"computed_torque": kl.ComputedTorqueController,
               "pd_gravity": kl.JointPdGravityController}
    if law not in classes:
        raise InputError(f"controller: expected 'computed_torque' or 'pd_gravity', got {law!r}")
    config = joint_config(robot, model, q, delay_ticks, config, law)
    with configuring(f"{robot.name} {law} controller"):
        return classes[law](model, config)
