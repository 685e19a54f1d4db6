"""The defaults of a robot file's [sim.*] sections, by robot kind: what a MuJoCo plant uses where
the file says nothing.

One table per family, read by two sides that must agree: the robot-file schema (robot/schema.py:
which keys a [sim.*] section accepts, and the type each takes) and the plants (sil/plant.py,
sil/floating_plant.py, sil/aerial_plant.py merge a file's sections over them). They live here, in
robot/, so that loading and checking a robot file needs neither the plants nor MuJoCo.
SI units; quaternions (w, x, y, z).
"""
from __future__ import annotations

# Fixed-base arms (sil/plant.py, MujocoPlant).
ARM = {
    "physics": {"timestep": 0.001, "integrator": "implicitfast",
                "gravity": [0.0, 0.0, -9.81], "floor": True},
    # damping, frictionloss None: the URDF's <dynamics> damping / friction (0 where it has none).
    # armature None: derived (robot/arm.py armature(): a geared actuator's reflected rotor inertia
    # where the URDF declares the joint's losses, else 0).
    "joints": {"damping": None, "frictionloss": None, "armature": None, "q0": None},
    "actuators": {"type": "motor"},
    # body None: the chain's tip link (the robot file's [chain] tip).
    "ee": {"body": None, "site": "ee_site"},
}

# The quadruped plant's solver options (robot files override them in [sim.physics]).
QUADRUPED_PHYSICS = {"timestep": 0.001, "integrator": "implicitfast",
                     "gravity": [0.0, 0.0, -9.81], "cone": "elliptic", "impratio": 100.0,
                     "noslip_iterations": 5}
# Foot links in the controller's leg order when [legs] names none (kiloloop's own quadruped).
QUADRUPED_FEET = ("FL_foot", "FR_foot", "RL_foot", "RR_foot")

# Legged robots on a floating base (sil/floating_plant.py, FloatingBasePlant).
QUADRUPED = {
    "physics": QUADRUPED_PHYSICS,
    "floor": {"enabled": True, "slope_deg": 0.0, "friction": 0.8},
    "joints": {"damping": 0.0, "frictionloss": 0.0, "armature": 0.0, "q0": None},
    # pos0 None: computed so that the lowest foot just touches flat ground at q0 (the plant's
    # _stand_pos).
    "base": {"pos0": None, "quat0": [1.0, 0.0, 0.0, 0.0]},
    "actuators": {"type": "motor"},
    "imu": {"body": None, "site": "imu", "pos": [0.0, 0.0, 0.0]},
    # offset: [m] the foot contact sphere's centre in each foot link's frame (the controller's
    # foot_offset; ANYmal's sits 23 mm up the shank): where each foot's site sits, the point
    # foot_positions() reports. Zero: the link origin.
    "feet": {"bodies": list(QUADRUPED_FEET), "offset": [0.0, 0.0, 0.0]},
}

# Multirotors, with or without an arm (sil/aerial_plant.py, AerialPlant).
AERIAL = {
    "physics": {"timestep": 0.001, "integrator": "implicitfast", "gravity": [0.0, 0.0, -9.81]},
    "joints": {"damping": 0.0, "frictionloss": 0.0, "armature": 0.0, "q0": None},
    "base": {"pos0": [0.0, 0.0, 1.0], "quat0": [1.0, 0.0, 0.0, 0.0]},
    "actuators": {"type": "motor"},
    # Per-rotor thrust and drag-torque scale (a damaged propeller); None: 1 for every rotor.
    "rotors": {"efficiency": None},
    "imu": {"body": None, "site": "imu", "pos": [0.0, 0.0, 0.0]},
    "ee": {"site": "ee_site"},
}

BY_KIND = {"arm": ARM, "quadruped": QUADRUPED, "aerial": AERIAL}
