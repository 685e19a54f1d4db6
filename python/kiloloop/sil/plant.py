"""MuJoCo plant built at run time from a URDF plus a small TOML overlay (models/<robot>/sim.toml).

The URDF is the single source of truth for kinematics, inertia and limits; the overlay adds what
only the simulator needs: integrator, floor, joint damping/friction/armature, torque motors, an
end-effector site and joint sensors. All arrays are numpy, SI units, in URDF joint order.
"""
from __future__ import annotations

import tomllib

import mujoco
import numpy as np

# The [sim.*] defaults live with the robot-file schema, which reads them too.
from ..robot.sim_defaults import ARM as _DEFAULTS
from ..robot import urdf_doc
from ..robot.urdf_doc import UrdfDoc
from ..robot.urdf_joints import urdf_joints
from ..errors import InputError
from .mujoco_refusal import compile_spec
from .urdf_import import prepare_urdf, weld_joints

# mj_step1/mj_step2 do not support RK4, and the plant relies on the split (see step()).
_INTEGRATORS = {"euler": mujoco.mjtIntegrator.mjINT_EULER,
                "implicit": mujoco.mjtIntegrator.mjINT_IMPLICIT,
                "implicitfast": mujoco.mjtIntegrator.mjINT_IMPLICITFAST}


def load_overlay(overlay, defaults: dict = _DEFAULTS) -> dict:
    """The overlay (a sim.toml path, a dict of its sections, or None) merged over `defaults`."""
    if overlay is None:
        user = {}
    elif isinstance(overlay, dict):
        user = overlay
    else:
        with open(overlay, "rb") as f:
            user = tomllib.load(f)
    merged = {k: dict(v) for k, v in defaults.items()}
    for section, values in user.items():
        if section not in merged:
            raise InputError(f"overlay: unknown section [{section}]")
        merged[section].update(values)
    return merged


def per_joint(value, n: int, name: str) -> np.ndarray:
    arr = np.asarray(value, dtype=float)
    if arr.ndim == 0:
        arr = np.full(n, float(arr))
    if arr.shape != (n,) or not np.all(np.isfinite(arr)) or np.any(arr < 0):
        raise InputError(f"{name}: expected a non-negative scalar or a sequence of {n}, "
                         f"got {value!r}")
    return arr


def add_joints_and_motors(spec, joint_names, effort, jcfg: dict, actuators: dict) -> None:
    """Joint damping/friction/armature from the overlay, one torque motor per joint (ctrlrange =
    forcerange = +-effort) and jointpos/jointvel encoders named <joint>_pos, <joint>_vel."""
    n = len(joint_names)
    # None: keep what MuJoCo imported from the URDF's <dynamics damping friction> (0 without).
    damp, fric, arm = (None if jcfg[k] is None else per_joint(jcfg[k], n, k)
                       for k in ("damping", "frictionloss", "armature"))
    for i, name in enumerate(joint_names):
        joint = spec.joint(name)
        if damp is not None:
            joint.damping = [damp[i], 0.0, 0.0]  # MuJoCo 4: linear coefficient, then polynomial
        if fric is not None:
            joint.frictionloss = fric[i]
        if arm is not None:
            joint.armature = arm[i]
    if actuators["type"] != "motor":
        raise InputError(f"actuators.type: only 'motor' is supported, got {actuators['type']!r}")
    for name, e in zip(joint_names, effort):
        act = spec.add_actuator(name=name, target=name, trntype=mujoco.mjtTrn.mjTRN_JOINT)
        act.set_to_motor()
        if np.isfinite(e):
            act.ctrllimited = act.forcelimited = mujoco.mjtLimited.mjLIMITED_TRUE
            act.ctrlrange = act.forcerange = [-e, e]
        spec.add_sensor(name=f"{name}_pos", type=mujoco.mjtSensor.mjSENS_JOINTPOS,
                        objtype=mujoco.mjtObj.mjOBJ_JOINT, objname=name)
        spec.add_sensor(name=f"{name}_vel", type=mujoco.mjtSensor.mjSENS_JOINTVEL,
                        objtype=mujoco.mjtObj.mjOBJ_JOINT, objname=name)


# Dry friction that sticks: MuJoCo's friction loss is a soft constraint, and with its default
# softness (solref 0.02 s, solimp 0.9) a joint held at 90 % of its friction creeps (xArm7's wrist,
# 0.03 kg m^2 with its rotor, 1 N m: 0.028 rad/s), so an arm held still never stops. Where a joint
# has friction loss, its constraint is made as stiff as the step allows (time constant two steps,
# impedance 0.99: creep 0.0003 rad/s); joints without friction are untouched.
STICK_SOLIMP = [0.99, 0.999, 0.001, 0.5, 2.0]


def stick_dry_friction(spec, joint_names, timestep: float) -> None:
    for name in joint_names:
        joint = spec.joint(name)
        if joint.frictionloss > 0:
            joint.solref_friction = [2.0 * timestep, 1.0]
            joint.solimp_friction = STICK_SOLIMP


