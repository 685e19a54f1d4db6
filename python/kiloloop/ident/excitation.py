"""An arm's excitation trajectory: a periodic Fourier series per joint (Swevers' form, so that it
starts at the start pose), scaled to stay inside the joints' position, velocity and effort limits
and clear of the floor, then laid out as via points of a quintic (what the joint controller
tracks in the native loop).

Why Fourier: a periodic trajectory with a few harmonics moves every joint through both
directions at speeds well away from zero (Coulomb friction and viscous friction separate), with
accelerations that change sign (armature), over a wide range of poses (the payload's gravity).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

import kiloloop as kl

PERIOD = 10.0          # [s] base period of the series (harmonics 1..HARMONICS of 1 / PERIOD)
HARMONICS = 5
VIA_SPACING = 0.4      # [s] between the quintic's via points (5 per period of the top harmonic)
MAX_EXCURSION = 0.9    # [rad] largest move of a joint away from the start pose
VELOCITY_FRACTION = 0.5  # of each joint's velocity limit
EFFORT_FRACTION = 0.8    # of each joint's effort limit the nominal model may need (the rest: what it
#                          does not know; the identification models the saturation anyway)
ACCEL_LIMIT = 8.0      # [rad/s^2] (a reference the controller can follow without saturating)


@dataclass(frozen=True)
class Excitation:
    """The via points (m, nq) [rad] at times (m,) [s] and the quintic through them."""

    points: np.ndarray
    times: np.ndarray

    def trajectory(self) -> "kl.QuinticTrajectory":
        return kl.QuinticTrajectory(self.points, self.times)

    def sampled(self, dt: float = 0.01) -> tuple[np.ndarray, ...]:
        """(q, qd, qdd) of the quintic at every dt [s]."""
        traj = self.trajectory()
        rows = [traj.sample(t) for t in np.arange(0.0, self.times[-1] + 1e-9, dt)]
        return tuple(np.array([r[i] for r in rows]) for i in range(3))


def fourier_shape(nq: int, t: np.ndarray, seed: int) -> np.ndarray:
    """(len(t), nq) zero at t = 0: sum_k a_jk sin(k w t) + b_jk (1 - cos(k w t)), coefficients
    drawn from the seed, falling as 1 / k (a flat velocity spectrum)."""
    rng = np.random.default_rng(seed)
    w = 2.0 * np.pi / PERIOD
    k = np.arange(1, HARMONICS + 1)
    a = rng.normal(size=(nq, HARMONICS)) / k
    b = rng.normal(size=(nq, HARMONICS)) / k
    phase = np.outer(t, k * w)                       # (T, K)
    return np.sin(phase) @ a.T + (1.0 - np.cos(phase)) @ b.T


def design(robot, model, plant, q0, duration: float, seed: int, probe=None) -> Excitation:
    """The excitation of an arm from q0 [rad] for `duration` [s]: each joint's shape scaled on
    its own into its free range (at most MAX_EXCURSION), its velocity limit's fraction and
    ACCEL_LIMIT (the quintic through scaled via points is the scaled quintic: Craig's via
    velocities are linear in a positive scale), then every joint shrunk together until the
    nominal torques stay inside the effort limits' fraction and the links clear of the floor
    (probe: a scenarios.arm_targets.PoseProbe, None: no floor check)."""
    from ..robot import arm as arm_defaults

    nq = model.nq
    times = np.arange(0.0, duration + 1e-9, VIA_SPACING)
    shape = fourier_shape(nq, times, seed)
    shape[-1] = shape[-2]  # the quintic ends at rest anyway; keep its last segment short
    down, up = arm_defaults.joint_range(model, np.asarray(q0, float))
    up, down = np.minimum(up, MAX_EXCURSION), np.minimum(down, MAX_EXCURSION)
    # Per joint: the largest scale that keeps the shape inside [q0 - down, q0 + up].
    hi, lo = shape.max(axis=0), -shape.min(axis=0)
    scale = np.minimum(np.where(hi > 0, up / np.maximum(hi, 1e-12), np.inf),
                       np.where(lo > 0, down / np.maximum(lo, 1e-12), np.inf))
    scale = np.where(np.isfinite(scale), scale, 0.0)
    _, qd, qdd = Excitation(shape, times).sampled(0.01)
    vmax = VELOCITY_FRACTION * np.asarray(model.velocity_limit)
    with np.errstate(divide="ignore"):
        scale = np.minimum(scale, np.minimum(vmax / np.abs(qd).max(axis=0),
                                             ACCEL_LIMIT / np.abs(qdd).max(axis=0)))
    clearance = None
    if probe is not None:
        probe.at(q0)
        clearance = min(probe.floor_clearance(), 0.02 * probe.reach) - 1e-9
    for _ in range(80):
        exc = Excitation(np.asarray(q0, float) + shape * scale, times)
        problem = _violation(exc, model, plant, probe, clearance)
        if problem is None:
            return exc
        # Too much torque: every joint smaller. Too low: only the joints that lower the links
        # at the lowest pose (a wrist that does not must keep its speed: its friction wants it).
        scale = scale * (0.85 if problem == "effort" else
                         np.where(_lowering(probe, q0, shape, scale, exc), 0.85, 1.0))
    raise ValueError("excitation: no scale of the trajectory stays inside the limits")


def _lowering(probe, q0, shape, scale, exc) -> np.ndarray:
    """(nq,) bool: the joints whose smaller excursion raises the links at the lowest via point
    (at least the one that raises them most)."""
    clear = []
    for q in exc.points:
        probe.at(q)
        clear.append(probe.floor_clearance())
    worst = int(np.argmin(clear))
    gain = np.zeros(len(scale))
    for j in range(len(scale)):
        trial = scale.copy()
        trial[j] *= 0.85
        probe.at(np.asarray(q0, float) + shape[worst] * trial)
        gain[j] = probe.floor_clearance() - clear[worst]
    return gain >= 0.2 * max(gain.max(), 1e-12)


def _violation(exc: Excitation, model, plant, probe, clearance) -> str | None:
    """"effort", "floor" or None: what the sampled quintic breaks first."""
    q, qd, qdd = exc.sampled(0.01)
    emax = EFFORT_FRACTION * np.asarray(model.effort_limit)
    for i in range(0, len(q), 5):
        if np.any(np.abs(plant.inverse_dynamics(q[i], qd[i], qdd[i])) > emax):
            return "effort"
    if probe is not None:
        for i in range(0, len(q), 5):
            probe.at(q[i])
            if probe.floor_clearance() < clearance:
                return "floor"
    return None
