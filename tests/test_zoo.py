"""The zoo's fast subset (`make zoo` runs all of bench/zoo.md): a handful of its cells, seed 0, each
robot from the zoo's own minimal robot file (python/kiloloop/bench/zoo_robots.py): a 7-DoF arm that
is not ours (Panda, the e-stop), a quadruped that is not ours (A1 standing), a multirotor of
example-robot-data without an arm (Hector, hover) and one with an arm (Borinot, wind). Then what
the harness does with what is not a pass: a refusal at start (a quadruped whose knee cannot hold
its weight: the zoo's cell, and `kiloloop run`'s one line and exit 2; rotors that cannot lift
the vehicle), a metric not computed
(its reason, never a number), and the table writer on a tiny fake result."""
from __future__ import annotations

import pytest

from kiloloop import scenarios
from kiloloop.bench import zoo, zoo_robots
from kiloloop.scenarios import NotComputed, evaluate

if zoo_robots.erd_share() is None:
    pytest.skip("example-robot-data (a test dependency) is not installed", allow_module_level=True)

# The cheapest representative cells that pass on every seed of bench/zoo.md.
CELLS = [("panda", "arm-estop", None), ("a1", "quadruped-stand", 0.010),
         ("hector", "aerial-hover", None), ("borinot", "aerial-wind", None)]


@pytest.mark.parametrize("robot,scenario,delay", CELLS)
def test_zoo_cell_passes(tmp_path, robot, scenario, delay):
    path = zoo_robots.robot_file(robot, tmp_path)
    record = zoo.run_one((robot, str(path), scenario, 0, delay))
    failed = {k: c for k, c in record["criteria"].items() if not c["passed"]}
    assert record["outcome"] == "passed", (record["text"], failed)
    assert record["criteria"] and record["mass_kg"] > 0


def test_minimal_files_hold_only_names_and_rotors(tmp_path):
    """Nothing tuned: a zoo file has the basics, its family's naming table and (aerial) rotors."""
    import tomllib

    allowed = {"name", "kind", "urdf", "package_dirs", "chain", "legs", "vehicle", "rotors"}
    for name in zoo_robots.ROBOTS:
        data = tomllib.loads(zoo_robots.robot_text(name))
        assert set(data) <= allowed, name
        assert ("rotors" in data) == (data["kind"] == "aerial"), name
    iris = tomllib.loads(zoo_robots.robot_text("iris"))
    # The rotor positions come from iris_simple.urdf's rotor links (rotor_0 at 0.13 -0.22 0.023).
    assert iris["rotors"][0]["position"] == [0.13, -0.22, 0.023]


def _weak_knee_go1(tmp_path):
    path = zoo_robots.robot_file("go1", tmp_path)
    path.write_text(path.read_text() + "\n[limits.FL_calf_joint]\neffort = 2.0\n")
    return path