def read_urdf(urdf, notes: list) -> UrdfDoc:
    """`urdf`: a robot's UrdfDoc (Robot.urdf_doc: `kiloloop robot check` lists its changes), or a
    URDF path, read here without a robot file (its changes join the plant's `notes`)."""
    if isinstance(urdf, UrdfDoc):
        return urdf
    doc = urdf_doc.read(urdf)
    notes.extend(doc.repairs)
    return doc


def spec_from_urdf(doc: UrdfDoc, phys: dict, package_dirs=(), visual: bool = False,
                   notes: list | None = None):
    """The URDF as an MjSpec with the compiler settings every plant uses, and the overlay's
    integrator, timestep and gravity. Mesh URIs are resolved and unreadable meshes replaced
    (sil/urdf_import.py); what was changed is appended to `notes`."""
    xml, changes = prepare_urdf(doc, package_dirs, visual=visual)
    if notes is not None:
        notes.extend(changes)
    spec = mujoco.MjSpec.from_string(xml)
    # The URDF importer fuses fixed-joint children (tool0, the feet) into their parent by default;
    # keep them as bodies: sites, poses and contacts are looked up by link name.
    spec.compiler.fusestatic = False
    # Inertia comes only from <inertial>, never from the collision primitives.
    spec.compiler.inertiafromgeom = mujoco.mjtInertiaFromGeom.mjINERTIAFROMGEOM_FALSE
    spec.compiler.discardvisual = not visual
    integrator = str(phys["integrator"]).lower()
    if integrator not in _INTEGRATORS:
        raise InputError(f"integrator: expected one of {sorted(_INTEGRATORS)}, "
                         f"got {integrator!r}")
    spec.option.integrator = _INTEGRATORS[integrator]
    spec.option.timestep = float(phys["timestep"])
    spec.option.gravity = np.asarray(phys["gravity"], dtype=float)
    return spec


def collision_geoms(spec) -> list:
    """The URDF's <collision> geoms. MuJoCo imports <visual> ones (kept only for rendering) with
    contype = conaffinity = 0 in group 1: they must stay out of every contact."""
    return [g for g in spec.geoms if not (g.contype == 0 and g.conaffinity == 0 and g.group == 1)]


def joint_addresses(m, joint_names) -> tuple[np.ndarray, ...]:
    """qpos and dof addresses, motor ids and encoder sensor addresses of the named joints (as
    built by add_joints_and_motors)."""
    jid = [m.joint(n).id for n in joint_names]
    # dtype=int: a plant without joints (a multirotor with no arm) gets empty index arrays.
    return (m.jnt_qposadr[jid].copy(), m.jnt_dofadr[jid].copy(),
            np.array([m.actuator(n).id for n in joint_names], dtype=int),
            np.array([m.sensor_adr[m.sensor(f"{n}_pos").id] for n in joint_names], dtype=int),
            np.array([m.sensor_adr[m.sensor(f"{n}_vel").id] for n in joint_names], dtype=int))


