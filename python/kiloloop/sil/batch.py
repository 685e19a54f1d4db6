"""Many SIL runs at once on one machine (MuJoCo's `rollout` shape).

`run(rollouts, threads)`: native Rollouts (sil/rig.py Rig.rollout), each with its own MjData and
controller objects, on a pool of C++ threads with the GIL released. The loop is deterministic and
rollouts share nothing mutable, so results do not depend on the thread count. Whole scenario
runs at once: scenarios/batch.py (a layer up).

    from kiloloop.sil import batch
    rollouts = [rig.rollout(4.5, reference, data=mujoco.MjData(rig.plant.model))
                for reference in references]
    batch.run(rollouts, threads=2)

Each new MjData starts at the plant's state (native.start_state: a copy of plant.data), as the
plant's own data would; the README's batch example runs in tests/test_doc_snippets.py.
"""
from __future__ import annotations

import os

from . import native


def run(rollouts: list, threads: int | None = None) -> list:
    """Runs every native Rollout once on `threads` C++ threads (default: all cores); returns the
    rollouts (read .ok, .error, .log() or native.signal_log(r)). A failed rollout (a MuJoCo
    error) is reported in its .ok/.error; the others go on."""
    native.check()
    threads = max(1, int(threads or os.cpu_count() or 1))
    native._native.run_batch(list(rollouts), threads)
    return list(rollouts)
