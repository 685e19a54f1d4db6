"""Linear least squares with the search of the actuation delay and lag around it: the regressor
Phi (rows x parameters) does not depend on the actuation, only the target does, so one QR of Phi
serves every candidate; the chosen one is then solved with physical bounds (scipy lsq_linear)
and each parameter gets a standard error from the unbounded fit's covariance."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import lsq_linear, minimize_scalar


@dataclass
class Solution:
    theta: np.ndarray          # the bounded estimate
    stderr: np.ndarray         # one standard error per parameter (unbounded fit)
    residual_rms: float        # of the bounded fit, in the target's unit
    delay_ticks: int
    lag: float                 # [s]
    delay_residuals: np.ndarray  # residual RMS per candidate delay (at the chosen lag)


class LinearModel:
    """target(delay, lag) ~ Phi theta, lower <= theta <= upper."""

    def __init__(self, phi: np.ndarray, target, lower, upper):
        self.scale = np.linalg.norm(phi, axis=0)
        self.scale[self.scale == 0] = 1.0
        self.phi = phi / self.scale
        self.q, self.r = np.linalg.qr(self.phi)
        self.target = target
        self.lower, self.upper = np.asarray(lower, float), np.asarray(upper, float)

    def rms(self, y: np.ndarray) -> float:
        """Residual RMS of the unbounded fit of y."""
        e = y - self.q @ (self.q.T @ y)
        return float(np.sqrt(np.mean(e ** 2)))

    def search(self, max_delay_ticks: int, max_lag: float) -> tuple[int, float, np.ndarray]:
        """The delay (whole ticks) and lag [s] that minimise the residual: delays at no lag,
        then the lag at the best delay, then the delays again at that lag."""
        def by_delay(lag):
            return np.array([self.rms(self.target(d, lag)) for d in range(max_delay_ticks + 1)])

        rms = by_delay(0.0)
        d = int(np.argmin(rms))
        lag = 0.0
        if max_lag > 0:
            for _ in range(2):
                best = minimize_scalar(lambda T: self.rms(self.target(d, T)),
                                       bounds=(0.0, max_lag), method="bounded",
                                       options={"xatol": 1e-5})
                lag = float(best.x) if best.fun < self.rms(self.target(d, 0.0)) else 0.0
                lo, hi = max(0, d - 15), min(max_delay_ticks, d + 15)
                local = [self.rms(self.target(k, lag)) for k in range(lo, hi + 1)]
                d_new = lo + int(np.argmin(local))
                rms = rms.copy()
                rms[lo:hi + 1] = local
                if d_new == d:
                    break
                d = d_new
        return d, lag, rms

    def solve(self, delay_ticks: int, lag: float, rms_by_delay) -> Solution:
        y = self.target(delay_ticks, lag)
        free = np.linalg.solve(self.r, self.q.T @ y)
        e = y - self.phi @ free
        dof = max(1, len(y) - len(free))
        s2 = float(e @ e) / dof
        rinv = np.linalg.inv(self.r)
        stderr = np.sqrt(s2 * np.sum(rinv ** 2, axis=1)) / self.scale
        bounded = lsq_linear(self.phi, y, bounds=(self.lower * self.scale, self.upper * self.scale),
                             method="bvls")
        theta = bounded.x / self.scale
        res = y - self.phi @ bounded.x
        return Solution(theta, stderr, float(np.sqrt(np.mean(res ** 2))), int(delay_ticks),
                        float(lag), np.asarray(rms_by_delay))
