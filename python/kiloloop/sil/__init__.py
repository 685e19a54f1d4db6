"""Software-in-the-loop: the MuJoCo plant and the glue that drives the control core against it.

Batch runs: `kl.sil.run_batch(rollouts, threads)` (native rollouts on C++ threads) and
`kl.sil.run_scenarios(scenario, runs, threads)` (sil/batch.py); the native loop: sil/native.py.
"""
from __future__ import annotations

import importlib as _importlib


def __getattr__(name: str):
    # Lazy: importing kiloloop.sil must not pull in mujoco or the scenarios.
    if name in ("batch", "native"):
        return _importlib.import_module(f".{name}", __name__)
    if name in ("run_batch", "run_scenarios"):
        batch = _importlib.import_module(".batch", __name__)
        return batch.run if name == "run_batch" else batch.run_scenarios
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
