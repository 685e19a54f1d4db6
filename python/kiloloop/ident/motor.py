"""The actuation model whose parameters identification searches: a transport delay of whole
control ticks and a first-order lag, the discrete form the SIL's motor model uses
(cpp/sil/signal_models.hpp): y_k = y_k-1 + alpha (u_k-delay - y_k-1), alpha = dt / (T + dt),
then saturated at the effort limits (a drive's current limit; MuJoCo's forcerange): a logger
records what was commanded, not what the drive could give."""
from __future__ import annotations

import numpy as np


def first_order(x: np.ndarray, alpha: float) -> np.ndarray:
    """y_k = (1 - alpha) y_k-1 + alpha x_k along axis 0, y_-1 = 0, in blocks: within a block
    y_k = r^k (y_start + alpha sum_i r^-i x_i) (r = 1 - alpha), the block short enough that
    r^-k stays below e^30."""
    x = np.asarray(x, float)
    r = 1.0 - alpha
    if r <= 0.0:
        return x.copy()
    block = max(1, int(30.0 / -np.log(r)))
    y = np.empty_like(x)
    prev = np.zeros(x.shape[1:])
    for start in range(0, len(x), block):
        xs = x[start:start + block]
        k = np.arange(len(xs)).reshape((-1,) + (1,) * (x.ndim - 1))
        powers = r ** k                                  # r^k
        acc = np.cumsum(xs / powers, axis=0) * alpha
        y[start:start + len(xs)] = powers * (r * prev + acc)
        prev = y[start + len(xs) - 1]
    return y


def applied(u: np.ndarray, delay_ticks: int, lag: float, dt: float, limit=None) -> np.ndarray:
    """(N, k) what reaches the plant from commands u (N, k): zero before the first command
    arrives, then the delayed commands through the lag T = lag [s], clipped to +-limit (k)
    (None: no limit)."""
    u = np.asarray(u, float)
    out = np.zeros_like(u)
    d = int(delay_ticks)
    if d < len(u):
        out[d:] = u[:len(u) - d]
    if lag > 0:
        out = first_order(out, dt / (lag + dt))
    if limit is not None:
        out = np.clip(out, -np.asarray(limit, float), np.asarray(limit, float))
    return out
