"""The actuation model whose parameters identification searches: a transport delay of whole
control ticks and a first-order lag, the discrete form the SIL's motor model uses
(cpp/sil/signal_models.hpp): y_k = y_k-1 + alpha (u_k-delay - y_k-1), alpha = dt / (T + dt)."""
from __future__ import annotations

import numpy as np
from scipy.signal import lfilter


def applied(u: np.ndarray, delay_ticks: int, lag: float, dt: float) -> np.ndarray:
    """(N, k) what reaches the plant from commands u (N, k): zero before the first command
    arrives, then the delayed commands through the lag T = lag [s]."""
    u = np.asarray(u, float)
    out = np.zeros_like(u)
    d = int(delay_ticks)
    if d < len(u):
        out[d:] = u[:len(u) - d]
    if lag > 0:
        alpha = dt / (lag + dt)
        out = lfilter([alpha], [1.0, alpha - 1.0], out, axis=0)
    return out
