"""What the aerial scenarios compute from a log (attitude errors, divergence, a hold's errors)
and their hover reference (Hold, hold). The rig (sil/rig.py, sil/aerial_family.py) only moves data; what a run
is judged by and the references the scenarios derive live with the scenarios."""
from __future__ import annotations

import numpy as np

import kiloloop as kl

from ..sil.aerial_signals import reference_row


def quat_angle(q_a: np.ndarray, q_b: np.ndarray) -> np.ndarray:
    """Rotation angle [rad] between rows of two (N, 4) w, x, y, z quaternion arrays."""
    dot = np.abs(np.sum(q_a * q_b, axis=1))
    return 2.0 * np.arccos(np.clip(dot, -1.0, 1.0))


def rotation_vector_error(q: np.ndarray, q_ref: np.ndarray) -> np.ndarray:
    """Body-frame rotation vector (N, 3) [rad] of q_ref^-1 q (w, x, y, z rows)."""
    w1, v1 = q_ref[:, :1], -q_ref[:, 1:]
    w2, v2 = q[:, :1], q[:, 1:]
    w = w1 * w2 - np.sum(v1 * v2, axis=1, keepdims=True)
    v = w1 * v2 + w2 * v1 + np.cross(v1, v2)
    sign = np.where(w < 0, -1.0, 1.0)
    w, v = w * sign, v * sign
    angle = 2.0 * np.arctan2(np.linalg.norm(v, axis=1, keepdims=True), w)
    norm = np.linalg.norm(v, axis=1, keepdims=True)
    return np.where(norm > 1e-12, v / np.maximum(norm, 1e-300) * angle, 2.0 * v)


def diverged(log, max_tilt_deg: float = 60.0) -> str:
    """'' when the run stayed sane, else why it did not (for the sweep's failure column)."""
    if "diverged" in log:
        return "non-finite simulation state"
    if np.any(log["safe_stop"] > 0):
        return "attitude > 60 deg (safe stop)"
    if np.any(np.degrees(log["tilt"]) > max_tilt_deg):
        return "attitude > 60 deg"
    if np.any(log["status"] == int(kl.Status.SOLVER_FAILED)):
        return "solver failure"
    if np.any(log["status"] == int(kl.Status.NON_FINITE_MEASUREMENT)):
        return "NaN/Inf measurement"
    return ""


def add_derived(log) -> None:
    """Attitude error vs the commanded attitude (deg), for plots and metrics."""
    log.put("att_err_deg", np.degrees(rotation_vector_error(log["base_quat"], log["quat_des"])))


class Hold:
    """Command: the hover point and the arm at its start pose (controller order), constant; its
    reference table is one row (the adapter holds the last row), so nothing is sampled per tick."""

    def __init__(self, hover, q0):
        self.hover, self.q0 = np.asarray(hover, float), np.asarray(q0, float)

    def __call__(self, t, inp) -> None:
        inp.position_ref[:] = self.hover
        inp.q_ref[:] = self.q0

    def table(self, controller, ticks: int) -> np.ndarray:
        inp = controller.make_input()
        self(0.0, inp)
        return reference_row(inp, controller.nq)[None, :]


def hold(rig) -> Hold:
    """Hover point and the arm at its start pose (controller order)."""
    return Hold(rig.hover_pos.copy(), rig.plant.q0.copy()[rig.to_ctrl])


def hold_errors(log, after) -> dict:
    """Position error [m] and attitude error [deg] of a hold (hover, wind) over the ticks where
    `after` is true: max and RMS."""
    pos_err = np.linalg.norm(log["base_pos"] - log["pos_ref"], axis=1)[after]
    att = np.linalg.norm(log["att_err_deg"], axis=1)[after]
    return {
        "max_position_error_m": float(pos_err.max()),
        "rms_position_error_m": float(np.sqrt(np.mean(pos_err ** 2))),
        "attitude_error_rms_deg": float(np.sqrt(np.mean(att ** 2))),
        "attitude_error_max_deg": float(att.max()),
    }
