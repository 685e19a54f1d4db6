"""Software-in-the-loop: the MuJoCo plant and the glue that drives the control core against it.

The rig: `kl.sil.Rig(robot, signals)` (sil/rig.py; one for every family, over the native loop);
batch runs: `kl.sil.run_batch(rollouts, threads)` (native rollouts on C++ threads, sil/batch.py);
logs: `kl.sil.SignalLog.load(path)` (.npz or .mcap, sil/log.py).
"""
from __future__ import annotations

import importlib as _importlib


def __getattr__(name: str):
    # Lazy: importing kiloloop.sil must not pull in mujoco or the scenarios.
    if name in ("batch", "native", "events", "signals", "rig"):
        return _importlib.import_module(f".{name}", __name__)
    if name == "run_batch":
        return _importlib.import_module(".batch", __name__).run
    if name in ("SignalLog", "load_log"):   # logs: .npz and .mcap (sil/log.py)
        return getattr(_importlib.import_module(".log", __name__), name)
    if name in ("Rig", "Signals"):
        return getattr(_importlib.import_module(f".{name.lower()}", __name__), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
