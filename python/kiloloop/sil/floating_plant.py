"""Floating-base MuJoCo plant (quadrupeds) built at run time from a URDF plus a TOML overlay.

The URDF is the single source of truth for kinematics, inertia and limits; the overlay
(models/<robot>/sim.toml) adds what only the simulator needs: a free joint on the root link, a
floor (optionally sloped), contact friction, torque motors, joint encoders, an IMU and the foot
bookkeeping. Built the same way as the fixed-base MujocoPlant (sil/plant.py). All arrays are
numpy, SI units; joints in URDF order; quaternions (w, x, y, z).

Timing, as in MujocoPlant: step() runs mj_step2 then mj_step1, so positions, velocities, the gyro,
the orientation and the encoders describe the state after the last step. The accelerometer and the
foot contact forces are acceleration-stage quantities: they describe the last step's interval (the
forces that produced the current velocity), which after reset() is the interval about to start.
"""
from __future__ import annotations


import mujoco
import numpy as np

from ..robot import sim_defaults
from ..robot.urdf_joints import urdf_joints
from ..errors import InputError
from .floating_base import FloatingBaseReadout, add_free_base, add_imu
from .geom_bottom import geom_bottom
from .floating_base import fixed as _fixed
from .floating_base import unit_quat as _unit_quat
from .mujoco_refusal import compile_spec
from .plant import add_joints_and_motors, collision_geoms, read_urdf, spec_from_urdf
from .plant import load_overlay as _load_plant_overlay
from .timing import whole_periods

# The [sim.*] defaults live with the robot-file schema, which reads them too.
_DEFAULTS = sim_defaults.QUADRUPED
# The quadruped plant's solver options (robot files override them in [sim.physics]).
DEFAULT_PHYSICS = sim_defaults.QUADRUPED_PHYSICS
_CONES = {"pyramidal": mujoco.mjtCone.mjCONE_PYRAMIDAL,
          "elliptic": mujoco.mjtCone.mjCONE_ELLIPTIC}
_FLOOR = "floor"
# MuJoCo's default torsional and rolling friction; only the sliding coefficient is configured.
_SPIN_ROLL = (0.005, 0.0001)


def _load_overlay(overlay) -> dict:
    return _load_plant_overlay(overlay, _DEFAULTS)


