"""Multirotor MuJoCo plant (n rotors, any positions and axes, an arm of 0..n joints or none),
built at run time from a robot file: the URDF plus its [[rotors]] tables and [sim.*] sections.

The URDF is the single source of truth for kinematics, inertia and joint limits; the plant adds a
free joint on the root link, one thrust actuator per rotor at a site whose z axis is the rotor's
axis (first-order motor lag through MuJoCo's filter dynamics, drag torque through the actuator
gear, saturation through the control range), joint friction, the arm's torque motors and
encoders, an IMU and an end-effector site. Joints that are not the arm's (rotor spin joints of a
description, say) are welded. Reuses the builders of the fixed-base and legged plants (plant.py,
floating_plant.py). SI units; quaternions (w, x, y, z); arm joints in the controller's chain
order; rotors in the robot file's order.

Timing as in the other plants: step() runs mj_step2 then mj_step1, so positions, velocities and
sensors describe the state after the last step.
"""
from __future__ import annotations


import mujoco
import numpy as np

from ..robot import aerial, sim_defaults
from ..robot.urdf_joints import urdf_joints
from ..errors import InputError
from .floating_base import FloatingBaseReadout, add_free_base, add_imu
from .floating_base import fixed as _fixed
from .floating_base import unit_quat as _unit_quat
from .mujoco_refusal import compile_spec
from .plant import add_joints_and_motors, load_overlay as _plant_overlay, read_urdf, spec_from_urdf
from .urdf_import import weld_joints

# The [sim.*] defaults live with the robot-file schema, which reads them too.
_DEFAULTS = sim_defaults.AERIAL


def load_overlay(overlay) -> dict:
    """The aerial [sim.*] sections (path, dict or None) merged over the defaults."""
    return _plant_overlay(overlay, _DEFAULTS)


def _rotor_frame(axis) -> np.ndarray:
    """(w, x, y, z) rotating +z onto `axis` (the site frame a rotor pushes along)."""
    z = np.array([0.0, 0.0, 1.0])
    a = np.asarray(axis, dtype=float) / np.linalg.norm(axis)
    q = np.zeros(4)
    mujoco.mju_quatZ2Vec(q, a)
    return q if np.all(np.isfinite(q)) else np.array([1.0, 0.0, 0.0, 0.0]) * np.sign(a @ z)


