"""The quadruped matrix's runner (`make matrix`, `make matrix-seeds`): one cell's runs through the
same code the tables use, and a cell over seeds that counts passes and names the failing ones."""
from kiloloop.bench.quadruped_matrix import _cell, _run_one, _seeds_cell


def test_one_run_is_recorded_with_its_seed_and_verdict():
    record = _run_one(("quadruped", "quadruped", "quadruped-stand", {}, 0.010, True, 3))
    assert record["seed"] == 3 and record["error"] == ""
    assert record["sets"] == {"motor_delay": 0.010, "ideal_sensors": "false"}
    assert record["passed"] and record["failed"] == []
    assert _cell("quadruped-stand", record).startswith("pass (height_error_after_1s_m ")


def test_a_refused_run_is_a_failing_record_not_an_exception():
    record = _run_one(("quadruped", "quadruped", "no-such-scenario", {}, 0.010, True, 0))
    assert not record["passed"] and record["error"]
    assert _cell("no-such-scenario", record).startswith("error: ")


def test_seeds_cell_counts_passes_and_names_the_failing_seeds():
    def rec(seed, passed, roll):
        return {"seed": seed, "passed": passed, "error": "", "failed": [] if passed else ["roll_after_recovery_deg"],
                "metrics": {"roll_after_recovery_deg": roll, "fell": 0.0}}
    cell = _seeds_cell("quadruped-push", [rec(0, True, 0.9), rec(1, False, 1.1), rec(2, True, 0.95)])
    assert cell.startswith("2/3 pass; worst seed 1: fail (roll_after_recovery_deg 1.1)")
    assert cell.endswith("failing seeds 1 (roll_after_recovery_deg)")
    assert _seeds_cell("quadruped-push", [rec(0, True, 0.9), rec(2, True, 0.95)]) == \
        "2/2 pass; worst seed 2: pass (roll_after_recovery_deg 0.95)"