def _quat_mul(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    out = np.zeros(4)
    mujoco.mju_mulQuat(out, a, b)
    return out


def set_friction_options(spec, phys: dict) -> None:
    """The plant's friction cone and its stiffness on spec.option from a [physics] table (cone,
    impratio, noslip_iterations; DEFAULT_PHYSICS holds the defaults), validated: MuJoCo's soft
    friction lets a loaded foot creep; see sim.toml for the measured creep under each setting."""
    cone = str(phys["cone"]).lower()
    if cone not in _CONES:
        raise InputError(f"cone: expected one of {sorted(_CONES)}, got {cone!r}")
    spec.option.cone = _CONES[cone]
    impratio = float(phys["impratio"])
    if not np.isfinite(impratio) or impratio <= 0:
        raise InputError(f"impratio: expected a positive number, got {phys['impratio']!r}")
    spec.option.impratio = impratio
    noslip = int(phys["noslip_iterations"])
    if noslip < 0:
        raise InputError(f"noslip_iterations: expected >= 0, got {noslip}")
    spec.option.noslip_iterations = noslip


class FloatingBasePlant(FloatingBaseReadout):
    """A torque-controlled MuJoCo model of a floating-base (legged) URDF robot on a floor."""

    def __init__(self, urdf_path, overlay=None, *, timestep=None, slope_deg=None, floor=None,
                 feet=None, package_dirs=(), notes: list | None = None, terrain=None):
        """overlay: path to a sim.toml, a dict of its sections, or None for the defaults.

        timestep [s], slope_deg [deg] (ground rising along +x), floor (bool) and feet (link names)
        override the overlay; feet defaults to the overlay's [feet] bodies (FL, FR, RL, RR).
        package_dirs: where package:// mesh URIs resolve; notes collects what the import changed
        (meshes replaced; a URDF path's inertia repairs, robot/urdf_doc.py: a robot's UrdfDoc
        keeps its own). terrain: a sil/terrain.py spec (Stones, Rough, Compliant) that replaces the
        floor plane (flat start pad at z = 0; no slope with it). urdf_path: a URDF path or a
        robot's UrdfDoc (Robot.urdf_doc).
        """
        self.notes = [] if notes is None else notes
        self.urdf_doc = doc = read_urdf(urdf_path, self.notes)
        urdf_path = doc.path
        cfg = _load_overlay(overlay)
        phys, fcfg, jcfg = cfg["physics"], cfg["floor"], cfg["joints"]
        if timestep is not None:
            phys["timestep"] = timestep
        if slope_deg is not None:
            fcfg["slope_deg"] = slope_deg
        if floor is not None:
            fcfg["enabled"] = floor
        self.feet = tuple(cfg["feet"]["bodies"] if feet is None else feet)
        foot_offset = _fixed(cfg["feet"]["offset"], (3,), "feet.offset")
        self.slope = np.deg2rad(float(fcfg["slope_deg"]))
        if not np.isfinite(self.slope) or abs(self.slope) >= np.pi / 2:
            raise InputError(f"slope_deg: expected |slope| < 90, got {fcfg['slope_deg']!r}")
        if terrain is not None and self.slope != 0.0:
            raise InputError("terrain: a terrain replaces the floor; slope_deg must be 0 with it")
        self.terrain = terrain
        friction = float(fcfg["friction"])
        if not np.isfinite(friction) or friction < 0:
            raise InputError(f"floor.friction: expected a non-negative number, got {friction!r}")

        self.joint_names, effort = urdf_joints(doc)
        self.nq = len(self.joint_names)
        self.effort = effort

        spec = spec_from_urdf(doc, phys, package_dirs, notes=self.notes)
        set_friction_options(spec, phys)

        self.base_body = add_free_base(spec, urdf_path).name

        # Robot geoms: contype 0, conaffinity 1. The floor (contype 1) hits them, but two robot
        # geoms never collide: legs may cross the trunk's box without a self-contact.
        for geom in collision_geoms(spec):
            geom.contype, geom.conaffinity = 0, 1
        for foot in self.feet:
            body = spec.body(foot)
            if body is None:
                raise InputError(f"feet: no link named {foot!r} in {urdf_path}")
            geoms = list(body.geoms)
            if not geoms:
                raise InputError(f"feet: link {foot!r} has no collision geometry")
            for k, geom in enumerate(geoms):
                geom.name = f"{foot}_geom" if len(geoms) == 1 else f"{foot}_geom{k}"
                geom.friction = [friction, *_SPIN_ROLL]
            body.add_site(name=f"{foot}_site", pos=foot_offset)

        if terrain is not None and fcfg["enabled"]:
            terrain.add_to(spec, friction)
        elif fcfg["enabled"]:
            # Plane normal = its local z; Ry(-slope) turns it to (-sin a, 0, cos a).
            quat = [np.cos(-self.slope / 2), 0.0, np.sin(-self.slope / 2), 0.0]
            spec.worldbody.add_geom(name=_FLOOR, type=mujoco.mjtGeom.mjGEOM_PLANE,
                                    size=[0.0, 0.0, 0.05], quat=quat, contype=1, conaffinity=1,
                                    friction=[friction, *_SPIN_ROLL])
        self.floor = bool(fcfg["enabled"])

        add_joints_and_motors(spec, self.joint_names, effort, jcfg, cfg["actuators"])

        self.imu_site = add_imu(spec, cfg["imu"], self.base_body, urdf_path)

        self.spec = spec  # kept for inspection, e.g. plant.spec.to_xml()
        self.model = compile_spec(spec, urdf_path)
        self.data = mujoco.MjData(self.model)

        self._index_floating_base()
        m = self.model
        self._foot_ids = np.array([m.body(f).id for f in self.feet])
        self._foot_sites = np.array([m.site(f"{f}_site").id for f in self.feet])
        # geom id -> foot index (or -1), for the contact bookkeeping
        self._geom_foot = np.full(m.ngeom, -1)
        for k, bid in enumerate(self._foot_ids):
            self._geom_foot[m.geom_bodyid == bid] = k
        if terrain is not None and self.floor:
            # Every robot geom that can touch the ground (contype 0, conaffinity 1; see above).
            terrain.configure(m, np.flatnonzero((m.geom_bodyid > 0) & (m.geom_conaffinity == 1)))

        q0 = jcfg["q0"]
        self.q0 = np.zeros(self.nq) if q0 is None else self._vector(q0, "q0")
        # Flat-ground standing pose; on a slope the whole configuration is rotated with the ground
        # about the world y axis through the origin, so that the same feet touch the tilted plane
        # and the trunk is aligned with it (pitched nose-up by the slope when climbing along +x).
        R_slope = np.array([[np.cos(self.slope), 0.0, -np.sin(self.slope)],
                            [0.0, 1.0, 0.0],
                            [np.sin(self.slope), 0.0, np.cos(self.slope)]])
        q_slope = np.array([np.cos(-self.slope / 2), 0.0, np.sin(-self.slope / 2), 0.0])
        quat0 = _unit_quat(cfg["base"]["quat0"], "base.quat0")
        pos0 = cfg["base"]["pos0"]
        pos0 = self._stand_pos(quat0) if pos0 is None else _fixed(pos0, (3,), "base.pos0")
        self.base_pos0 = R_slope @ pos0
        self.base_quat0 = _quat_mul(q_slope, quat0)

        self._foot_forces = np.zeros((len(self.feet), 3))
        self.reset()

    # --- configuration ---------------------------------------------------------------------

    def _vector(self, x, name: str) -> np.ndarray:
        return _fixed(x, (self.nq,), name)

    def _stand_pos(self, quat0: np.ndarray) -> np.ndarray:
        """Trunk position over the origin at which the lowest foot geom touches flat ground at
        z = 0, with the joints at q0 (sil/geom_bottom.py: exact for spheres, capsules, cylinders,
        boxes and meshes)."""
        d = mujoco.MjData(self.model)
        d.qpos[self._qadr] = self.q0
        d.qpos[self._free_q + 3:self._free_q + 7] = quat0
        mujoco.mj_kinematics(self.model, d)
        feet = np.flatnonzero(self._geom_foot >= 0)
        bottom = min(geom_bottom(self.model, d, g) for g in feet)
        return np.array([0.0, 0.0, -bottom])

    def reset(self, q=None, base_pos=None, base_quat=None) -> None:
        """Joints at q (default q0), trunk at base_pos/base_quat, all velocities 0.

        The defaults base_pos0/base_quat0 put the standing pose on the ground with the feet just
        touching it. On a slope that is the flat-ground pose rotated with the ground about the
        world y axis: the trunk is aligned with the plane (pitched nose-up by the slope, yaw 0,
        facing uphill along +x), its origin at the standing height along the ground normal from
        the plane (h / cos(slope) vertically), and the legs perpendicular to the plane. Pass
        base_quat=(1, 0, 0, 0) and a base_pos of your own for a level trunk.
        """
        mujoco.mj_resetData(self.model, self.data)
        d = self.data
        d.qpos[self._qadr] = self.q0 if q is None else self._vector(q, "q")
        self._set_base_pose(d, base_pos, base_quat)
        self._push_force = np.zeros(3)
        self._push_steps = 0
        self._pushing = False  # mj_resetData cleared xfrc_applied
        # Positions, velocities, sensors and the contact forces for the state just set (zero ctrl).
        mujoco.mj_forward(self.model, d)
        self._foot_forces = self._contact_forces()

    # --- ground truth (what only the simulator knows; base_pose/base_velocity: mixin) ---------

    def foot_positions(self) -> np.ndarray:
        """The feet's contact sphere centres (their sites: the link origin + R_foot feet.offset) in
        the world frame (n_feet, 3) [m]; with a zero offset MuJoCo copies the link origin."""
        return self.data.site_xpos[self._foot_sites].copy()

    def foot_contact_forces(self) -> np.ndarray:
        """Force exerted by the ground on each foot, world frame (n_feet, 3) [N], summed over the
        foot's contacts, during the last step (see the module docstring)."""
        return self._foot_forces.copy()

    def ground_normal(self) -> np.ndarray:
        """Unit normal of the floor plane in the world frame (3,)."""
        return np.array([-np.sin(self.slope), 0.0, np.cos(self.slope)])

    def ground_height(self, x: float, y: float = 0.0) -> float:
        """Floor height [m] at world (x, y): the terrain's, or the plane's (which contains the
        world y axis)."""
        if self.terrain is not None:
            return self.terrain.height(float(x), float(y))
        return float(x) * np.tan(self.slope)

    # --- commands ----------------------------------------------------------------------------

    def set_torque(self, tau) -> None:
        # MuJoCo clamps ctrl to ctrlrange (the URDF effort limit) inside the step.
        self.data.ctrl[self._act] = self._vector(tau, "tau")

    def apply_push(self, force_world, duration) -> None:
        """Constant force (3,) [N] on the trunk CoM, world frame, for `duration` [s] from now,
        rounded to whole physics steps (impulse = force * steps * timestep). Replaces a push in
        progress; step() clears it when it ends."""
        force = _fixed(force_world, (3,), "force_world")
        duration = float(duration)
        if not np.isfinite(duration) or duration < 0:
            raise InputError(f"duration: expected a non-negative number, got {duration!r}")
        self._push_force = force
        self._push_steps = whole_periods(duration, self.timestep)

    def step(self, n: int = 1) -> None:
        # mj_step2 then mj_step1 instead of mj_step: mj_step computes sensors and site poses before
        # integrating, so after it they would describe the previous state. This way positions,
        # velocities and their sensors describe the current state, at the cost of one mj_step.
        m, d, b = self.model, self.data, self._base_id
        n = int(n)
        for k in range(n):
            if self._push_steps > 0:
                d.xfrc_applied[b, :3] = self._push_force
                self._push_steps -= 1
                self._pushing = True
            elif self._pushing:
                d.xfrc_applied[b, :3] = 0.0
                self._pushing = False
            mujoco.mj_step2(m, d)
            if k == n - 1:
                # Contacts and constraint forces agree only here: mj_step1 re-detects the
                # contacts for the new positions, whose forces the next mj_step2 solves.
                self._foot_forces = self._contact_forces()
            mujoco.mj_step1(m, d)

    def _contact_forces(self) -> np.ndarray:
        m, d = self.model, self.data
        out = np.zeros((len(self.feet), 3))
        f6 = np.zeros(6)
        for i in range(d.ncon):
            c = d.contact[i]
            k1, k2 = self._geom_foot[c.geom1], self._geom_foot[c.geom2]
            if k1 < 0 and k2 < 0:
                continue
            mujoco.mj_contactForce(m, d, i, f6)
            # f6[:3]: force of geom1 on geom2 in the contact frame, whose rows are its axes
            # (normal first, pointing from geom1 to geom2).
            f_world = c.frame.reshape(3, 3).T @ f6[:3]
            if k2 >= 0:
                out[k2] += f_world
            if k1 >= 0:
                out[k1] -= f_world
        return out
