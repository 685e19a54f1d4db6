"""The aerial benchmark runs and reports allocation-free controller steps (timings are printed by
`kiloloop bench`, never asserted)."""
from kiloloop.bench.aerial_bench import run_aerial_bench


def test_aerial_bench_quick_reports_zero_allocations():
    report = run_aerial_bench(quick=True)
    names = {r["name"] for r in report["core"]["results"]}
    assert any(n.startswith("aerial.step") for n in names)
    assert "floating_base_rne.compute" in names
    for n in (4, 6, 8):
        assert f"rotor_allocation.allocate ({n} rotors)" in names
    assert {"aerial.step (6 rotors, joints)", "aerial.step (8 rotors, joints)"} <= names
    for r in report["core"]["results"]:
        assert r["allocations_per_call"] == 0, r["name"]
        assert 0 < r["median_ns"] <= r["p99_ns"] <= r["max_ns"]
    assert report["sil"]["real_time_factor"] > 0
    assert report["crosscheck"]["max_tau_error_Nm"] < 1e-6
