"""Linear least squares with the search of the actuation delay and lag around it: the regressor
Phi (rows x parameters) does not depend on the actuation, only the target does, so one QR of Phi
serves every candidate; the chosen one is then solved with physical bounds (an active set: a
parameter that must be >= 0 and comes out negative is held at 0) and each parameter gets a
standard error from the unbounded fit's covariance. numpy only (scipy is no dependency).

Rows whose residual lies beyond OUTLIER robust standard deviations of their group's (a joint's
equations) are trimmed before the final fit: a model of friction as Coulomb's is wrong in places,
on a real drive (stiction) as in MuJoCo (its frictionloss is a soft constraint that falls short
of the friction where the joint is braked hard: the UR5's elbow at 0.47 rad/s, 8.3 of 10 N m).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

GOLDEN = (np.sqrt(5.0) - 1.0) / 2.0


def golden_section(f, lo: float, hi: float, tol: float) -> tuple[float, float]:
    """(x, f(x)) minimising a unimodal f on [lo, hi] to within tol."""
    a, b = lo, hi
    c, d = b - GOLDEN * (b - a), a + GOLDEN * (b - a)
    fc, fd = f(c), f(d)
    while b - a > tol:
        if fc < fd:
            b, d, fd = d, c, fc
            c = b - GOLDEN * (b - a)
            fc = f(c)
        else:
            a, c, fc = c, d, fd
            d = a + GOLDEN * (b - a)
            fd = f(d)
    return (c, fc) if fc < fd else (d, fd)


def identifiable_columns(phi: np.ndarray) -> np.ndarray:
    """(columns,) bool: the parameters the rows tell apart. phi's columns at unit norm (or 0);
    while its smallest singular value is under CONDITION of the largest, the column that weighs
    most in that direction is left out (a joint that never moved, a payload parameter these
    motions do not excite)."""
    keep = np.linalg.norm(phi, axis=0) > 0
    while keep.any():
        idx = np.nonzero(keep)[0]
        _, sv, vt = np.linalg.svd(phi[:, idx], full_matrices=False)
        if sv[-1] > CONDITION * sv[0]:
            break
        keep[idx[int(np.argmax(np.abs(vt[-1])))]] = False
    return keep


def bounded_lstsq(phi: np.ndarray, y: np.ndarray, lower: np.ndarray) -> np.ndarray:
    """min |phi theta - y| with theta_i >= lower_i (lower -inf: free): the most violating
    parameter is held at its bound and the rest solved again, until none violates."""
    held = np.zeros(phi.shape[1], bool)
    theta = np.zeros(phi.shape[1])
    for _ in range(phi.shape[1] + 1):
        theta = np.where(held, lower, 0.0)
        free = ~held
        rhs = y - phi[:, held] @ lower[held] if held.any() else y
        theta[free] = np.linalg.lstsq(phi[:, free], rhs, rcond=None)[0]
        violation = np.where(free & np.isfinite(lower), lower - theta, 0.0)
        if violation.max() <= 0.0:
            break
        held[int(np.argmax(violation))] = True
    return theta

CONDITION = 1e-7   # smallest singular value over the largest (columns scaled to unit norm) kept
OUTLIER = 5.0       # robust standard deviations (1.4826 MAD) of a group's residuals
TRIM_PASSES = 3
NEAR = 8            # [ticks] delays searched again around a first answer
LAG_PATIENCE = 3    # delays tried past the best when walking the delay down against the lag


@dataclass
class Solution:
    theta: np.ndarray          # the bounded estimate
    stderr: np.ndarray         # one standard error per parameter (unbounded fit)
    residual_rms: float        # of the bounded fit, in the target's unit
    delay_ticks: int
    lag: float                 # [s]
    delay_residuals: np.ndarray  # residual RMS per candidate delay (at the chosen lag)
    trimmed: int = 0           # rows left out as outliers
    target_rms: float = 0.0    # of the rows fitted, in the target's unit


class LinearModel:
    """target(delay, lag) ~ Phi theta, theta >= lower; groups: a label per row (the
    outliers' scale is each group's own)."""

    def __init__(self, phi: np.ndarray, target, lower, groups=None, prior=None):
        """prior: the values (the nominal file's) a parameter the logs cannot tell apart is
        held at (default 0)."""
        n = phi.shape[1]
        self.prior = np.zeros(n) if prior is None else np.asarray(prior, float)
        scale = np.linalg.norm(phi, axis=0)
        scaled = phi / np.where(scale > 0, scale, 1.0)
        self.identifiable = identifiable_columns(scaled)
        held = ~self.identifiable
        self._raw_target = target
        self._held_part = phi[:, held] @ self.prior[held]
        self.columns = np.nonzero(self.identifiable)[0]
        self.scale = scale[self.columns]
        self.phi_all = scaled[:, self.columns]
        self.groups = np.zeros(len(phi), int) if groups is None else np.asarray(groups)
        self.lower = np.asarray(lower, float)[self.columns]
        self.keep(np.ones(len(phi), bool))

    def target_all(self, delay_ticks: int, lag: float) -> np.ndarray:
        """The target less what the held parameters explain."""
        return self._raw_target(delay_ticks, lag) - self._held_part

    def full(self, theta: np.ndarray, fill: np.ndarray) -> np.ndarray:
        """A vector over every parameter: theta on the identifiable ones, fill on the rest."""
        out = np.array(fill, float, copy=True)
        out[self.columns] = theta
        return out

    def keep(self, rows: np.ndarray) -> None:
        self.rows = rows
        self.phi = self.phi_all[rows]
        q, self.r = np.linalg.qr(self.phi)
        self.qt = np.ascontiguousarray(q.T)  # (parameters, rows): Q^T y in one fast pass

    def target(self, delay_ticks: int, lag: float) -> np.ndarray:
        return self.target_all(delay_ticks, lag)[self.rows]

    def rms(self, y: np.ndarray) -> float:
        """Residual RMS of the unbounded fit of y."""
        projected = self.qt @ y  # |y - Q Q^T y|^2 = |y|^2 - |Q^T y|^2: one pass over Q
        return float(np.sqrt(max(0.0, float(y @ y) - float(projected @ projected)) / len(y)))

    def search(self, max_delay_ticks: int, max_lag: float, near=None) -> tuple[int, float, np.ndarray]:
        """The delay (whole ticks) and lag [s] that minimise the residual: delays at no lag,
        then from the best one down, each with its best lag (golden section). near: an earlier
        (delay, lag, residuals) to refine (only delays within NEAR ticks of it, at its lag)."""
        if near is None:
            rms = np.array([self.rms(self.target(d, 0.0)) for d in range(max_delay_ticks + 1)])
            d = int(np.argmin(rms))
        else:
            d, rms = near[0], np.array(near[2], float)
            lo, hi = max(0, d - NEAR), min(max_delay_ticks, d + NEAR)
            rms[lo:hi + 1] = [self.rms(self.target(k, near[1])) for k in range(lo, hi + 1)]
            d = lo + int(np.argmin(rms[lo:hi + 1]))
        lag = 0.0
        if max_lag > 0:
            # A lag T looks like T more delay to a slow motion: walk the delay down from the
            # no-lag answer, each with its best lag, while the residual falls (a few more
            # candidates past the best, then stop).
            def best_lag(k):
                x, fx = golden_section(lambda T: self.rms(self.target(k, T)), 0.0, max_lag, 1e-5)
                f0 = self.rms(self.target(k, 0.0))
                return (float(x), fx) if fx < f0 else (0.0, f0)
            lag, best = best_lag(d)
            worse = 0
            for k in range(d - 1, max(-1, d - 1 - int(round(max_lag / 0.001))), -1):
                T, f = best_lag(k)
                if f < best:
                    d, lag, best, worse = k, T, f, 0
                else:
                    worse += 1
                    if worse >= LAG_PATIENCE:
                        break
            rms = rms.copy()
            rms[d] = best
        return d, lag, rms

    def trim(self, delay_ticks: int, lag: float) -> int:
        """Leaves out the outlier rows (see the module doc); returns how many."""
        for _ in range(TRIM_PASSES):
            y = self.target_all(delay_ticks, lag)
            theta = np.linalg.solve(self.r, self.qt @ y[self.rows])
            e = y - self.phi_all @ theta
            keep = np.ones(len(e), bool)
            for g in np.unique(self.groups):
                sel = self.groups == g
                inlier = sel & self.rows
                sigma = 1.4826 * np.median(np.abs(e[inlier] - np.median(e[inlier])))
                keep[sel] = np.abs(e[sel]) <= OUTLIER * max(sigma, 1e-12 * (1 + np.abs(y[sel]).max()))
            if np.array_equal(keep, self.rows):
                break
            self.keep(keep)
        return int(np.sum(~self.rows))

    def solve(self, delay_ticks: int, lag: float, rms_by_delay) -> Solution:
        y = self.target(delay_ticks, lag)
        free = np.linalg.solve(self.r, self.qt @ y)
        e = y - self.phi @ free
        dof = max(1, len(y) - len(free))
        s2 = float(e @ e) / dof
        rinv = np.linalg.inv(self.r)
        stderr = np.sqrt(s2 * np.sum(rinv ** 2, axis=1)) / self.scale
        scaled = bounded_lstsq(self.phi, y, self.lower * self.scale)
        theta = self.full(scaled / self.scale, self.prior)
        stderr = self.full(stderr, np.full(len(self.prior), np.inf))
        res = y - self.phi @ scaled
        return Solution(theta, stderr, float(np.sqrt(np.mean(res ** 2))), int(delay_ticks),
                        float(lag), np.asarray(rms_by_delay), int(np.sum(~self.rows)),
                        float(np.sqrt(np.mean(y ** 2))))

    def identify(self, max_delay_ticks: int, max_lag: float) -> Solution:
        """search, trim the outliers, search again near the first answer, solve."""
        d, lag, rms = self.search(max_delay_ticks, max_lag)
        if self.trim(d, lag):
            d, lag, rms = self.search(max_delay_ticks, max_lag, near=(d, lag, rms))
        return self.solve(d, lag, rms)
