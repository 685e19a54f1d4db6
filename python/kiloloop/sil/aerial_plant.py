"""Aerial-manipulator MuJoCo plant built at run time from a URDF plus a TOML overlay.

The URDF (models/aerial_manipulator/) is the single source of truth for kinematics, inertia and
joint limits; the overlay (sim.toml) adds a free joint on the root link, four rotors as thrust
actuators at sites on the body (first-order motor lag through MuJoCo's filter dynamics, yaw drag
torque through the actuator gear), joint friction, the arm's torque motors and encoders, an IMU and
an end-effector site. Reuses the builders of the fixed-base and legged plants (plant.py,
floating_plant.py). SI units; quaternions (w, x, y, z); arm joints in URDF order; rotors in the
overlay's order.

Timing as in the other plants: step() runs mj_step2 then mj_step1, so positions, velocities and
sensors describe the state after the last step.
"""
from __future__ import annotations

from pathlib import Path

import mujoco
import numpy as np

from .floating_base import FloatingBaseReadout, add_free_base, add_imu
from .floating_base import fixed as _fixed
from .floating_base import unit_quat as _unit_quat
from .plant import _add_joints_and_motors, _load_overlay, _spec_from_urdf, _urdf_joints

_DEFAULTS = {
    "physics": {"timestep": 0.001, "integrator": "implicitfast", "gravity": [0.0, 0.0, -9.81]},
    "joints": {"damping": 0.0, "frictionloss": 0.0, "armature": 0.0, "q0": None},
    "base": {"pos0": [0.0, 0.0, 1.0], "quat0": [1.0, 0.0, 0.0, 0.0]},
    "actuators": {"type": "motor"},
    "rotors": {"positions": None, "spin": None, "drag_coefficient": 0.016, "thrust_min": 0.0,
               "thrust_max": 8.0, "time_constant": 0.03, "efficiency": [1.0, 1.0, 1.0, 1.0]},
    "imu": {"body": None, "site": "imu", "pos": [0.0, 0.0, 0.0]},
    "ee": {"body": "ee_link", "site": "ee_site"},
}


def load_overlay(overlay) -> dict:
    """The aerial overlay (path, dict or None) merged over the defaults; also used by the rig to
    hand the rotor geometry to the controller."""
    return _load_overlay(overlay, _DEFAULTS)


def rotor_geometry(cfg: dict) -> dict:
    """Checked rotor section: positions (4, 3) [m], spin (4,), drag [m], limits [N], tau [s]."""
    r = cfg["rotors"]
    pos = _fixed(r["positions"], (4, 3), "rotors.positions")
    spin = _fixed(r["spin"], (4,), "rotors.spin")
    if not np.all(np.abs(spin) == 1.0):
        raise ValueError(f"rotors.spin: expected +-1 each, got {r['spin']!r}")
    eff = _fixed(r["efficiency"], (4,), "rotors.efficiency")
    if np.any(eff < 0):
        raise ValueError(f"rotors.efficiency: expected >= 0, got {r['efficiency']!r}")
    out = {"positions": pos, "spin": spin, "efficiency": eff}
    for key in ("drag_coefficient", "thrust_min", "thrust_max", "time_constant"):
        value = float(r[key])
        if not np.isfinite(value) or value < 0:
            raise ValueError(f"rotors.{key}: expected a finite number >= 0, got {r[key]!r}")
        out[key] = value
    if out["thrust_max"] <= out["thrust_min"]:
        raise ValueError("rotors: thrust_max must exceed thrust_min")
    return out


