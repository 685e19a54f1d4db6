"""A plant's MjSpec compiled, and MuJoCo's refusal, when it still refuses, said in the URDF's terms.

robot/urdf_inertia.py repairs or refuses the inertias MuJoCo's compiler would refuse before it
sees them; what only the compiled tree shows is said here: a link that moves (a joint of its own,
not welded) while neither it nor the links fixed to it carry mass and rotational inertia (a
massless intermediate link of a two-axis joint). MuJoCo's own words ("mass and inertia of moving
bodies must be larger than mjMINVAL") name neither the URDF's link nor the fix.
"""
from __future__ import annotations

import re
from pathlib import Path

from ..errors import InputError

# MuJoCo's message -> what it means for the URDF's link, and what the user can do.
_MEANINGS = {
    "mass and inertia of moving bodies must be larger than mjMINVAL":
        "moves on a joint of its own, but neither it nor the links fixed to it carry mass and "
        "rotational inertia (MuJoCo cannot accelerate it); give it an <inertial> with a mass "
        "and an inertia in the URDF",
    "inertia must satisfy A + B >= C":
        "has principal moments that, as MuJoCo computes them, break A + B >= C; correct the "
        "URDF's <inertia>, or set `balance_inertia = true` in the robot file",
    "inertia must have positive eigenvalues":
        "has an inertia that is not positive definite; correct the URDF's <inertia>",
}


def compile_spec(spec, urdf_path: Path):
    """spec.compile(), or an InputError naming the URDF, the link and the fix."""
    try:
        return spec.compile()
    except ValueError as e:
        text = str(e)
        link = re.search(r"Element name '([^']*)'", text)
        for words, meaning in _MEANINGS.items():
            if words in text and link:
                raise InputError(f"MuJoCo refuses {Path(urdf_path).name}: link "
                                 f"'{link.group(1)}' {meaning}") from None
        raise InputError(f"MuJoCo refuses {Path(urdf_path).name}: "
                         f"{' '.join(text.split())}") from None
