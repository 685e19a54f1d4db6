"""The Bode plot of a loop analysis (PNG, matplotlib's Figure without pyplot state, as plot.py):
gain [dB] and phase [deg] of L over frequency [rad/s], the linearization as a line, the
injection's lines as dots, the crossover and the margins marked."""
from __future__ import annotations

import numpy as np


def _phase_deg(L: np.ndarray) -> np.ndarray:
    """Unwrapped, shifted by whole turns so the first value lies in (-360, 0]."""
    ph = np.degrees(np.unwrap(np.angle(L)))
    return ph - 360.0 * np.ceil(ph[0] / 360.0) if len(ph) else ph


def plot(analysis, path: str, title: str = "") -> None:
    from matplotlib.figure import Figure

    fig = Figure(figsize=(8, 6.5))
    gain, phase = fig.subplots(2, 1, sharex=True)
    a = analysis
    ref = None
    if a.L is not None:
        ph = _phase_deg(a.L)
        ref = (a.w, ph)
        gain.semilogx(a.w, 20 * np.log10(np.abs(a.L)), color="tab:blue", label="linearization")
        phase.semilogx(a.w, ph, color="tab:blue", label="linearization")
    if a.L_injected is not None:
        ph = np.degrees(np.angle(a.L_injected))
        if ref is not None:   # on the same branch as the line
            near = np.interp(np.log(a.w_injected), np.log(ref[0]), ref[1])
            ph = ph + 360.0 * np.round((near - ph) / 360.0)
        gain.semilogx(a.w_injected, 20 * np.log10(np.abs(a.L_injected)), "o", ms=4,
                      color="tab:orange", label="injection (multi-sine lines)")
        phase.semilogx(a.w_injected, ph, "o", ms=4, color="tab:orange", label="injection")
    m = a.margins or a.margins_injected
    gain.axhline(0.0, color="0.5", lw=0.8)
    for level in (-180.0, -540.0, 180.0):
        phase.axhline(level, color="0.5", lw=0.8, ls=":")
    if m is not None and np.isfinite(m.crossover_rad_s):
        for ax in (gain, phase):
            ax.axvline(m.crossover_rad_s, color="tab:red", lw=0.8, ls="--")
        gm = "inf" if not np.isfinite(m.gain_margin_db) else f"{m.gain_margin_db:.1f} dB"
        gain.set_title(f"{title}  crossover {m.crossover_rad_s:.1f} rad/s, phase margin "
                       f"{m.phase_margin_deg:.1f} deg, delay margin "
                       f"{1e3 * m.delay_margin_s:.1f} ms, gain margin {gm}", fontsize=9)
    gain.set_ylabel("|L| [dB]")
    phase.set_ylabel("arg L [deg]")
    phase.set_xlabel("frequency [rad/s]")
    for ax in (gain, phase):
        ax.grid(True, which="both", alpha=0.3)
    gain.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
