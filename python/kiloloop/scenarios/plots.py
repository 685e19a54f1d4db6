"""What `--plot` draws for each scenario, and the criteria's thresholds on it.

The panel lists (kiloloop.plot.Panel or (title, signal, reference, unit) tuples; unit None: the
log's own, scenarios/signals.py) live here, one module for every family, and each scenario's
plot_signals() returns one of them. plot_result() draws a ScenarioResult with its criteria: a
criterion whose metric is read off a plotted signal (CRITERION_SIGNALS) becomes a dotted line on
that signal's panel, in the signal's unit (e.g. max_ee_error_m < 0.001 -> 1 mm on ee_err_mm).
"""
from __future__ import annotations

from ..plot import Panel, plot_log

ARM_TRACK_PLOT = [Panel("joint position", "q_true", "q_ref"),
                  Panel("joint error q_ref - q", "q_err"),
                  Panel("joint torque", "tau"),
                  Panel("end-effector position error", "ee_err_mm")]
ARM_LINE_PLOT = [Panel("end-effector position", "ee", "ee_ref"),
                 Panel("end-effector position error", "ee_err_mm"),
                 Panel("end-effector orientation error", "ee_rot_err_mrad"),
                 Panel("joint torque", "tau")]
ARM_ESTOP_PLOT = [Panel("joint velocity", "qd_true"),
                  Panel("joint position", "q_true", "q_ref"),
                  Panel("supervisor mode (0 normal, 1 stopping, 2 holding)", "mode"),
                  Panel("joint torque", "tau")]
ARM_PRESS_PLOT = [Panel("pressing force (MuJoCo sensor)", "force_z"),
                  Panel("x error", "x_err_mm"),
                  Panel("joint torque", "tau")]
ARM_RRT_PLOT = [Panel("joint position", "q_true", "q_ref"),
                Panel("distance links-box (MuJoCo)", "box_distance"),
                Panel("joint torque", "tau")]

# Contact against the gait's schedule (the contact's reference).
QUADRUPED_PLOT = [Panel("trunk position", "base_pos"),
                  Panel("trunk velocity (world)", "base_vel"),
                  Panel("roll, pitch", "roll_pitch_deg"),
                  Panel("ground reaction, vertical", "foot_fz"),
                  Panel("contact detected (dashed: scheduled stance)", "contact", "scheduled")]

AERIAL_PLOT = [Panel("body position", "base_pos", "pos_ref"),
               Panel("attitude error (rotation vector)", "att_err_deg"),
               Panel("rotor thrust", "thrust"),
               Panel("arm joints", "q", "q_ref"),
               Panel("arm torque", "tau")]

# The same signals of both runs (the feed-forward off run's under "_no_ff"), each pair on one
# y range, so that the difference reads off the figure.
AERIAL_ARM_SWEEP_PLOT = [
    Panel("arm joints (feed-forward on)", "q", "q_ref"),
    Panel("attitude error (rotation vector), feed-forward ON", "att_err_deg", group="att"),
    Panel("attitude error (rotation vector), feed-forward OFF", "att_err_deg_no_ff", group="att"),
    Panel("attitude vs level, feed-forward ON", "att_level_deg", group="level"),
    Panel("attitude vs level, feed-forward OFF", "att_level_deg_no_ff", group="level"),
    Panel("body position, feed-forward ON", "base_pos", "pos_ref", group="pos"),
    Panel("body position, feed-forward OFF", "base_pos_no_ff", "pos_ref_no_ff", group="pos"),
]

# metric -> (signal it is read off, scale from the metric's unit to the signal's, symmetric: the
# metric bounds |signal| (lines at +-threshold), around: a metric or setting the bound is
# relative to (lines at around +- threshold) or None, from [s]: the window the metric judges
# starts then (None: the whole run)).
CRITERION_SIGNALS = {
    "max_joint_error_rad": ("q_err", 1.0, True, None, None),
    "max_ee_error_m": ("ee_err_mm", 1e3, False, None, None),
    "max_ee_orientation_error_rad": ("ee_rot_err_mrad", 1e3, False, None, None),
    "max_x_error_m": ("x_err_mm", 1e3, True, None, None),
    "max_force_error_N": ("force_z", 1.0, True, "force", None),
    "min_box_distance_m": ("box_distance", 1.0, False, None, None),
    "height_error_after_1s_m": ("base_pos", 1.0, True, "body_height_m", 1.0),
    # RMS and peak bounds drawn on the instantaneous signal, as a guide (the label says which).
    "roll_pitch_rms_deg": ("roll_pitch_deg", 1.0, True, None, None),
    "roll_peak_deg": ("roll_pitch_deg", 1.0, True, None, None),
    "roll_after_recovery_deg": ("roll_pitch_deg", 1.0, True, None, None),
    "attitude_error_rms_deg": ("att_err_deg", 1.0, True, None, None),
}


def criteria_thresholds(result) -> dict[str, list[tuple]]:
    """{signal: [(op, value, label, t0)]} (kiloloop.plot's thresholds) of the result's criteria
    that a plotted signal shows (a scenario file's: its criteria's own signals and windows)."""
    if getattr(result, "scenario_file", None) is not None:
        from .scenario_file.report import thresholds

        return thresholds(result)
    out: dict[str, list] = {}
    for metric, c in result.criteria.items():
        if metric not in CRITERION_SIGNALS:
            continue
        signal, scale, symmetric, around, t0 = CRITERION_SIGNALS[metric]
        centre = 0.0
        if around is not None:
            value = result.metrics.get(around, result.settings.get(around))
            if value is None:
                continue
            centre = float(value) * scale
        bound = float(c["threshold"]) * scale
        label = f"{metric} {c['op']} {c['threshold']:g}"  # as the criterion reads, its unit
        lines = out.setdefault(signal, [])
        lines.append((c["op"], centre + bound, label, t0))
        if symmetric:
            mirrored = {"<": ">", "<=": ">=", ">": "<", ">=": "<="}[c["op"]]
            lines.append((mirrored, centre - bound, label, t0))
    return out


def plot_result(result, panels, path, title: str = ""):
    """plot_log of a ScenarioResult's log with its criteria's thresholds; returns the path."""
    return plot_log(result.log, panels, path, title=title, thresholds=criteria_thresholds(result))
