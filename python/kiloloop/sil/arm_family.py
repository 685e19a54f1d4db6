"""The arm family of the SIL rig (sil/rig.py), as data (sil/family.py): the MuJoCo plant of the robot
file's chain (only the chain actuated, everything else welded, meshes resolved; sil/plant.py), the
measurement y = [q (nq); qd (nq)] from its joint sensors (plus the sensors a reference asks for: a
tool's force), the command u = tau (nq). An arm's scenarios choose among several controllers
(computed torque, PD + gravity, Cartesian tracking, a supervisor, hybrid force/position): the
reference names its controller and its C++ adapter (sil/arm_adapters.py). No control logic here.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..robot import arm as arm_defaults
from . import events as ev
from . import native
from .plant import MujocoPlant
from .family import CONTROL_DT, Family, Measurement, Motor


@dataclass
class ArmParts:
    robot: object
    model: object            # kl.RobotModel of the chain
    plant: MujocoPlant
    controller: object = None  # the reference's (an arm scenario picks its law)

    def T_world_root(self) -> np.ndarray:
        """(4, 4) pose of the chain's root link in MuJoCo's world (fixed base: constant)."""
        m, d = self.plant.model, self.plant.data
        b = m.body(self.model.root_name).id
        T = np.eye(4)
        T[:3, :3], T[:3, 3] = d.xmat[b].reshape(3, 3), d.xpos[b]
        return T


def build_plant(robot, *, scene=None, visual: bool = False, timestep=None, damping=None,
                frictionloss=None, armature=None) -> MujocoPlant:
    """The MuJoCo plant of an arm's robot file, resting at the derived start pose."""
    model = robot.model()
    sim = robot.sim
    sim.setdefault("ee", {}).setdefault("body", robot.section("chain")["tip"])
    # The rotor inertia the controllers' gains account for (given or derived, robot/arm.py).
    sim.setdefault("joints", {})["armature"] = arm_defaults.armature(robot, model).tolist()
    plant = MujocoPlant(robot.urdf_doc, sim, timestep=timestep, damping=damping,
                        frictionloss=frictionloss, armature=armature, scene=scene,
                        joints=list(model.joint_names),
                        locked=robot.section("chain").get("locked", {}),
                        package_dirs=robot.package_dirs, visual=visual)
    plant.q0 = arm_defaults.start_pose(robot, model)
    plant.reset()
    return plant


def build(robot, signals, seed, options) -> ArmParts:
    """options: scene (fn(MjSpec): a table, a box, a tool), physics_dt [s], damping,
    frictionloss, armature (plant overrides of the robot file's [sim.joints]), visual."""
    options = dict(options)
    kwargs = {k: options.pop(k) for k in ("scene", "damping", "frictionloss", "armature",
                                         "visual") if k in options}
    if "physics_dt" in options:
        kwargs["timestep"] = options.pop("physics_dt")
    if options:
        raise TypeError(f"arm rig: unknown option(s) {', '.join(sorted(options))}")
    return ArmParts(robot=robot, model=robot.model(), plant=build_plant(robot, **kwargs))


def measurement(parts: ArmParts, signals, seed: int, reference) -> Measurement:
    """[q; qd] with encoder noise and quantization; a reference's extra sensordata addresses
    (`extra_measurement`, e.g. a tool's force and orientation) follow, untouched."""
    p, nq = parts.plant, parts.plant.nq
    extra = [int(a) for a in getattr(reference, "extra_measurement", lambda _p: [])(p)]
    addresses = [int(a) for a in p._pos_sens] + [int(a) for a in p._vel_sens] + extra
    s = signals
    # The arrays cover [q; qd] only: the extra entries pass untouched and draw no noise.
    sigma = ([s.on("q_sigma")] * nq + [s.on("qd_sigma")] * nq
             if s.on("q_sigma") > 0 or s.on("qd_sigma") > 0 else [])
    quantum = ([s.on("encoder_resolution")] * nq + [0.0] * nq
               if s.on("encoder_resolution") > 0 else [])
    return Measurement(addresses, [0] * len(addresses), sigma, quantum, [])


def motor(parts, signals) -> Motor:
    return Motor(delay_ticks=signals.ticks("motor_delay", CONTROL_DT),
                 time_constant=signals.on("motor_time_constant"))


def actuators(parts: ArmParts) -> list[int]:
    return [int(a) for a in parts.plant._act]


def adapter(parts, reference, controller, ticks: int):
    if controller is not None:
        raise InputError("an arm's reference names its own controller")
    return reference.native_adapter()


def reference_events(parts, reference) -> list:
    return list(reference.native_events())


def events(parts: ArmParts, timed) -> list:
    """Pushes (on the tool's body unless a body is named), e-stops, reference offsets."""
    p, out = parts.plant, []
    tip = int(p.model.site_bodyid[p.model.site(p.ee_site).id])
    for t, e in timed:
        if isinstance(e, ev.Push):
            named = isinstance(e.body, str)
            body = tip if e.body is None else (int(p.model.body(e.body).id) if named
                                               else int(e.body))
            out.append(ev.force_event(t, body, [*e.force, 0.0, 0.0, 0.0], e.duration))
        elif isinstance(e, ev.EStop):
            out.append((float(t), ev.ESTOP, [1.0 if e.pressed else 0.0]))
        elif isinstance(e, ev.ReferenceOffset):
            out.append((float(t), ev.REFERENCE, [float(x) for x in e.offset]))
        else:
            raise InputError(f"an arm run takes pushes, e-stops and reference offsets as "
                             f"events, not {type(e).__name__}")
    return out


def probes(parts: ArmParts, observe) -> list:
    """Ground truth the caller asks for: a native.Observe (q_true, qd_true, ee, ee_rot...)."""
    return [] if observe is None else observe.probes(parts.plant)


def stop(parts, condition) -> None:
    if condition is not None:
        raise InputError("an arm run has no stop condition")
    return None


def camera_body(parts: ArmParts) -> int:
    root = parts.model.root_name
    return int(parts.plant.model.body(root).id) if root else 1


FAMILY = Family(name="arm", build=build, measurement=measurement, motor=motor,
                actuators=actuators, adapter=adapter, reference_events=reference_events,
                events=events, probes=probes, stop=stop, camera_body=camera_body)
