"""Plots and described logs: legends by component name, references and criteria drawn, units
through save/load (kiloloop.plot, scenarios/plots.py, scenarios/signals.py, sil/log.py)."""
import numpy as np
import pytest

import kiloloop as kl
from kiloloop import scenarios
from kiloloop.plot import as_panel, figure, legend_labels
from kiloloop.scenarios.plots import criteria_thresholds, plot_result
from kiloloop.sil.log import META_KEY, SignalLog, load_log

PNG = b"\x89PNG\r\n\x1a\n"


def _run(name, duration=0.5):
    module = scenarios.get(name)
    return module, scenarios.run_named(name, duration=duration)


def _figure(module, result):
    return figure(result.log, module.plot_signals(), thresholds=criteria_thresholds(result))


def test_units_and_components_round_trip_through_save_and_load(tmp_path):
    log = SignalLog()
    for k in range(3):
        log.record("t", 0.001 * k)
        log.record("q", [k, 2.0 * k])
    log.describe("q", "rad", ["shoulder", "elbow"], label="joint position")
    log.describe("t", "s")
    path = log.save(tmp_path / "a.npz")
    back = SignalLog.load(path)
    assert back.unit("q") == "rad" and back.components("q") == ["shoulder", "elbow"]
    assert back.label("q") == "joint position" and back.label("t") == "t"
    assert back.unit("t") == "s" and back.components("t") is None
    np.testing.assert_array_equal(back["q"], log["q"])
    # load_log keeps returning the signals only; the descriptions are one extra npz entry.
    assert set(load_log(path)) == {"t", "q"}
    with np.load(path) as raw:
        assert META_KEY in raw.files


def test_a_log_saved_without_descriptions_loads(tmp_path):
    path = tmp_path / "old.npz"
    np.savez_compressed(path, t=np.arange(4) * 0.001, q=np.ones((4, 2)))
    log = SignalLog.load(path)
    assert sorted(log.names()) == ["q", "t"] and log["q"].shape == (4, 2)
    assert log.unit("q") == "" and log.components("q") is None and log.label("q") == "q"
    assert set(load_log(path)) == {"t", "q"}
    # Undescribed (and plain dict) logs still plot, components as name[i].
    fig = figure(load_log(path), [("q", "q", None, "rad")])
    assert legend_labels(fig) == [["q[0]", "q[1]"]]
    assert fig.axes[0].get_ylabel() == "q [rad]"


def test_arm_track_plot_names_joints_draws_reference_and_criteria(tmp_path):
    module, result = _run("arm-track")
    joints = list(kl.Robot.load("ur5").model().joint_names)
    assert result.log.components("q_true") == joints and result.log.unit("tau") == "N m"
    fig = _figure(module, result)
    labels = legend_labels(fig)
    assert labels[0] == joints + ["reference (dashed): q_ref"]
    assert labels[1] == joints + ["criterion: max_joint_error_rad < 0.001"]
    assert labels[2] == joints
    assert "criterion: max_ee_error_m < 0.001" in labels[3]
    assert [ax.get_ylabel() for ax in fig.axes] == ["q_true [rad]", "q_err [rad]", "tau [N m]",
                                                    "ee_err_mm [mm]"]
    # The joint error panel: +-1 mrad drawn (max_joint_error_rad bounds |q_ref - q|).
    levels = sorted(line.get_ydata()[0] for line in fig.axes[1].get_lines()
                    if line.get_linestyle() == ":")
    assert levels == pytest.approx([-1e-3, 1e-3])
    path = plot_result(result, module.plot_signals(), tmp_path / "arm.png", title="arm-track")
    assert path.read_bytes()[:8] == PNG


def test_quadruped_stand_plot_names_axes_and_feet(tmp_path):
    module, result = _run("quadruped-stand")
    fig = _figure(module, result)
    labels = legend_labels(fig)
    feet = result.log.components("foot_fz")
    assert len(feet) == 4
    assert all(f.startswith(leg) for f, leg in zip(feet, ["FL", "FR", "RL", "RR"]))
    assert labels[0] == ["x", "y", "z", "criterion: height_error_after_1s_m < 0.01"]
    assert labels[2] == ["roll", "pitch"]
    assert labels[3] == feet and labels[4] == feet + ["reference (dashed): scheduled"]
    assert fig.axes[2].get_ylabel() == "roll_pitch_deg [deg]"
    assert len(result.log.components("tau")) == 12
    path = plot_result(result, module.plot_signals(), tmp_path / "quad.png")
    assert path.read_bytes()[:8] == PNG


def test_aerial_hover_plot_names_rotors_and_arm_joints(tmp_path):
    module, result = _run("aerial-hover")
    fig = _figure(module, result)
    labels = legend_labels(fig)
    from kiloloop.robot import aerial

    joints = list(aerial.model(kl.Robot.load("aerial_manipulator")).joint_names)
    assert labels[0] == ["x", "y", "z", "reference (dashed): pos_ref"]
    assert labels[1] == ["x", "y", "z", "criterion: attitude_error_rms_deg < 0.5"]
    assert labels[2] == ["rotor0", "rotor1", "rotor2", "rotor3"]
    assert labels[3] == joints + ["reference (dashed): q_ref"] and len(joints) == 3
    assert fig.axes[2].get_ylabel() == "thrust [N]"
    path = plot_result(result, module.plot_signals(), tmp_path / "hover.png")
    assert path.read_bytes()[:8] == PNG


def test_aerial_arm_sweep_plots_feedforward_on_and_off_on_one_scale(tmp_path):
    module, result = _run("aerial-arm-sweep", duration=1.0)
    log = result.log
    assert log["att_err_deg_no_ff"].shape == log["att_err_deg"].shape
    assert log.label("att_err_deg_no_ff").endswith("(feed-forward off)")
    # The two runs differ (the feed-forward is on in one only).
    assert not np.array_equal(log["att_err_deg"], log["att_err_deg_no_ff"])
    fig = _figure(module, result)
    panels = [as_panel(p) for p in module.plot_signals()]
    signals = [p.signal for p in panels]
    assert {"att_err_deg", "att_err_deg_no_ff", "att_level_deg",
            "att_level_deg_no_ff"} <= set(signals)
    on, off = fig.axes[signals.index("att_err_deg")], fig.axes[signals.index("att_err_deg_no_ff")]
    assert on.get_ylim() == off.get_ylim()
    assert "feed-forward ON" in on.get_title(loc="left") and "OFF" in off.get_title(loc="left")
    path = plot_result(result, module.plot_signals(), tmp_path / "sweep.png")
    assert path.read_bytes()[:8] == PNG


def test_describe_drops_component_names_that_do_not_fit():
    from kiloloop.scenarios.signals import describe

    log = SignalLog()
    log.put_array("t", np.zeros(2))
    log.put_array("base_pos", np.zeros((2, 3)))
    log.put_array("thrust", np.zeros((2, 6)))
    log.put_array("unknown", np.zeros(2))
    describe(log, "aerial", robot=None)
    assert log.components("base_pos") == ["x", "y", "z"] and log.unit("base_pos") == "m"
    assert log.components("thrust") is None and log.unit("thrust") == "N"  # no robot: no names
    assert log.unit("unknown") == "" and log.label("unknown") == "unknown"
