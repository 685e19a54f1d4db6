"""The arm benchmark program runs and reports zero heap allocations per step."""
import json
import subprocess
from importlib.resources import files
from pathlib import Path

import kiloloop as kl


def test_bench_arm_reports_zero_allocations_and_no_failures():
    exe = Path(str(files("kiloloop") / "bin" / "kiloloop_bench_arm"))
    urdf = kl.models_dir() / "ur5" / "ur5.urdf"
    out = subprocess.run([str(exe), str(urdf), "--calls", "3000", "--json"], check=True,
                         capture_output=True, text=True)
    report = json.loads(out.stdout)
    names = {r["name"] for r in report["results"]}
    assert {"CartesianImpedance.step", "HybridForcePosition.step", "ArmSupervisor.step (normal)",
            "ArmSupervisor.step (e-stop)", "SingularityMonitor.update"} <= names
    for r in report["results"]:
        assert r["allocations_per_call"] == 0, r["name"]
        assert r["failures"] == 0, r["name"]
        assert 0 < r["median_ns"] <= r["p99_ns"] <= r["max_ns"]
    assert report["plan"]["failures"] == 0
