"""Stability margins of a loop from its frequency response L(jw) (the return ratio at the break:
the loop is stable with margin when 1 + L stays clear of zero):

  crossover [rad/s]       where |L| falls through 1 (the one of least phase margin)
  phase margin [deg]      180 + arg L there (wrapped to (-180, 180])
  delay margin [s]        phase margin [rad] / crossover: the pure delay added to the loop that
                          brings L onto -1 at the crossover
  gain margin [dB]        -20 log10 |L| where L crosses the negative real axis with |L| < 1 (the
                          gain increase that makes it -1); inf when it never does

Crossings are interpolated linearly between grid points (log |L| and phase over log w).
"""
from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np


@dataclass(frozen=True)
class Margins:
    gain_margin_db: float
    phase_margin_deg: float
    delay_margin_s: float
    crossover_rad_s: float
    phase_crossover_rad_s: float

    def as_dict(self) -> dict:
        return {k: (None if not math.isfinite(v) else float(v)) for k, v in asdict(self).items()}


def grid(w_min: float, w_max: float, n: int) -> np.ndarray:
    """[rad/s] n log-spaced frequencies."""
    return np.logspace(np.log10(w_min), np.log10(w_max), int(n))


def _wrap(angle: np.ndarray) -> np.ndarray:
    """(-pi, pi]"""
    return np.pi - np.mod(np.pi - angle, 2 * np.pi)


def margins(w: np.ndarray, L: np.ndarray) -> Margins:
    """The margins of L (complex, at increasing w [rad/s])."""
    w, L = np.asarray(w, float), np.asarray(L, complex)
    lw = np.log(w)
    mag = np.log(np.abs(L))
    phase = np.unwrap(np.angle(L))
    pm, wc = math.inf, math.nan
    for k in np.nonzero((mag[:-1] >= 0) & (mag[1:] < 0))[0]:
        a = mag[k] / (mag[k] - mag[k + 1])
        w_c = math.exp(lw[k] + a * (lw[k + 1] - lw[k]))
        ph = phase[k] + a * (phase[k + 1] - phase[k])
        m = float(_wrap(np.array(ph + np.pi)))
        if m < pm:
            pm, wc = m, w_c
    gm, wp = math.inf, math.nan
    # Crossings of the negative real axis: the phase through -180 deg (mod 360).
    turns = np.floor((phase + np.pi) / (2 * np.pi))
    for k in np.nonzero(turns[:-1] != turns[1:])[0]:
        target = 2 * np.pi * max(turns[k], turns[k + 1]) - np.pi
        a = (target - phase[k]) / (phase[k + 1] - phase[k])
        gain = mag[k] + a * (mag[k + 1] - mag[k])
        if gain < 0 and -gain < gm:
            gm, wp = -gain, math.exp(lw[k] + a * (lw[k + 1] - lw[k]))
    gm_db = 20 * gm / math.log(10) if math.isfinite(gm) else math.inf
    delay = pm / wc if math.isfinite(pm) and wc > 0 else math.inf
    return Margins(gm_db, math.degrees(pm), delay, wc, wp)
