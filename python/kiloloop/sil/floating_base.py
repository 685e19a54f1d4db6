"""What the free-floating plants (legged: floating_plant.py, aerial: aerial_plant.py) build and
read the same way: the free joint on the URDF root link, the IMU site and its sensors, the model
addresses they look up once, and the ground-truth and IMU readouts. SI units; quaternions
(w, x, y, z), world <- body.
"""
from __future__ import annotations

from pathlib import Path

import mujoco
import numpy as np

from ..errors import InputError
from .plant import joint_addresses

FREE_JOINT = "floating_base"
_IMU_KINDS = (("gyro", mujoco.mjtSensor.mjSENS_GYRO),
              ("accel", mujoco.mjtSensor.mjSENS_ACCELEROMETER),
              ("quat", mujoco.mjtSensor.mjSENS_FRAMEQUAT))


def fixed(x, shape: tuple, name: str) -> np.ndarray:
    """x as a finite float array of exactly `shape`; ValueError naming `name` otherwise."""
    arr = np.asarray(x, dtype=float)
    if arr.shape != shape:
        raise ValueError(f"{name}: expected shape {shape}, got {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name}: non-finite value")
    return arr


def unit_quat(x, name: str) -> np.ndarray:
    q = fixed(x, (4,), name)
    norm = np.linalg.norm(q)
    if norm < 1e-9:
        raise ValueError(f"{name}: zero quaternion")
    return q / norm


def add_free_base(spec, urdf_path: Path):
    """Gives the URDF root link (the only child of the world) the six free DoFs; returns it."""
    root = spec.worldbody.first_body()
    if root is None:
        raise InputError(f"{urdf_path}: no links")
    root.add_freejoint(name=FREE_JOINT)
    return root


def add_imu(spec, imu: dict, base_body: str, urdf_path: Path) -> str:
    """An IMU site on imu["body"] (default: the base) at imu["pos"] with a gyro, an accelerometer
    and an orientation sensor named <site>_gyro, _accel, _quat; returns the site name."""
    body = spec.body(imu["body"] or base_body)
    if body is None:
        raise InputError(f"imu.body: no link named {imu['body']!r} in {urdf_path}")
    site = imu["site"]
    body.add_site(name=site, pos=fixed(imu["pos"], (3,), "imu.pos"))
    for kind, stype in _IMU_KINDS:
        spec.add_sensor(name=f"{site}_{kind}", type=stype, objtype=mujoco.mjtObj.mjOBJ_SITE,
                        objname=site)
    return site


class FloatingBaseReadout:
    """Mixin for a compiled plant with `model`, `data`, `joint_names`, `base_body`, `imu_site`:
    call `_index_floating_base()` once after compiling."""

    def _index_floating_base(self) -> None:
        m = self.model
        (self._qadr, self._dadr, self._act, self._pos_sens,
         self._vel_sens) = joint_addresses(m, self.joint_names)
        free = m.joint(FREE_JOINT)
        self._free_q = int(free.qposadr[0])
        self._free_d = int(free.dofadr[0])
        self._imu_adr = {k: int(m.sensor_adr[m.sensor(f"{self.imu_site}_{k}").id])
                         for k, _ in _IMU_KINDS}
        self._base_id = m.body(self.base_body).id
        self.total_mass = float(mujoco.mj_getTotalmass(m))

    def _set_base_pose(self, d, base_pos, base_quat) -> None:
        """Writes the free joint's position and orientation (None: the plant's initial pose)."""
        fq = self._free_q
        d.qpos[fq:fq + 3] = self.base_pos0 if base_pos is None else fixed(base_pos, (3,),
                                                                          "base_pos")
        d.qpos[fq + 3:fq + 7] = (self.base_quat0 if base_quat is None
                                 else unit_quat(base_quat, "base_quat"))

    @property
    def timestep(self) -> float:
        return float(self.model.opt.timestep)

    def time(self) -> float:
        return float(self.data.time)

    # --- sensors (what a robot measures) -----------------------------------------------------

    def joint_q(self) -> np.ndarray:
        """Joint encoder positions (nq,) [rad]."""
        return self.data.sensordata[self._pos_sens].copy()

    def joint_qd(self) -> np.ndarray:
        """Joint encoder velocities (nq,) [rad/s]."""
        return self.data.sensordata[self._vel_sens].copy()

    # The names the fixed-base SIL loop (sil/loop.py) expects of a plant.
    q = joint_q
    qd = joint_qd

    def imu(self) -> dict:
        """Ideal IMU at the IMU site: "gyro" (3,) [rad/s] and "accel" (3,) [m/s^2] in the body
        frame, the accelerometer reading specific force (+g up at rest); "quat" (4,) w, x, y, z,
        world <- body."""
        s, a = self.data.sensordata, self._imu_adr
        return {"gyro": s[a["gyro"]:a["gyro"] + 3].copy(),
                "accel": s[a["accel"]:a["accel"] + 3].copy(),
                "quat": s[a["quat"]:a["quat"] + 4].copy()}

    # --- ground truth (what only the simulator knows) ----------------------------------------

    def base_pose(self) -> tuple[np.ndarray, np.ndarray]:
        """Base link origin position (3,) [m] and orientation quat (4,) w, x, y, z, world <- base."""
        fq = self._free_q
        return self.data.qpos[fq:fq + 3].copy(), self.data.qpos[fq + 3:fq + 7].copy()

    def base_velocity(self) -> tuple[np.ndarray, np.ndarray]:
        """Base link origin linear velocity in the world frame (3,) [m/s] and angular velocity in
        the base frame (3,) [rad/s] (MuJoCo's free-joint convention)."""
        fd = self._free_d
        return self.data.qvel[fd:fd + 3].copy(), self.data.qvel[fd + 3:fd + 6].copy()
