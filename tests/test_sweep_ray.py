"""`kiloloop sweep --backend ray` on a local Ray instance: the same CSV as the local backend for
the same seeds (every column but the wall time), and a failing run is a row, not a crash."""
import csv

import pytest

from kiloloop import cli

ray = pytest.importorskip("ray")


@pytest.fixture(scope="module")
def local_ray():
    # A small object store (results are a few kB): kind to a shared machine.
    ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False,
             object_store_memory=100 * 1024 * 1024)
    yield
    ray.shutdown()


def rows(path):
    with open(path) as f:
        return [{k: v for k, v in r.items() if k != "wall_s"} for r in csv.DictReader(f)]


def test_ray_csv_equals_local_csv(tmp_path, local_ray, capsys):
    # att_kp = 4000 flips the vehicle: a failed run with its reason, in both CSVs.
    args = ["sweep", "aerial-hover", "--grid", "att_kp=400,4000", "--grid", "gyro_sigma=0.01,0.05",
            "--duration", "0.6", "--seed", "3", "--workers", "2",
            "--metric", "max_position_error_m"]
    assert cli.main(args + ["--out", str(tmp_path / "local")]) == 0
    assert cli.main(args + ["--out", str(tmp_path / "ray"), "--backend", "ray"]) == 0
    local, remote = rows(tmp_path / "local.csv"), rows(tmp_path / "ray.csv")
    assert len(local) == 4 and local == remote
    assert (tmp_path / "ray.png").stat().st_size > 1000
    assert any(r["passed"] == "0" for r in remote)
    assert "4/4" in capsys.readouterr().err  # the progress bar reached the end


def test_ray_captures_a_run_that_raises(local_ray):
    from kiloloop import sweep

    results = sweep.run_sweep("aerial-hover", {"law": ["quaternion_pd", "no_such_law"]},
                              duration=0.2, backend="ray")
    assert results[0]["reason"] == ""
    assert not results[1]["passed"] and results[1]["reason"].startswith("error:")
