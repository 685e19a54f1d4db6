"""MCAP logs (issue 32, item 3): a quadruped-trot run logged to .mcap opens with the `mcap`
reader itself, every signal of the .npz there with its unit; .npz -> .mcap -> .npz keeps every
bit; values that rounding would change survive; `kiloloop log show` reads both formats;
`--log run.mcap` on `kiloloop run` and `kiloloop sweep`, and as `--baseline`."""
import csv
import json

import numpy as np
import pytest
from mcap.reader import make_reader

from kiloloop import cli, scenarios
from kiloloop.robot import Robot
from kiloloop.sil.log import META_KEY, RUN_KEY, SignalLog, load_log


@pytest.fixture(scope="module")
def trot(tmp_path_factory):
    """The shortest quadruped-trot the scenario judges, saved as .npz and as .mcap."""
    module = scenarios.get("quadruped-trot")
    result = scenarios.run_named("quadruped-trot", duration=scenarios.min_duration(module))
    out = tmp_path_factory.mktemp("trot")
    return result, result.log.save(out / "run.npz"), result.log.save(out / "run.mcap")


def _raw(path) -> dict:
    """Every entry of a .npz, the descriptions and the run's info included."""
    with np.load(path) as data:
        return {k: data[k] for k in data.files}


def test_the_mcap_reader_sees_every_signal_with_its_unit(trot):
    result, npz, mcap = trot
    arrays = load_log(npz)
    with open(mcap, "rb") as f:
        reader = make_reader(f)
        summary = reader.get_summary()
        channels = {c.topic: c for c in summary.channels.values()}
        assert set(channels) == {f"/{name}" for name in arrays}
        for name, series in arrays.items():
            c = channels[f"/{name}"]
            assert c.message_encoding == "json" and c.metadata["signal"] == name
            assert c.metadata["unit"] == result.log.unit(name)
            assert summary.statistics.channel_message_counts[c.id] == len(series)
            schema = summary.schemas[c.schema_id]
            assert schema.encoding == "jsonschema"
            assert set(json.loads(schema.data)["required"]) == {"timestamp", "value"}
        assert result.log.unit("tau") == "N m" and channels["/base_omega"].metadata["frame"] \
            == "trunk"
        # A message: the sample's time as log time [ns] and as timestamp [s], the value, and
        # the value by component name.
        t = arrays["t"]
        for k, (_, channel, message) in enumerate(reader.iter_messages(topics=["/tau"])):
            body = json.loads(message.data)
            assert message.log_time == round(t[k] * 1e9) and body["timestamp"] == t[k]
            joints = result.log.components("tau")
            assert body["value"] == arrays["tau"][k].tolist()
            assert [body[j] for j in joints] == body["value"]
            if k == 2:
                break
        meta = {m.name: {k: json.loads(v) for k, v in m.metadata.items()}
                for m in reader.iter_metadata() if m.name != "kiloloop.log"}
    assert meta["kiloloop.scenario"]["name"] == "quadruped-trot"
    assert meta["kiloloop.robot"]["digest"] == Robot.load("quadruped").digest()
    assert meta["kiloloop.settings"]["speed"] == result.settings["speed"]
    assert meta["kiloloop.criteria"] == result.criteria and result.criteria


def test_npz_to_mcap_to_npz_keeps_every_bit(trot, tmp_path):
    _, npz, mcap = trot
    again = SignalLog.load(npz).save(tmp_path / "again.mcap")
    assert again.read_bytes() == mcap.read_bytes()   # the writer is deterministic
    back = SignalLog.load(again).save(tmp_path / "back.npz")
    before, after = _raw(npz), _raw(back)
    assert list(after) == list(before) and RUN_KEY in after and META_KEY in after
    for key, a in before.items():
        b = after[key]
        assert a.dtype == b.dtype and a.shape == b.shape, key
        assert a.tobytes() == b.tobytes(), key


def test_values_that_rounding_would_change_survive(tmp_path):
    # 0.1 + 0.2 needs all 17 digits, 5e-324 is the smallest subnormal, -0.0 has a sign bit;
    # NaNs differ in sign and payload (x86's inf - inf is 0xfff8...), JSON has none of them.
    special = np.array([0.1 + 0.2, 5e-324, -0.0, np.nextafter(1.0, 2.0), 1 / 3, np.inf,
                        -np.inf, np.nan, np.nan, np.nan])
    bits = special.view(np.uint64)
    bits[8], bits[9] = 0xFFF8000000000000, 0x7FF0000000000001
    log = SignalLog()
    for k in range(3):
        log.record("t", 0.001 * k)
        log.record("x", special if k == 0 else special[::-1])
    log.describe("x", "m", [f"c{i}" for i in range(len(special))], frame="world")
    log.info = {"run": {"note": 0.1 + 0.2}}
    path = log.save(tmp_path / "special.mcap")
    with open(path, "rb") as f:
        first = next(make_reader(f).iter_messages(topics=["/x"]))[2]
    assert b"0.30000000000000004" in first.data and b"5e-324" in first.data
    assert b'"NaN:0xfff8000000000000"' in first.data and b'"Infinity"' in first.data
    back = SignalLog.load(path)
    assert back["x"].dtype == np.float64 and back["x"].tobytes() == log["x"].tobytes()
    assert back.info == log.info and back.frame("x") == "world"


def test_log_show_reads_both_formats_alike(trot, capsys):
    _, npz, mcap = trot
    assert cli.main(["log", "show", str(npz)]) == 0
    from_npz = capsys.readouterr().out.splitlines()
    assert cli.main(["log", "show", str(mcap)]) == 0
    from_mcap = capsys.readouterr().out.splitlines()
    assert "MCAP log, 22 signals" in from_mcap[0] and "npz log" in from_npz[0]
    assert from_npz[1:] == from_mcap[1:]
    text = "\n".join(from_mcap)
    assert "duration  2.1 s: 2100 ticks of 1 ms" in text and "quadruped-trot" in text
    tau = next(line.split() for line in from_mcap if line.split()[:1] == ["tau"])
    assert tau[:6] == ["tau", "N", "m", "-", "2100", "12"]
    assert "ok   velocity_rms_error" in text
    assert cli.main(["log", "show", str(npz.parent / "nothing.mcap")]) == 2


def test_run_and_sweep_write_mcap(tmp_path, capsys):
    log = tmp_path / "run.mcap"
    assert cli.main(["run", "arm-track", "--duration", "0.2", "--log", str(log)]) == 0
    back = SignalLog.load(log)
    assert back["q_true"].shape == (200, 6) and back.info["scenario"]["name"] == "arm-track"
    # A log is a baseline too: the same run again, every signal bit for bit.
    assert cli.main(["run", "arm-track", "--duration", "0.2", "--baseline", str(log)]) == 0
    assert cli.main(["run", "arm-track", "--log", str(tmp_path / "run.csv")]) == 2
    assert cli.main(["sweep", "arm-track", "--grid", "damping=0,1", "--duration", "0.2",
                     "--workers", "2", "--out", str(tmp_path / "s"),
                     "--log", str(tmp_path / "runs.mcap")]) == 0
    rows = list(csv.DictReader(open(tmp_path / "s.csv")))
    assert [r["log"] for r in rows] == [str(tmp_path / f"runs-{i}.mcap") for i in (0, 1)]
    second = SignalLog.load(rows[1]["log"])
    assert second.info["run"]["params"] == {"damping": "1"}
    assert second.info["settings"]["damping"] == 1.0
    capsys.readouterr()