class MujocoPlant:
    """A torque-controlled MuJoCo model of a fixed-base URDF robot."""

    def __init__(self, urdf_path, overlay=None, *, timestep=None, damping=None, frictionloss=None,
                 armature=None, floor=None, scene=None, joints=None, locked=None,
                 package_dirs=(), visual=False):
        """urdf_path: a URDF path or a robot's UrdfDoc (read_urdf). overlay: the robot file's
        [sim] sections (a dict) or a TOML path of them. joints: the controlled chain's joints
        (default: every movable joint); all other joints are welded at `locked` (joint -> [rad]
        or [m], default 0). package_dirs: for package:// mesh URIs. visual: keep visual geometry
        (for rendering)."""
        self.notes: list[str] = []
        self.urdf_doc = doc = read_urdf(urdf_path, self.notes)
        urdf_path = doc.path
        cfg = load_overlay(overlay)
        phys, jcfg = cfg["physics"], cfg["joints"]
        for key, val in (("damping", damping), ("frictionloss", frictionloss),
                         ("armature", armature)):
            if val is not None:
                jcfg[key] = val
        if timestep is not None:
            phys["timestep"] = timestep
        if floor is not None:
            phys["floor"] = floor

        all_names, all_effort = urdf_joints(doc)
        if joints is None:
            joints = all_names
        missing = [n for n in joints if n not in all_names]
        if missing:
            raise InputError(f"joint {missing[0]!r}: not a movable joint of {urdf_path}")
        effort_of = dict(zip(all_names, all_effort))
        self.joint_names = list(joints)
        effort = np.array([effort_of[n] for n in self.joint_names])
        self.nq = len(self.joint_names)

        spec = spec_from_urdf(doc, phys, package_dirs, visual, self.notes)
        welded = weld_joints(spec, self.joint_names, locked)
        self.welded = len(welded)
        if welded:
            self.notes.append(f"welded {len(welded)} joint(s) off the chain: {', '.join(welded)}")

        # Robot geoms: contype 0, conaffinity 1. Environment geoms (floor, obstacles; default
        # contype 1) hit them, but two robot geoms never collide, adjacent or not.
        for geom in collision_geoms(spec):
            geom.contype, geom.conaffinity = 0, 1
        if phys["floor"]:
            spec.worldbody.add_geom(name="floor", type=mujoco.mjtGeom.mjGEOM_PLANE,
                                    size=[0.0, 0.0, 0.05], contype=1, conaffinity=1)

        add_joints_and_motors(spec, self.joint_names, effort, jcfg, cfg["actuators"])
        stick_dry_friction(spec, self.joint_names, float(phys["timestep"]))

        ee = cfg["ee"]
        self.ee_site = ee["site"]
        if ee["body"] is None:
            ee["body"] = "tool0"  # kiloloop's own convention; robot files name their tip
        ee_body = spec.body(ee["body"])
        if ee_body is None:
            raise InputError(f"ee.body: no link named {ee['body']!r} in {urdf_path}")
        ee_body.add_site(name=self.ee_site)

        # Optional scene additions (obstacles, a table, a tool with a force sensor: sil/arm_scene.py)
        # made on the spec before it is compiled.
        if scene is not None:
            scene(spec)
        self.spec = spec  # kept for inspection, e.g. plant.spec.to_xml()
        self.model = compile_spec(spec, urdf_path)
        self.data = mujoco.MjData(self.model)
        # Scratch data for inverse dynamics, so queries never disturb the simulated state.
        self._scratch = mujoco.MjData(self.model)

        m = self.model
        (self._qadr, self._dadr, self._act, self._pos_sens,
         self._vel_sens) = joint_addresses(m, self.joint_names)
        # Public: where the controlled joints live in MuJoCo's qpos and qvel (rigs and probes).
        self.qpos_addresses, self.dof_addresses = self._qadr, self._dadr
        self._site = m.site(self.ee_site).id
        q0 = jcfg["q0"]
        self.q0 = np.zeros(self.nq) if q0 is None else self._vector(q0, "q0")
        self.reset()

    @property
    def timestep(self) -> float:
        return float(self.model.opt.timestep)

    def total_mass(self) -> float:
        """[kg] every body's mass (the world's is 0)."""
        return float(np.sum(self.model.body_mass))

    def _vector(self, x, name: str) -> np.ndarray:
        arr = np.asarray(x, dtype=float)
        if arr.shape != (self.nq,):
            raise ValueError(f"{name}: expected shape ({self.nq},), got {arr.shape}")
        if not np.all(np.isfinite(arr)):
            raise ValueError(f"{name}: non-finite value")
        return arr

    def reset(self, q=None, qd=None) -> None:
        mujoco.mj_resetData(self.model, self.data)
        self.data.qpos[self._qadr] = self.q0 if q is None else self._vector(q, "q")
        self.data.qvel[self._dadr] = 0.0 if qd is None else self._vector(qd, "qd")
        # Fill positions, velocities and sensors for the state just set (see step()).
        mujoco.mj_forward(self.model, self.data)

    def q(self) -> np.ndarray:
        return self.data.sensordata[self._pos_sens].copy()

    def qd(self) -> np.ndarray:
        return self.data.sensordata[self._vel_sens].copy()

    def set_torque(self, tau) -> None:
        # MuJoCo clamps ctrl to ctrlrange (the URDF effort limit) inside the step.
        self.data.ctrl[self._act] = self._vector(tau, "tau")

    def step(self, n: int = 1) -> None:
        # mj_step2 then mj_step1 instead of mj_step: mj_step computes sensors and site poses before
        # integrating, so after it they would describe the previous state. This way q(), qd() and
        # ee_pose() always describe the current state, at the cost of one mj_step.
        for _ in range(int(n)):
            mujoco.mj_step2(self.model, self.data)
            mujoco.mj_step1(self.model, self.data)

    def time(self) -> float:
        return float(self.data.time)

    def ee_pose(self) -> tuple[np.ndarray, np.ndarray]:
        """End-effector site position (3,) [m] and rotation (3, 3) in the world frame."""
        return (self.data.site_xpos[self._site].copy(),
                self.data.site_xmat[self._site].reshape(3, 3).copy())

    def inverse_dynamics(self, q, qd, qdd) -> np.ndarray:
        """Joint torques [N m] that produce qdd at (q, qd): M qdd + bias - passive (damping).

        Contacts, joint limits and friction loss (all constraints) are excluded, so with zero
        damping and armature this is the rigid-body inverse dynamics of the URDF.
        """
        d = self._scratch
        d.qpos[self._qadr] = self._vector(q, "q")
        d.qvel[self._dadr] = self._vector(qd, "qd")
        d.qacc[self._dadr] = self._vector(qdd, "qdd")
        flags = self.model.opt.disableflags
        self.model.opt.disableflags = flags | mujoco.mjtDisableBit.mjDSBL_CONSTRAINT
        try:
            mujoco.mj_inverse(self.model, d)
        finally:
            self.model.opt.disableflags = flags
        return d.qfrc_inverse[self._dadr].copy()