def test_refused_at_start_is_a_cell_and_one_cli_line(tmp_path, capsys):
    """A quadruped whose front-left knee gives 2 N m (Go1 needs 5.6 standing): every quadruped
    scenario refuses it at start; the zoo shows the reason, `kiloloop run` prints one line."""
    from kiloloop.cli import main
    from kiloloop.errors import ScenarioRefused

    path = _weak_knee_go1(tmp_path)
    with pytest.raises(ScenarioRefused, match="FL_calf_joint"):
        scenarios.run_named("quadruped-trot", str(path))
    record = zoo.run_one(("go1", str(path), "quadruped-stand", 0, 0.010))
    assert record["outcome"] == "refused" and "effort limit is 2 N m" in record["text"]
    assert zoo.cell_text([record]).startswith("refused: go1: quadruped-stand refused at start")

    assert main(["run", "quadruped-stand", "--robot", str(path)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "standing needs" in err and "Traceback" not in err


def test_rotors_that_cannot_lift_the_vehicle_are_refused(tmp_path):
    """Iris (1.5 kg) with 3 N rotors: 12 N of thrust for 14.8 N of weight."""
    from kiloloop.errors import ScenarioRefused

    path = zoo_robots.robot_file("iris", tmp_path)
    path.write_text(path.read_text().replace(f"thrust_max = {zoo_robots.IRIS_THRUST_MAX!r}",
                                             "thrust_max = 3.0"))
    with pytest.raises(ScenarioRefused, match="cannot lift the vehicle .largest collective "
                                              "thrust 12.0+ N <= m g = 15.05"):
        scenarios.prepare(scenarios.get("aerial-hover"), str(path))


def test_not_computed_metric_fails_with_its_reason(capsys):
    from kiloloop.cli import _print_summary

    table = evaluate({"stop_time": ("<", 0.5), "drift": ("<", 1.0), "peak": (">", 0.0),
                      "ok": ("<", 1.0)},
                     {"stop_time": NotComputed("the arm never stopped"), "drift": float("nan"),
                      "ok": 0.5}, reasons={"peak": "no contact"})
    assert table["stop_time"] == {**table["stop_time"], "passed": False,
                                  "reason": "not computed: the arm never stopped"}
    assert table["drift"]["reason"] == "not computed: NaN (the scenario gave no reason)"
    assert table["peak"]["reason"] == "not computed: no contact" and not table["peak"]["passed"]
    assert table["ok"]["passed"] and "reason" not in table["ok"]
    fell = evaluate({"drift": ("<", 1.0)}, {"drift": float("nan"), "fell": 1.0})
    assert fell["drift"]["reason"] == "not computed: NaN, the run ended early (fell)"

    result = scenarios.ScenarioResult("x", {"stop_time": table["stop_time"]["value"]}, table)
    _print_summary(result, {})
    out = capsys.readouterr().out
    assert "FAIL stop_time: not computed: the arm never stopped" in out and "nan" not in out


def _record(robot, scenario, seed, outcome="passed", criteria=None, text="", kind="arm",
            delay=None):
    return {"robot": robot, "kind": kind, "scenario": scenario, "seed": seed, "delay_ms": delay,
            "mass_kg": 10.6, "outcome": outcome, "passed": outcome == "passed",
            "criteria": criteria or {}, "text": text, "wall_s": 1.0, "date": "2026-11-28"}


def test_table_writer_on_a_fake_result(tmp_path):
    ok = {"max_ee_error_m": {"value": 0.001, "op": "<", "threshold": 0.005, "passed": True}}

    def bad(v):
        return {"max_ee_error_m": {"value": v, "op": "<", "threshold": 0.005, "passed": False}}
    nan = {"stop_time": {"value": None, "op": "<", "threshold": 0.5, "passed": False,
                         "reason": "not computed: the arm never stopped"}}
    records = [_record("ur3", "arm-track", s, criteria=ok) for s in range(5)]
    records += [_record("ur3", "arm-line", 0, criteria=ok),
                _record("ur3", "arm-line", 1, "failed", bad(0.009)),
                _record("ur3", "arm-line", 2, "failed", bad(0.02)),
                _record("ur3", "arm-estop", 0, "failed", nan),
                _record("ur3", "arm-press", 0, "refused", text="ur3: arm-press refused at "
                        "start: a | in the reason")]
    assert zoo.cell_text(records[:5]) == "5/5"
    assert zoo.cell_text(records[5:8]) == "1/3: max_ee_error_m 0.02 (< 0.005) [seed 2]"
    assert zoo.cell_text(records[8:9]) == \
        "0/1: stop_time not computed: the arm never stopped [seed 0]"
    assert zoo.cell_text(records[9:]) == \
        "refused: ur3: arm-press refused at start: a \\| in the reason"

    zoo.write(records, tmp_path)
    text = (tmp_path / "zoo.md").read_text()
    row = next(line for line in text.splitlines() if line.startswith("| ur3"))
    assert row.startswith("| ur3 (10.6 kg) | 5/5 | 1/3: max_ee_error_m 0.02")
    assert "arms: 1 robots, 10 runs, seeds 0,1,2,3,4" in text
    # A rerun of one cell replaces its records, the others stay.
    merged = zoo.merge(records, [_record("ur3", "arm-line", 2, criteria=ok)])
    assert len(merged) == len(records)
    assert zoo.cell_text([r for r in merged if r["scenario"] == "arm-line"]).startswith("2/3")


def test_jobs_cover_every_family_scenario():
    jobs = zoo.jobs_for(["go1", "iris"], [], [0, 1], None)
    quadruped = [n for n in scenarios.names() if n.startswith("quadruped-")]
    aerial = [n for n in scenarios.names() if n.startswith("aerial-")]
    assert len(jobs) == len(quadruped) * 2 * 2 + len(aerial) * 2
    assert {d for _, s, _, d in jobs if s.startswith("quadruped-")} == {0.010, 0.035}
    assert {d for _, s, _, d in jobs if s.startswith("aerial-")} == {None}
    assert zoo.jobs_for(["go1"], ["quadruped-st"], [0], [10]) == []     # a prefix ends in '-'
    assert len(zoo.jobs_for(["go1"], ["quadruped-"], [0], [10])) == len(quadruped)