class AerialPlant(FloatingBaseReadout):
    """A multirotor, with or without a torque-controlled arm: rotor thrust commands [N] and joint
    torques [N m]."""

    @classmethod
    def from_robot(cls, robot, **kw) -> "AerialPlant":
        """The plant of a loaded aerial robot file (kl.Robot)."""
        model = aerial.model(robot)
        v = robot.section("vehicle")
        return cls(robot.urdf_doc, robot.sim, rotors=aerial.rotors(robot),
                   joints=list(model.joint_names) if v.get("ee") else [], ee=v.get("ee") or None,
                   package_dirs=robot.package_dirs, **kw)

    def __init__(self, urdf_path, overlay=None, *, rotors, joints=None, ee=None, package_dirs=(),
                 visual=False, timestep=None, damping=None, frictionloss=None, efficiency=None,
                 motor_lag=True):
        """overlay: the [sim.*] sections (a dict or a TOML path) or None. rotors: the checked
        [[rotors]] tables (robot/aerial.py rotors()). joints: the arm's joints in chain order
        (None: every actuated URDF joint); the others are welded. ee: the end-effector link (None:
        no arm site). timestep [s], damping, frictionloss (arm joints) and efficiency (n,)
        override the overlay; motor_lag=False makes thrust follow the command instantly (used by
        the inverse-dynamics cross-check). urdf_path: a URDF path or a robot's UrdfDoc
        (Robot.urdf_doc)."""
        self.notes = []
        self.urdf_doc = doc = read_urdf(urdf_path, self.notes)
        urdf_path = doc.path
        cfg = load_overlay(overlay)
        phys, jcfg = cfg["physics"], cfg["joints"]
        if timestep is not None:
            phys["timestep"] = timestep
        for key, val in (("damping", damping), ("frictionloss", frictionloss)):
            if val is not None:
                jcfg[key] = val
        self.rotors = list(rotors)
        self.n_rotors = n = len(self.rotors)
        eff = efficiency if efficiency is not None else cfg["rotors"]["efficiency"]
        self.efficiency = np.ones(n) if eff is None else _fixed(eff, (n,), "rotors.efficiency")
        if np.any(self.efficiency < 0):
            raise InputError(f"rotors.efficiency: expected >= 0, got {eff!r}")

        names, effort = urdf_joints(doc)
        index = {name: i for i, name in enumerate(names)}
        self.joint_names = list(names if joints is None else joints)
        missing = [j for j in self.joint_names if j not in index]
        if missing:
            raise InputError(f"{urdf_path}: no actuated joint named {missing[0]!r}")
        self.nq = len(self.joint_names)
        self.effort = np.array([effort[index[j]] for j in self.joint_names])

        spec = spec_from_urdf(doc, phys, package_dirs, visual, self.notes)
        welded = weld_joints(spec, self.joint_names)
        if welded:
            self.notes.append(f"welded {len(welded)} joints off the arm: {', '.join(welded)}")
        root = add_free_base(spec, urdf_path)
        self.base_body = root.name
        # Free flight: no floor and no self-collision (the arm may pass under the body).
        for geom in spec.geoms:
            geom.contype, geom.conaffinity = 0, 0

        if self.nq:
            add_joints_and_motors(spec, self.joint_names, self.effort, jcfg, cfg["actuators"])

        # Rotors: a site per rotor with z along its axis; a site-transmission actuator pushes along
        # the site's z and twists about it with gear (0, 0, 1, 0, 0, -spin * c): a rotor turning
        # counter-clockwise about its axis (spin +1) drags the body the other way.
        # Filter dynamics: d/dt act = (ctrl - act) / tau, force = efficiency * act.
        self.rotor_names = []
        for k, r in enumerate(self.rotors):
            name = f"rotor{k}"
            root.add_site(name=name, pos=r["position"], quat=_rotor_frame(r["axis"]))
            act = spec.add_actuator(name=name, target=name, trntype=mujoco.mjtTrn.mjTRN_SITE)
            act.gear = [0.0, 0.0, 1.0, 0.0, 0.0, -r["spin"] * r["torque_coefficient"]]
            act.gaintype = mujoco.mjtGain.mjGAIN_FIXED
            act.gainprm[0] = self.efficiency[k]
            act.biastype = mujoco.mjtBias.mjBIAS_NONE
            lag = r["time_constant"] if motor_lag else 0.0
            if lag > 0:
                act.dyntype = mujoco.mjtDyn.mjDYN_FILTER
                act.dynprm[0] = lag
            act.ctrllimited = mujoco.mjtLimited.mjLIMITED_TRUE
            act.ctrlrange = [r["thrust_min"], r["thrust_max"]]
            self.rotor_names.append(name)

        self.imu_site = add_imu(spec, cfg["imu"], self.base_body, urdf_path)
        self.ee_site = None
        if ee is not None:
            ee_body = spec.body(ee)
            if ee_body is None:
                raise InputError(f"vehicle.ee: no link named {ee!r} in {urdf_path}")
            self.ee_site = cfg["ee"]["site"]
            ee_body.add_site(name=self.ee_site)

        self.spec = spec
        self.model = compile_spec(spec, urdf_path)
        self.data = mujoco.MjData(self.model)
        self._scratch = mujoco.MjData(self.model)

        self._index_floating_base()
        m = self.model
        self._rotor_act = np.array([m.actuator(n).id for n in self.rotor_names])
        self._ee_site = m.site(self.ee_site).id if self.ee_site else None
        q0 = jcfg["q0"]
        self.q0 = np.zeros(self.nq) if q0 is None else _fixed(q0, (self.nq,), "q0")
        self.base_pos0 = _fixed(cfg["base"]["pos0"], (3,), "base.pos0")
        self.base_quat0 = _unit_quat(cfg["base"]["quat0"], "base.quat0")
        self.reset()

    def reset(self, q=None, base_pos=None, base_quat=None, thrust=None) -> None:
        """Arm at q (default q0), body at base_pos/base_quat, at rest; the rotors' filtered thrust
        starts at `thrust` (n,) [N] (default: the hover share, the weight through the pseudo-
        inverse of the rotors' force and torque about the CoM, so a hover starts without a drop
        while the motor lag winds up)."""
        mujoco.mj_resetData(self.model, self.data)
        d = self.data
        d.qpos[self._qadr] = self.q0 if q is None else _fixed(q, (self.nq,), "q")
        self._set_base_pose(d, base_pos, base_quat)
        f0 = self.hover_thrusts() if thrust is None else _fixed(thrust, (self.n_rotors,),
                                                                 "thrust")
        d.ctrl[self._rotor_act] = f0
        adr = self.model.actuator_actadr[self._rotor_act]
        has_act = adr >= 0
        d.act[adr[has_act]] = f0[has_act]
        mujoco.mj_forward(self.model, d)

    def hover_thrusts(self) -> np.ndarray:
        """(n,) [N] the minimum-norm thrusts that hold the vehicle's weight at the current pose
        with zero net torque about its CoM and no lateral force (rotors within their range)."""
        m, d = self.model, self.data
        mujoco.mj_kinematics(m, d)
        mujoco.mj_comPos(m, d)
        com = d.subtree_com[self._base_id]
        B = np.zeros((6, self.n_rotors))
        for k, r in enumerate(self.rotors):
            sid = m.site(self.rotor_names[k]).id
            a = d.site_xmat[sid].reshape(3, 3)[:, 2]
            p = d.site_xpos[sid] - com
            B[:3, k] = self.efficiency[k] * a
            B[3:, k] = self.efficiency[k] * (np.cross(p, a) - r["spin"] * r["torque_coefficient"] * a)
        w = np.zeros(6)
        w[2] = self.total_mass * abs(m.opt.gravity[2])
        f = np.linalg.lstsq(B, w, rcond=None)[0]
        return np.clip(f, [r["thrust_min"] for r in self.rotors],
                       [r["thrust_max"] for r in self.rotors])

    # --- ground truth beyond the mixin's (joint_q/q, imu, base_pose, base_velocity) ---------

    def com(self) -> np.ndarray:
        """Centre of mass of the whole vehicle (body + arm), world frame (3,) [m]."""
        return self.data.subtree_com[self._base_id].copy()

    def ee_pose(self) -> tuple[np.ndarray, np.ndarray]:
        """End-effector site position (3,) [m] and rotation (3, 3), world frame (the base link's
        origin without an arm)."""
        if self._ee_site is None:
            b = self._base_id
            return self.data.xpos[b].copy(), self.data.xmat[b].reshape(3, 3).copy()
        return (self.data.site_xpos[self._ee_site].copy(),
                self.data.site_xmat[self._ee_site].reshape(3, 3).copy())

    def rotor_thrust(self) -> np.ndarray:
        """Thrust each rotor produces now (n,) [N] (after the lag and the efficiency)."""
        return self.data.actuator_force[self._rotor_act].copy()

    # --- commands -----------------------------------------------------------------------------

    def set_torque(self, tau) -> None:
        """Arm joint torques (nq,) [N m]; MuJoCo clamps them to +-effort."""
        if self.nq:
            self.data.ctrl[self._act] = _fixed(tau, (self.nq,), "tau")

    def set_thrust(self, thrust) -> None:
        """Rotor thrust commands (n,) [N]; MuJoCo clamps them to [thrust_min, thrust_max]."""
        self.data.ctrl[self._rotor_act] = _fixed(thrust, (self.n_rotors,), "thrust")

    def apply_force(self, force, point=None) -> None:
        """A world-frame force (3,) [N] on the base body at `point` (3,) [m, world; default its
        CoM], until changed (MuJoCo's xfrc_applied: wind, a push)."""
        f = _fixed(force, (3,), "force")
        b = self._base_id
        torque = np.zeros(3)
        if point is not None:
            torque = np.cross(_fixed(point, (3,), "point") - self.data.xipos[b], f)
        self.data.xfrc_applied[b, :3] = f
        self.data.xfrc_applied[b, 3:] = torque

    def set_efficiency(self, k: int, efficiency: float) -> None:
        """Scales rotor k's thrust and drag torque from now on (a damaged propeller)."""
        self.model.actuator_gainprm[self._rotor_act[k], 0] = float(efficiency)

    def step(self, n: int = 1) -> None:
        for _ in range(int(n)):
            mujoco.mj_step2(self.model, self.data)
            mujoco.mj_step1(self.model, self.data)

    # --- oracle -------------------------------------------------------------------------------

    def inverse_dynamics(self, base_pos, base_quat, q, v_world, omega_body, qd, a_world,
                         alpha_body, qdd) -> np.ndarray:
        """mj_inverse on a scratch copy, constraints off: the generalized forces (6 + nq) that
        produce the given accelerations. Free-joint part: force (3,) [N] in the world frame and
        torque (3,) [N m] in the body frame about the body origin; then the arm torques."""
        d = self._scratch
        fq, fd = self._free_q, self._free_d
        d.qpos[:] = self.data.qpos
        d.qpos[fq:fq + 3] = _fixed(base_pos, (3,), "base_pos")
        d.qpos[fq + 3:fq + 7] = _unit_quat(base_quat, "base_quat")
        d.qpos[self._qadr] = _fixed(q, (self.nq,), "q")
        d.qvel[:] = 0.0
        d.qvel[fd:fd + 3] = _fixed(v_world, (3,), "v_world")
        d.qvel[fd + 3:fd + 6] = _fixed(omega_body, (3,), "omega_body")
        d.qvel[self._dadr] = _fixed(qd, (self.nq,), "qd")
        d.qacc[:] = 0.0
        d.qacc[fd:fd + 3] = _fixed(a_world, (3,), "a_world")
        d.qacc[fd + 3:fd + 6] = _fixed(alpha_body, (3,), "alpha_body")
        d.qacc[self._dadr] = _fixed(qdd, (self.nq,), "qdd")
        flags = self.model.opt.disableflags
        self.model.opt.disableflags = flags | mujoco.mjtDisableBit.mjDSBL_CONSTRAINT
        try:
            mujoco.mj_inverse(self.model, d)
        finally:
            self.model.opt.disableflags = flags
        return np.concatenate([d.qfrc_inverse[fd:fd + 6], d.qfrc_inverse[self._dadr]])
