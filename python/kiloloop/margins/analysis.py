"""One loop analysed both ways at its operating point (margins/__init__.py)."""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..errors import InputError
from ..sil.family import CONTROL_DT
from . import injection, linearization
from .frequency_response import Margins, grid, margins
from .loops import loop_of

NYQUIST = np.pi / CONTROL_DT          # [rad/s]
W_MIN = 2.0                           # [rad/s] lowest frequency analysed
GRID_POINTS = 600                     # linearization grid, W_MIN .. 0.98 Nyquist


@dataclass
class LoopAnalysis:
    loop: object                               # margins/loops.py Loop
    w: np.ndarray = None                       # [rad/s] linearization grid
    L: np.ndarray = None                       # its L
    margins: Margins = None                    # from the linearization
    w_injected: np.ndarray = None              # [rad/s] the multi-sine's lines
    L_injected: np.ndarray = None
    margins_injected: Margins = None           # from the lines (coarser)
    agreement: dict = field(default_factory=dict)
    impulse: np.ndarray = None                 # (N, nu, ny) the controller chain's

    def as_dict(self) -> dict:
        primary = self.margins or self.margins_injected
        out = dict(primary.as_dict(), loop=self.loop.name, unit=self.loop.unit,
                   method="linearization" if self.margins else "injection")
        if self.margins is not None:
            out["linearization"] = self.margins.as_dict()
        if self.margins_injected is not None:
            out["injection"] = self.margins_injected.as_dict()
        out.update(self.agreement)
        return out


def compare(w_lin, L_lin, w_inj, L_inj, w_max: float) -> dict:
    """Largest gain [dB] and phase [deg] difference of the injected lines from the
    linearization (interpolated in log w) up to w_max [rad/s]."""
    sel = w_inj <= w_max
    lw = np.log(w_lin)
    mag = np.interp(np.log(w_inj[sel]), lw, 20 * np.log10(np.abs(L_lin)))
    ph = np.interp(np.log(w_inj[sel]), lw, np.unwrap(np.angle(L_lin)))
    dmag = 20 * np.log10(np.abs(L_inj[sel])) - mag
    dph = np.degrees(np.angle(L_inj[sel] * np.exp(-1j * ph)))
    worst = (lambda x: float(np.max(np.abs(x))) if sel.any() else None)   # noqa: E731
    return {"agreement_up_to_rad_s": float(w_max), "max_gain_difference_db": worst(dmag),
            "max_phase_difference_deg": worst(dph)}


def analyse(op, loop_name: str, *, seed: int = 0, inject: bool = True, linearize: bool = True,
            memory: float | None = None, impulse=None) -> LoopAnalysis:
    """The loop `loop_name` of the operating point `op` (margins/operating_point.py).
    impulse: the controller chain's impulse response of an earlier analysis of the same `op`
    (LoopAnalysis.impulse; it is the same for every loop), else measured here."""
    if not (inject or linearize):
        raise InputError("--no-injection and --no-linearization leave nothing to do")
    rig = op.rig
    r, data = op.rollout(0)
    r.run()
    loop = loop_of(op, data, loop_name)
    result = LoopAnalysis(loop)
    acts = [int(a) for a in rig.family.actuators(rig.parts)]
    if linearize:
        reference, _ = op.fresh()
        meas = rig.family.measurement(rig.parts, rig.signals, rig.seed, reference)
        H = impulse if impulse is not None else linearization.controller_impulse(
            op, meas, acts, memory or op.memory)[0]
        result.impulse = H
        P = linearization.plant(rig.plant.model, data, acts, loop.qfrc, loop.w)
        rows = linearization.measurement_rows(rig.plant.model, meas.addresses, meas.sources)
        result.w = grid(W_MIN, 0.98 * NYQUIST, GRID_POINTS)
        result.L = linearization.loop_response(P, rows, H, result.w)
        result.margins = margins(result.w, result.L)
    if inject:
        if not np.isfinite(loop.authority):
            raise InputError(f"--loop {loop_name}: its actuators have no limits to scale the "
                             "injection by; --no-injection")
        rms = injection.FRACTION * loop.authority
        signal = injection.multisine(W_MIN, NYQUIST / 3, rms, seed)
        result.w_injected, result.L_injected, _, _ = injection.inject(op, loop, signal)
        result.margins_injected = margins(result.w_injected, result.L_injected)
    if inject and linearize:
        result.agreement = compare(result.w, result.L, result.w_injected, result.L_injected,
                                   NYQUIST / 3)
    return result
