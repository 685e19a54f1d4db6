"""What the quadruped scenarios compute from a log (roll/pitch, heading-frame velocity, falls,
trot metrics, the estimator's attitude errors) and the trotting command and stop condition they
share (trot, push, turn, slope-trot, the terrain trots). The rig (sil/rig.py,
sil/quadruped_family.py) only moves data; what a run is judged by lives with the scenarios."""
from __future__ import annotations

import numpy as np

from ..sil.events import FellBelow
from ..sil.quadruped_family import CommandSchedule


def roll_pitch(quat_wxyz: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Roll and pitch [rad] of a (N, 4) array of w, x, y, z quaternions (world <- body)."""
    w, x, y, z = quat_wxyz.T
    roll = np.arctan2(2 * (w * x + y * z), 1 - 2 * (x * x + y * y))
    pitch = np.arcsin(np.clip(2 * (w * y - z * x), -1.0, 1.0))
    return roll, pitch


def heading_velocity(log) -> np.ndarray:
    """Ground-truth trunk velocity in the heading frame (x forward, y left), (N, 2)."""
    w, x, y, z = log["base_quat"].T
    yaw = np.arctan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z))
    v = log["base_vel"]
    c, s = np.cos(yaw), np.sin(yaw)
    return np.stack([c * v[:, 0] + s * v[:, 1], -s * v[:, 0] + c * v[:, 1]], axis=1)


def fallen(log, min_height: float = 0.15, max_tilt_deg: float = 45.0) -> bool:
    """Trunk below min_height [m] (rigs: QuadrupedRig.fall_height) or tilted past max_tilt_deg."""
    roll, pitch = roll_pitch(log["base_quat"])
    tilt = np.degrees(np.arccos(np.clip(np.cos(roll) * np.cos(pitch), -1, 1)))
    return bool(np.any(log["base_pos"][:, 2] < min_height) or np.any(tilt > max_tilt_deg))


def add_derived(log) -> None:
    """Series the plots and metrics share: roll/pitch in degrees, vertical foot forces."""
    roll, pitch = roll_pitch(log["base_quat"])
    log.put("roll_pitch_deg", np.degrees(np.stack([roll, pitch], axis=1)))
    log.put("foot_fz", log["foot_force"][:, :, 2])


# Trotting helpers shared by the trotting scenarios (trot, push, turn, slope-trot).
def trot_command(speed: float, start: float = 0.5) -> CommandSchedule:
    """Stand until `start` [s], then trot forward at `speed` [m/s] (heading frame)."""
    return CommandSchedule([(0.0, 0, np.zeros(3)), (start, 1, np.array([speed, 0.0, 0.0]))])


def trot_metrics(log, speed: float, since: float, fall_height: float = 0.15) -> dict:
    """Fall, roll/pitch RMS and forward-velocity tracking of a trot from `since` [s] on."""
    t = log["t"]
    k = t >= since
    rp = log["roll_pitch_deg"][k]
    v = heading_velocity(log)[k]
    return {
        "fell": float(fallen(log, fall_height)),
        "roll_rms_deg": float(np.sqrt(np.mean(rp[:, 0] ** 2))),
        "pitch_rms_deg": float(np.sqrt(np.mean(rp[:, 1] ** 2))),
        "roll_pitch_rms_deg": float(np.sqrt(np.mean(rp ** 2, axis=0)).max()),
        # Forward velocity (heading frame) against the command, as the criterion asks.
        "velocity_rms_error": float(np.sqrt(np.mean((v[:, 0] - speed) ** 2))),
        "lateral_velocity_rms": float(np.sqrt(np.mean(v[:, 1] ** 2))),
        "mean_forward_velocity": float(np.mean(v[:, 0])),
        "distance_m": float(log["base_pos"][-1, 0] - log["base_pos"][0, 0]),
        "failed_ticks": int(np.sum(log["status"] < 0)),
        **attitude_errors(log, since),
    }


def attitude_errors(log, since: float = 0.0) -> dict:
    """RMS error [deg] of the controller's roll and pitch estimate against the simulator's, from
    `since` [s] on (yaw is not observed without a magnetometer: its drift is reported apart)."""
    k = log["t"] >= since
    roll, pitch = roll_pitch(log["base_quat"][k])
    roll_est, pitch_est = roll_pitch(log["est_quat"][k])
    def yaw(q):
        return np.unwrap(np.arctan2(2 * (q[:, 0] * q[:, 3] + q[:, 1] * q[:, 2]),
                                    1 - 2 * (q[:, 2] ** 2 + q[:, 3] ** 2)))
    yaw_error = yaw(log["est_quat"][k]) - yaw(log["base_quat"][k])
    return {
        "roll_estimate_rms_error_deg": float(np.degrees(np.sqrt(np.mean((roll_est - roll) ** 2)))),
        "pitch_estimate_rms_error_deg": float(np.degrees(np.sqrt(np.mean((pitch_est - pitch) ** 2)))),
        "yaw_estimate_drift_deg": float(np.degrees(yaw_error[-1] - yaw_error[0])) if yaw_error.size else 0.0,
    }


def fell_early(rig) -> FellBelow:
    """stop_when for trotting runs: the trunk near the ground ends the run (a fall either way)."""
    return FellBelow(0.8 * rig.fall_height)
