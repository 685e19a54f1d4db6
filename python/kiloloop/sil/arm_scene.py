"""Scene additions for the arm scenarios, applied to a MujocoPlant's MjSpec before it compiles
(MujocoPlant(..., scene=fn)): box obstacles, a table, a tool tip with a 3-axis force sensor.

Collision bits: robot links are contype 0 / conaffinity 1 (sil/plant.py); box obstacles are 3 / 3
so they touch the links and the tool tip; the tip is 2 / 2 so it touches the table and obstacles
but never the arm it is mounted on; the table (a plane) is 2 / 2, the tip only.
"""
from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np

from ..errors import InputError


def add_box(spec, name: str, center, half_extents, *, friction: float = 1.0,
            rgba=(0.8, 0.3, 0.2, 0.6)) -> None:
    """A static box in the world [m]."""
    spec.worldbody.add_geom(name=name, type=mujoco.mjtGeom.mjGEOM_BOX,
                            pos=np.asarray(center, dtype=float),
                            size=np.asarray(half_extents, dtype=float),
                            contype=3, conaffinity=3, rgba=list(rgba),
                            friction=[float(friction), 0.005, 0.0001])


def add_table(spec, name: str, center, half_size, *, friction: float = 1.0, solref=None,
              solimp=None, rgba=(0.6, 0.5, 0.4, 1.0)) -> None:
    """A horizontal table top: a finite plane whose surface is at center[2] [m] (only the top
    matters for pressing on it). A plane is a half-space to MuJoCo, so it touches only the tool
    tip (bits 2 / 2), never the links below its surface. solref / solimp: MuJoCo contact
    softness of the table (None: MuJoCo's defaults)."""
    geom = spec.worldbody.add_geom(name=name, type=mujoco.mjtGeom.mjGEOM_PLANE,
                                   pos=np.asarray(center, dtype=float),
                                   size=[float(half_size[0]), float(half_size[1]), 0.01],
                                   contype=2, conaffinity=2, rgba=list(rgba),
                                   friction=[float(friction), 0.005, 0.0001])
    # A contact pair mixes both geoms' solref/solimp (solmix, equal weights by default).
    if solref is not None:
        geom.solref = list(solref)
    if solimp is not None:
        geom.solimp = list(solimp)


@dataclass(frozen=True)
class ToolTip:
    """A sphere rigidly mounted on a link at `offset` (link frame) [m], with a force sensor and
    the site's orientation (a framequat sensor: the native loop turns the force into the world
    frame from the measurement alone, sil/native.py press_adapter)."""

    parent: str = "tool0"
    offset: tuple = (0.0, 0.0, 0.02)   # [m] sphere centre in the parent frame
    radius: float = 0.01               # [m]
    mass: float = 0.001                # [kg] (negligible next to the 0.19 kg wrist 3)
    friction: float = 1.0              # Coulomb coefficient (MuJoCo takes the larger of a pair's)
    body: str = "tool_tip"
    site: str = "tool_tip_site"
    sensor: str = "tool_tip_force"
    quat_sensor: str = "tool_tip_quat"

    def __call__(self, spec) -> None:
        parent = spec.body(self.parent)
        if parent is None:
            raise InputError(f"tool tip: no link named {self.parent!r}")
        # No joint: welded to the parent. The force sensor measures what the parent transmits.
        body = parent.add_body(name=self.body, pos=list(self.offset), mass=self.mass,
                               inertia=[1e-8, 1e-8, 1e-8])
        body.add_geom(name=self.body, type=mujoco.mjtGeom.mjGEOM_SPHERE, size=[self.radius, 0, 0],
                      contype=2, conaffinity=2, friction=[self.friction, 0.005, 0.0001])
        body.add_site(name=self.site)
        spec.add_sensor(name=self.sensor, type=mujoco.mjtSensor.mjSENS_FORCE,
                        objtype=mujoco.mjtObj.mjOBJ_SITE, objname=self.site)
        # World <- site orientation (w, x, y, z), read with the force in the same tick.
        spec.add_sensor(name=self.quat_sensor, type=mujoco.mjtSensor.mjSENS_FRAMEQUAT,
                        objtype=mujoco.mjtObj.mjOBJ_SITE, objname=self.site)

    def measurement_addresses(self, model) -> list[int]:
        """sensordata addresses of [force in the site frame (3) [N]; site quaternion (4)]: the
        press adapter's entries after [q; qd] (native.rollout(extra_measurement=...))."""
        force, quat = (int(model.sensor_adr[model.sensor(n).id]) for n in (self.sensor, self.quat_sensor))
        return list(range(force, force + 3)) + list(range(quat, quat + 4))


def compose(*fns):
    """One scene function that applies several in order."""
    def scene(spec):
        for fn in fns:
            fn(spec)
    return scene


def tip_force_world(plant, tip: ToolTip) -> np.ndarray:
    """Force [N] that the tool tip applies on what it touches, in the world frame.

    MuJoCo's force sensor gives the force the child body (the tip) receives from its parent, in
    the site frame. In quasi-static contact the parent pushes the tip with what the tip pushes
    on the environment (the tip's own weight, 0.01 N, aside), so that is the applied force.
    """
    m, d = plant.model, plant.data
    sid = m.sensor(tip.sensor).id
    adr = m.sensor_adr[sid]
    f_site = d.sensordata[adr:adr + 3]
    R = d.site_xmat[m.site(tip.site).id].reshape(3, 3)
    return R @ f_site


def robot_geoms(plant, exclude=("floor",)) -> list[int]:
    """Geom ids of the robot's links (contype 0), i.e. everything the arm could hit things with."""
    m = plant.model
    return [g for g in range(m.ngeom) if m.geom_contype[g] == 0 and m.geom(g).name not in exclude]


def contacts_with(plant, geom_id: int) -> int:
    """Number of active contacts involving geom_id."""
    d = plant.data
    return sum(1 for i in range(d.ncon) if geom_id in (d.contact[i].geom1, d.contact[i].geom2))


def min_distance(plant, geom_id: int, others, distmax: float = 1.0) -> float:
    """Smallest signed distance [m] between geom_id and any of `others` (MuJoCo's narrow phase)."""
    fromto = np.zeros(6)
    return min(mujoco.mj_geomDistance(plant.model, plant.data, geom_id, g, distmax, fromto)
               for g in others)
