"""Where and how the feet stood, from the ground truth of a quadruped log (foot_pos, foot_force):
stance intervals, how far a loaded foot slid, and each touch-down's height against the terrain.
Shared by the terrain scenarios (quadruped-stones, -rough, -compliant)."""
from __future__ import annotations

import numpy as np

# A foot is loaded while the ground pushes on it with more than this fraction of the robot's
# weight: the controller's own lift-off threshold (QuadrupedConfig.contact_force_off, 0.058).
LOADED = 0.058
# [s] shorter loaded spells are bounces at touch-down (soft ground), not stances: the
# controller's own load ramp (QuadrupedConfig.load_ramp, 0.03 s) is not even through.
MIN_STANCE = 0.03


def stances(log, weight: float, since: float = 0.0) -> list[tuple[int, int, int]]:
    """(leg, first tick, last tick) of every loaded interval that starts at or after `since` [s],
    ends before the log does (a whole stance) and lasts MIN_STANCE or more."""
    loaded = log["foot_force"][:, :, 2] > LOADED * weight  # (ticks, legs)
    t = log["t"]
    out = []
    for leg in range(loaded.shape[1]):
        edges = np.flatnonzero(np.diff(loaded[:, leg].astype(np.int8)))
        starts = [e + 1 for e in edges if loaded[e + 1, leg]]
        ends = [e for e in edges if not loaded[e + 1, leg]]
        for s in starts:
            later = [e for e in ends if e >= s]
            if later and t[s] >= since and t[later[0]] - t[s] >= MIN_STANCE:
                out.append((leg, s, later[0]))
    return out


def slip(log, intervals) -> np.ndarray:
    """Horizontal travel [m] of each foot's centre over its loaded interval (largest distance from
    where it landed). A sphere that rolls moves its centre by radius x rolled angle; more is a
    slide."""
    p = log["foot_pos"]
    return np.array([np.linalg.norm(p[s:e + 1, leg, :2] - p[s, leg, :2], axis=1).max()
                     for leg, s, e in intervals]) if intervals else np.zeros(0)


def touchdown_heights(log, intervals, ground_height, foot_radius: float) -> np.ndarray:
    """Each touch-down's foot bottom minus the terrain height under it [m] (tick where the load
    first exceeds LOADED): ~0 on a surface (below 0 by the sinkage on soft ground), above 0 when
    the sphere rests on an edge with its centre over lower ground (a gap, the foot of a step)."""
    p = log["foot_pos"]
    return np.array([p[s, leg, 2] - foot_radius - ground_height(p[s, leg, 0], p[s, leg, 1])
                     for leg, s, _ in intervals]) if intervals else np.zeros(0)
