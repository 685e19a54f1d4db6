"""`kiloloop sweep`: a tiny grid in parallel processes; a diverging run is reported with its reason
and does not stop the others; CSV and heat map are written."""
import csv

import pytest

from kiloloop import cli, sweep


def test_parse_grid_and_combinations():
    grid = sweep.parse_grid(["a=1,2", "b=x"])
    assert grid == {"a": ["1", "2"], "b": ["x"]}
    assert sweep.combinations(grid) == [{"a": "1", "b": "x"}, {"a": "2", "b": "x"}]
    with pytest.raises(ValueError, match="KEY=V1"):
        sweep.parse_grid(["nokey"])


def test_sweep_runs_in_parallel_and_survives_a_diverging_run(tmp_path, capsys):
    # att_kp = 4000 [1/s^2] is far beyond what the 30 ms rotor lag allows: the vehicle flips.
    code = cli.main(["sweep", "aerial-hover", "--grid", "att_kp=400,4000", "--workers", "2",
                     "--duration", "1.0", "--metric", "max_position_error_m",
                     "--out", str(tmp_path / "hover")])
    out = capsys.readouterr().out
    assert code == 0
    rows = list(csv.DictReader(open(tmp_path / "hover.csv")))
    assert [r["att_kp"] for r in rows] == ["400", "4000"]
    assert rows[0]["passed"] == "1" and rows[0]["reason"] == ""
    assert rows[1]["passed"] == "0" and "60 deg" in rows[1]["reason"]
    assert float(rows[0]["max_position_error_m"]) < 0.02
    assert (tmp_path / "hover.png").stat().st_size > 1000
    assert "1/2 passed" in out and "diverged" in out


def test_a_run_that_raises_is_recorded_not_fatal():
    r = sweep.run_one("aerial-hover", {"law": "no_such_law"}, seed=0, duration=0.1)
    assert not r["passed"] and r["reason"].startswith("error: InputError")


def test_unknown_setting_is_a_usage_error(capsys):
    assert cli.main(["sweep", "aerial-hover", "--grid", "nope=1,2"]) == 2
    assert "unknown setting" in capsys.readouterr().err
