"""Every key a robot file accepts, by robot kind. An unknown key is an error naming it and the file.

A schema is a nested dict of templates: a dict recurses, FREE accepts any value (its contents are
checked by whoever reads them), any other value is the key's default (documentation only; the
readers apply defaults). Families register their sections here; controller and sim sections come
from the readers' own default tables so that they cannot drift apart.
"""
from __future__ import annotations

FREE = object()  # any value (a table of user-chosen names, or a value checked elsewhere)

KINDS = ("arm", "quadruped", "aerial")

_COMMON = {
    "name": "", "kind": "", "urdf": "", "package_dirs": [], "description": "",
    "scenario": FREE,   # [scenario.<name>]: checked against that scenario's settings
}


def _arm() -> dict:
    from ..sil.plant import _DEFAULTS as plant

    return {
        # The controlled chain; joints off it (grippers, mimic joints) are locked at `locked`
        # (joint name -> [rad] or [m], default 0) and their links folded in as rigid mass.
        "chain": {"root": "", "tip": "", "locked": FREE, "q0": FREE},
        "controller": {
            "bandwidth": 30.0,       # [rad/s] joint error bandwidth (computed torque omega_n)
            "damping_ratio": 1.0,    # [-]
            "kp": FREE, "kd": FREE,  # explicit per-joint (or scalar) gains override the above
            "max_measurement_age": 0.005,  # [s]
            # Joint friction the controllers compensate; default: the URDF's <dynamics damping
            # friction> of the chain joints (scalar or one per joint).
            "friction_compensation": True,
            "viscous_friction": FREE,      # [N m s/rad]
            "coulomb_friction": FREE,      # [N m]
            "friction_smoothing_speed": 0.01,  # [rad/s]
        },
        "sim": {section: dict(values) for section, values in plant.items()},
        # Link capsules for planning: { link = [[x0,y0,z0, x1,y1,z1, r], ...] } in the link frame;
        # links with mesh collision geometry get capsules fitted to the mesh otherwise.
        "collision": {"capsules": FREE, "margin": 0.02},
    }


def _quadruped() -> dict:
    from ..sil.floating_plant import _DEFAULTS as plant

    return {
        "legs": {"base": "", "feet": []},
        "controller": FREE,  # fields of kl.QuadrupedConfig (dotted for nested structs)
        "sim": {section: dict(values) for section, values in plant.items()},
    }


def _aerial() -> dict:
    from ..sil.aerial_plant import _DEFAULTS as plant

    return {
        "vehicle": {"base": "", "ee": ""},
        "rotors": FREE,      # [[rotors]] tables, checked by the aerial reader
        "controller": FREE,  # fields of kl.AerialConfig (dotted for nested structs)
        "sim": {section: dict(values) for section, values in plant.items()},
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
        if sub is FREE:
            continue
        if isinstance(sub, dict):
            if not isinstance(value, dict):
                bad.append(f"{path} (expected a table)")
                continue
            bad.extend(unknown_keys(value, sub, path + "."))
    return bad
