"""The lowest point of a MuJoCo geom in the world [m] (its world z), from the data's kinematics:
where a plant's standing pose puts the ground. Exact per type: a sphere's centre minus its radius,
a capsule's or cylinder's lower end, a box's lowest corner, a mesh's lowest vertex (MuJoCo keeps a
mesh's vertices in its geom frame). Any other type: the bounding sphere (below the geom, never
inside it). A mesh foot's bounding sphere is centred on the mesh's centroid, not on its contact
point: Go2's reaches 18 mm below its lowest vertex, which dropped the robot that far at start."""
from __future__ import annotations

import mujoco
import numpy as np


def geom_bottom(model, data, g: int) -> float:
    kind = int(model.geom_type[g])
    centre = data.geom_xpos[g]
    R = data.geom_xmat[g].reshape(3, 3)
    size = model.geom_size[g]
    if kind == mujoco.mjtGeom.mjGEOM_SPHERE:
        return float(centre[2] - size[0])
    if kind == mujoco.mjtGeom.mjGEOM_CAPSULE:  # axis z, half-length size[1], radius size[0]
        return float(centre[2] - abs(R[2, 2]) * size[1] - size[0])
    if kind == mujoco.mjtGeom.mjGEOM_CYLINDER:  # a disc of radius size[0] at each end
        return float(centre[2] - abs(R[2, 2]) * size[1] - size[0] * np.sqrt(max(0.0, 1.0 - R[2, 2] ** 2)))
    if kind == mujoco.mjtGeom.mjGEOM_BOX:
        return float(centre[2] - np.abs(R[2, :]) @ size)
    if kind == mujoco.mjtGeom.mjGEOM_MESH:
        m = int(model.geom_dataid[g])
        start, count = int(model.mesh_vertadr[m]), int(model.mesh_vertnum[m])
        vertices = model.mesh_vert[start:start + count]
        return float(centre[2] + np.min(vertices @ R[2, :]))
    return float(centre[2] - model.geom_rbound[g])
