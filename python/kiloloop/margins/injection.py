"""A loop's frequency response by injection in the native closed loop: a seeded multi-sine d
added along the loop's direction as a generalized force (what the actuators would apply,
margins/loops.py), the return r = w . actuator_force read back every tick; the plant sees
s = r + d, so at each excited frequency L = -R / S = -R / (R + D) (DFT lines of whole periods,
the first period dropped as the transient).

The multi-sine: `lines` log-spaced DFT bins of a `period`-tick period between w_min and w_max
[rad/s], equal amplitudes, random phases from the seed; its RMS is FRACTION of the loop's
authority (the largest signal along v within the actuators' limits).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..sil import native
from ..sil.family import CONTROL_DT

PERIOD = 4096      # [ticks] one multi-sine period (1.53 rad/s resolution at 1 kHz)
PERIODS = 2        # analysed periods after the transient one
LINES = 40
FRACTION = 0.02    # of the loop's authority, RMS


@dataclass(frozen=True)
class MultiSine:
    bins: np.ndarray      # DFT bins of one period
    amplitude: float      # per line
    phases: np.ndarray    # [rad]
    period: int           # [ticks]

    @property
    def w(self) -> np.ndarray:
        """[rad/s] the excited frequencies"""
        return 2 * np.pi * self.bins / (self.period * CONTROL_DT)

    def at(self, k: np.ndarray) -> np.ndarray:
        arg = 2 * np.pi * np.outer(k, self.bins) / self.period + self.phases
        return self.amplitude * np.cos(arg).sum(axis=1)


def multisine(w_min: float, w_max: float, rms: float, seed: int, lines: int = LINES,
              period: int = PERIOD) -> MultiSine:
    res = 2 * np.pi / (period * CONTROL_DT)
    bins = np.unique(np.round(np.logspace(np.log10(max(np.ceil(w_min / res), 1.0)),
                                          np.log10(w_max / res), lines)).astype(int))
    phases = np.random.default_rng(seed).uniform(0.0, 2 * np.pi, len(bins))
    return MultiSine(bins, rms * np.sqrt(2.0 / len(bins)), phases, period)


def inject(op, loop, signal: MultiSine, periods: int = PERIODS):
    """(w [rad/s], L) at the multi-sine's lines, and the run's (d, r) series."""
    acts = [int(a) for a in op.rig.family.actuators(op.rig.parts)]
    n = signal.period * (periods + 1)
    probe = ("margins_return", native._ACTUATOR_FORCE, acts)
    r, data = op.rollout(n + 1, probes=[probe])
    r.advance(op.settle_ticks)
    d = signal.at(np.arange(n))
    for k in range(n + 1):
        data.qfrc_applied[:] = loop.qfrc * (d[k] if k < n else 0.0)
        r.advance(1)
    if not r.ok or r.diverged:
        raise RuntimeError(f"margins: the injection run failed at tick {r.ticks_run}: "
                           f"{r.error or 'diverged'}")
    forces = r.log()["margins_return"][op.settle_ticks:]
    # The probe at a tick's start reads the force of the step before: r[k] = row k + 1.
    ret = forces[1:n + 1] @ loop.w
    ret = ret - ret[signal.period:].mean()
    keep = slice(signal.period, n)
    R, Dd = np.fft.rfft(ret[keep]), np.fft.rfft(d[keep])
    lines = signal.bins * periods
    L = -R[lines] / (R[lines] + Dd[lines])
    return signal.w, L, d, ret
