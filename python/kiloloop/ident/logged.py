"""The signals an excitation keeps: what a real robot's logger has, described (unit, label)."""
from __future__ import annotations

import numpy as np

from ..sil.log import SignalLog


def keep(log: SignalLog, names: dict, out: SignalLog | None = None) -> SignalLog:
    """A log of the named signals only (name -> (unit, label); ground truth left out)."""
    out = SignalLog() if out is None else out
    for name, (unit, label) in names.items():
        out.put_array(name, np.asarray(log[name], float))
        out.describe(name, unit, label=label)
    return out