class AerialPlant(FloatingBaseReadout):
    """A quadrotor with a torque-controlled arm: rotor thrust commands [N] and joint torques [N m]."""

    n_rotors = 4

    def __init__(self, urdf_path, overlay=None, *, timestep=None, damping=None, frictionloss=None,
                 efficiency=None, motor_lag=True):
        """overlay: a sim.toml path, a dict of its sections, or None. timestep [s], damping,
        frictionloss (arm joints) and efficiency (4,) override it; motor_lag=False makes thrust
        follow the command instantly (used by the inverse-dynamics cross-check)."""
        urdf_path = Path(urdf_path)
        cfg = load_overlay(overlay)
        phys, jcfg = cfg["physics"], cfg["joints"]
        if timestep is not None:
            phys["timestep"] = timestep
        for key, val in (("damping", damping), ("frictionloss", frictionloss)):
            if val is not None:
                jcfg[key] = val
        if efficiency is not None:
            cfg["rotors"]["efficiency"] = list(np.asarray(efficiency, dtype=float))
        self.rotors = rotor_geometry(cfg)

        self.joint_names, effort = _urdf_joints(urdf_path)
        self.nq = len(self.joint_names)
        self.effort = effort

        spec = _spec_from_urdf(urdf_path, phys)
        root = add_free_base(spec, urdf_path)
        self.base_body = root.name
        # Free flight: no floor and no self-collision (the arm may pass under the body).
        for geom in spec.geoms:
            geom.contype, geom.conaffinity = 0, 0

        _add_joints_and_motors(spec, self.joint_names, effort, jcfg, cfg["actuators"])

        # Rotors: a site per rotor; a site-transmission actuator pushes along the site's z and
        # twists about it with gear (0, 0, 1, 0, 0, spin * drag), so torque = drag * thrust.
        # Filter dynamics: d/dt act = (ctrl - act) / tau, force = efficiency * act.
        rot = self.rotors
        lag = rot["time_constant"] if motor_lag else 0.0
        self.rotor_names = []
        for k in range(self.n_rotors):
            name = f"rotor{k}"
            root.add_site(name=name, pos=rot["positions"][k])
            act = spec.add_actuator(name=name, target=name, trntype=mujoco.mjtTrn.mjTRN_SITE)
            act.gear = [0.0, 0.0, 1.0, 0.0, 0.0, rot["spin"][k] * rot["drag_coefficient"]]
            act.gaintype = mujoco.mjtGain.mjGAIN_FIXED
            act.gainprm[0] = rot["efficiency"][k]
            act.biastype = mujoco.mjtBias.mjBIAS_NONE
            if lag > 0:
                act.dyntype = mujoco.mjtDyn.mjDYN_FILTER
                act.dynprm[0] = lag
            act.ctrllimited = mujoco.mjtLimited.mjLIMITED_TRUE
            act.ctrlrange = [rot["thrust_min"], rot["thrust_max"]]
            self.rotor_names.append(name)

        self.imu_site = add_imu(spec, cfg["imu"], self.base_body, urdf_path)
        ee_body = spec.body(cfg["ee"]["body"])
        if ee_body is None:
            raise ValueError(f"ee.body: no link named {cfg['ee']['body']!r} in {urdf_path}")
        self.ee_site = cfg["ee"]["site"]
        ee_body.add_site(name=self.ee_site)

        self.spec = spec
        self.model = spec.compile()
        self.data = mujoco.MjData(self.model)
        self._scratch = mujoco.MjData(self.model)

        self._index_floating_base()
        m = self.model
        self._rotor_act = np.array([m.actuator(n).id for n in self.rotor_names])
        self._ee_site = m.site(self.ee_site).id
        q0 = jcfg["q0"]
        self.q0 = np.zeros(self.nq) if q0 is None else _fixed(q0, (self.nq,), "q0")
        self.base_pos0 = _fixed(cfg["base"]["pos0"], (3,), "base.pos0")
        self.base_quat0 = _unit_quat(cfg["base"]["quat0"], "base.quat0")
        self.reset()

    def reset(self, q=None, base_pos=None, base_quat=None, thrust=None) -> None:
        """Arm at q (default q0), body at base_pos/base_quat, at rest; the rotors' filtered thrust
        starts at `thrust` (4,) [N] (default: each carries a quarter of the total weight, so a
        hover starts without a drop while the motor lag winds up)."""
        mujoco.mj_resetData(self.model, self.data)
        d = self.data
        d.qpos[self._qadr] = self.q0 if q is None else _fixed(q, (self.nq,), "q")
        self._set_base_pose(d, base_pos, base_quat)
        hover = self.total_mass * abs(self.model.opt.gravity[2]) / self.n_rotors
        f0 = np.full(self.n_rotors, hover) if thrust is None else _fixed(thrust, (4,), "thrust")
        d.ctrl[self._rotor_act] = f0
        adr = self.model.actuator_actadr[self._rotor_act]
        has_act = adr >= 0
        d.act[adr[has_act]] = f0[has_act]
        mujoco.mj_forward(self.model, d)

    # --- ground truth beyond the mixin's (joint_q/q, imu, base_pose, base_velocity) ---------

    def com(self) -> np.ndarray:
        """Centre of mass of the whole vehicle (body + arm), world frame (3,) [m]."""
        return self.data.subtree_com[self._base_id].copy()

    def ee_pose(self) -> tuple[np.ndarray, np.ndarray]:
        """End-effector site position (3,) [m] and rotation (3, 3), world frame."""
        return (self.data.site_xpos[self._ee_site].copy(),
                self.data.site_xmat[self._ee_site].reshape(3, 3).copy())

    def rotor_thrust(self) -> np.ndarray:
        """Thrust each rotor produces now (4,) [N] (after the lag and the efficiency)."""
        return self.data.actuator_force[self._rotor_act].copy()

    # --- commands -----------------------------------------------------------------------------

    def set_torque(self, tau) -> None:
        """Arm joint torques (nq,) [N m]; MuJoCo clamps them to +-effort."""
        self.data.ctrl[self._act] = _fixed(tau, (self.nq,), "tau")

    def set_thrust(self, thrust) -> None:
        """Rotor thrust commands (4,) [N]; MuJoCo clamps them to [thrust_min, thrust_max]."""
        self.data.ctrl[self._rotor_act] = _fixed(thrust, (self.n_rotors,), "thrust")

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
