"""Does MuJoCo's heightfield hold a foot that sinks into it? A probe behind bench/go1_35ms_diagnosis.md
("Rough ground at 35 ms").

A 20 mm sphere (the quadrupeds' foot radius), 0.3 kg, moving forward at 0.5 m/s, hits flat ground
at 1, 2 and 3 m/s downward. The ground is a plane (what quadruped-trot stands on) or a flat
heightfield built by the rough terrain (sil/terrain.py Rough, amplitude 0) with its 2 cm cells
(quadruped-rough's), collided by MuJoCo's prism collider (smooth_contact=False) or by kiloloop's
(cpp/sil/smooth_heightfield.hpp), with MuJoCo's default contact time constant (20 ms) and
quadruped-rough's (8 ms). The physics options are the quadruped plant's (sil/floating_plant.py:
elliptic cone, impratio 100, noslip 5, implicitfast, 1 ms). Prints the deepest penetration, where
the sphere rests 150 ms after the hit [mm below the surface] and the most contacts at once. Then
the contact normals of a sphere held at given depths in the 2 cm heightfield.

    .venv/bin/python scripts/hfield_trap_probe.py
"""
from __future__ import annotations

import mujoco
import numpy as np

from kiloloop.sil.floating_plant import DEFAULT_PHYSICS, set_friction_options
from kiloloop.sil.terrain import Rough

RADIUS = 0.02  # [m]
MASS = 0.3     # [kg]


def build(ground: str, time_constant: float = 0.02):
    """ground "plane" (z = 0), "prisms" or "smooth" (a flat 2 cm heightfield, each collider)."""
    spec = mujoco.MjSpec()
    set_friction_options(spec, DEFAULT_PHYSICS)
    spec.option.integrator = mujoco.mjtIntegrator.mjINT_IMPLICITFAST
    spec.option.timestep = DEFAULT_PHYSICS["timestep"]
    if ground == "plane":
        spec.worldbody.add_geom(type=mujoco.mjtGeom.mjGEOM_PLANE, size=[0, 0, 0.05])
    else:
        Rough(amplitude=0.0, bump_length=0.3, contact_time_constant=time_constant,
              smooth_contact=ground == "smooth").add_to(spec, 0.8)
    body = spec.worldbody.add_body(name="foot", pos=[1.2, 0.15, 0.1])
    body.add_freejoint()
    body.add_geom(type=mujoco.mjtGeom.mjGEOM_SPHERE, size=[RADIUS, 0, 0], mass=MASS)
    model = spec.compile()
    return model, mujoco.MjData(model)


def drop(model, data, x: float, vz: float) -> tuple[float, float, int]:
    """Deepest penetration and the one 150 ms after a hit at vz [m/s] (mm below the surface), and
    the most contacts at once."""
    mujoco.mj_resetData(model, data)
    data.qpos[:3] = [x, 0.15, RADIUS + 0.001]
    data.qvel[0], data.qvel[2] = 0.5, vz
    deepest, most = 0.0, 0
    for _ in range(150):
        mujoco.mj_step(model, data)
        deepest = max(deepest, RADIUS - data.qpos[2])
        most = max(most, data.ncon)
    return 1e3 * deepest, 1e3 * (RADIUS - data.qpos[2]), most


def main() -> None:
    for label, ground, tc in (("plane, 20 ms", "plane", 0.02), ("prisms, 20 ms", "prisms", 0.02),
                              ("prisms, 8 ms", "prisms", 0.008), ("smooth, 20 ms", "smooth", 0.02),
                              ("smooth, 8 ms", "smooth", 0.008)):
        model, data = build(ground, tc)
        rows = []
        for vz in (-1.0, -2.0, -3.0):
            sunk = [drop(model, data, x, vz) for x in (1.2, 1.205, 1.21, 1.2133)]
            rows.append(f"{-vz:.0f} m/s: deepest {max(s[0] for s in sunk):5.1f}, "
                        f"after 150 ms {max(s[1] for s in sunk):5.1f}, "
                        f"contacts {max(s[2] for s in sunk)}")
        print(f"{label:<14} " + " | ".join(rows))
    for ground in ("prisms", "smooth"):
        model, data = build(ground)
        print(f"tilt from vertical [deg] of the contact normals of a sphere held at a depth in the "
              f"2 cm heightfield, {ground} (flat: all should be 0):")
        for depth in (0.002, 0.005, 0.010, 0.015, 0.020, 0.030):
            mujoco.mj_resetData(model, data)
            data.qpos[:3] = [1.207, 0.157, RADIUS - depth]
            mujoco.mj_forward(model, data)
            tilts = sorted({round(float(np.degrees(np.arccos(min(1.0, abs(data.contact[i].frame[2]))))))
                            for i in range(data.ncon)})
            print(f"  {1e3 * depth:4.1f} mm: {data.ncon} contacts, tilts {tilts}")


if __name__ == "__main__":
    main()
