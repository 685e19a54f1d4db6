"""Every key a robot file accepts, by robot kind. An unknown key is an error naming it and the file.

A schema is a nested dict of templates: a dict recurses, FREE accepts any value (its contents are
checked by whoever reads them), any other value is the key's default (documentation only; the
readers apply defaults). Families register their sections here; controller and sim sections come
from the readers' own default tables (sim_defaults.py, which the plants merge files over; the
QuadrupedConfig struct) so that they cannot drift apart.
"""
from __future__ import annotations

import math

from . import sim_defaults
from .quadruped import controller_schema

FREE = object()  # any value (a table of user-chosen names, or a value checked elsewhere)
# A number or a list of numbers, no default (per-joint values: their count is the reader's check,
# against the robot's joints).
NUMBERS = object()

KINDS = ("arm", "quadruped", "aerial")

_COMMON = {
    "name": "", "kind": "", "urdf": "", "package_dirs": [], "description": "",
    "scenario": FREE,   # [scenario.<name>]: checked against that scenario's settings
    # How the URDF is read, by the controller's model and the plant alike (robot/urdf_doc.py):
    # link inertias MuJoCo refuses balanced (robot/urdf_inertia.py) instead of refused, and
    # [limits.<joint>] tables of lower, upper, velocity, effort (robot/joint_limits.py).
    "balance_inertia": False,
    "limits": FREE,
}


def _sim(kind: str) -> dict:
    return {section: dict(values) for section, values in sim_defaults.BY_KIND[kind].items()}


def _arm() -> dict:
    return {
        # The controlled chain; joints off it (grippers, mimic joints) are locked at `locked`
        # (joint name -> [rad] or [m], default 0) and their links folded in as rigid mass.
        "chain": {"root": "", "tip": "", "locked": FREE, "q0": NUMBERS},
        "controller": {
            "bandwidth": 30.0,       # [rad/s] joint error bandwidth (computed torque omega_n)
            "damping_ratio": 1.0,    # [-]
            "kp": NUMBERS, "kd": NUMBERS,  # explicit per-joint (or scalar) gains override the above
            "max_measurement_age": 0.005,  # [s]
            # Joint friction the controllers compensate; default: the URDF's <dynamics damping
            # friction> of the chain joints (scalar or one per joint).
            "friction_compensation": True,
            "viscous_friction": NUMBERS,   # [N m s/rad]
            "coulomb_friction": NUMBERS,   # [N m]
            "friction_smoothing_speed": 0.01,  # [rad/s]
        },
        "sim": _sim("arm"),
        # Link capsules for planning: { link = [[x0,y0,z0, x1,y1,z1, r], ...] } in the link frame;
        # links with mesh collision geometry get capsules fitted to the mesh otherwise.
        "collision": {"capsules": FREE, "margin": 0.02},
    }


def _quadruped() -> dict:
    return {
        "legs": {"base": "", "feet": []},
        # Fields of kl.QuadrupedConfig ([controller.gait] etc. for its nested structs).
        "controller": controller_schema(),
        "sim": _sim("quadruped"),
    }


def _aerial() -> dict:
    return {
        "vehicle": {"base": "", "ee": ""},
        "rotors": FREE,      # [[rotors]] tables, checked by the aerial reader
        "controller": FREE,  # fields of kl.AerialConfig (dotted for nested structs)
        "sim": _sim("aerial"),
    }


_FAMILIES = {"arm": _arm, "quadruped": _quadruped, "aerial": _aerial}


def schema_for(kind: str) -> dict:
    out = dict(_COMMON)
    out.update(_FAMILIES[kind]())
    return out


def unknown_keys(data: dict, template: dict, prefix: str = "") -> list[str]:
    """Dotted paths of keys in `data` that `template` does not know (first level of FREE only)."""
    bad = []
    for key, value in data.items():
        path = f"{prefix}{key}"
        if key not in template:
            bad.append(path)
            continue
        sub = template[key]
        if sub is FREE or sub is NUMBERS:
            continue
        if isinstance(sub, dict):
            if not isinstance(value, dict):
                bad.append(f"{path} (expected a table)")
                continue
            bad.extend(unknown_keys(value, sub, path + "."))
    return bad


def bad_values(data: dict, template: dict, prefix: str = "") -> list[str]:
    """Dotted paths, each with what is wrong, of values that cannot be what their key documents:
    a number that is not finite (NaN or Inf: no setting means either; anywhere in the file, FREE
    tables included), and where the template's default is a number, a string or a boolean, a value
    of another type (a number's key also takes a list of numbers: per-joint values)."""
    bad = []
    for key, value in data.items():
        path = f"{prefix}{key}"
        sub = template.get(key, FREE) if isinstance(template, dict) else FREE
        if isinstance(value, dict):
            bad.extend(bad_values(value, sub if isinstance(sub, dict) else FREE, path + "."))
            continue
        if not _finite(value):
            bad.append(f"{path}: not a finite number (NaN or Inf)")
            continue
        if sub is FREE or isinstance(sub, dict) or sub is None:
            continue
        if sub is NUMBERS or (isinstance(sub, (int, float)) and not isinstance(sub, bool)):
            items = value if isinstance(value, list) else [value]
            if not items or not all(_number(v) for v in items):
                bad.append(f"{path}: expected a number (or a list of numbers), got {value!r}")
        elif isinstance(sub, bool):
            if not isinstance(value, bool):
                bad.append(f"{path}: expected true or false, got {value!r}")
        elif isinstance(sub, str) and not isinstance(value, str):
            bad.append(f"{path}: expected a string, got {value!r}")
    return bad


def _number(v) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def _finite(value) -> bool:
    """False when value is, or contains (lists, tables), a NaN or an infinity."""
    if isinstance(value, float):
        return math.isfinite(value)
    if isinstance(value, list):
        return all(_finite(v) for v in value)
    if isinstance(value, dict):
        return all(_finite(v) for v in value.values())
    return True
