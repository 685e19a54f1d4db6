"""The identification acceptance (issue 34): hidden-parameter SIL logs, 5 seeds per case, every
identified parameter against the truth, and the family's tracking scenario re-run on the true
file and on the identified one. `python -m kiloloop.ident.acceptance [--family arm|aerial]
[--seeds 5] [--json FILE]` prints the table bench/identification.md keeps."""
from __future__ import annotations

import argparse
import json
import sys
import tempfile
from pathlib import Path

import numpy as np

import kiloloop as kl

from .excite import excite
from .identify import identify
from .truth import UR5_JOINTS, Hidden, nominal_joints, true_payload, write_true_robot

DURATION = 30.0  # [s] of excitation (the budget)


def seed_delay(seed: int) -> float:
    """[s] the true actuation delay of a seed: whole ms spread over 10 to 35 ms."""
    return 0.001 * float(np.random.default_rng(1000 + seed).integers(10, 36))


def arm_cases(seed: int) -> dict[str, Hidden]:
    d = seed_delay(seed)
    return {"friction x2, armature x0.5": Hidden(2.0, 0.5, 0.3, d),
            "friction x0.5, armature x2": Hidden(0.5, 2.0, 0.3, d)}


def _tracking(robot_path, scenario: str, metric: str) -> tuple[float, np.ndarray]:
    """(the scenario's metric, its joint trajectory q_true (ticks, nq) [rad])."""
    from .. import scenarios

    robot = kl.Robot.load(robot_path)
    result = scenarios.run_named(scenario, robot=robot)
    return float(result.metrics[metric]), np.asarray(result.log["q_true"])


# White encoder noise of `--encoder-noise` rows: q [rad], qd [rad/s].
ENCODER_NOISE = {"q_sigma": 1e-5, "qd_sigma": 2e-3}


def arm_row(nominal, hidden: Hidden, seed: int, work: Path, noise=None) -> dict:
    true_path = write_true_robot(nominal, hidden, work / "true")
    log_path = work / "excite.npz"
    excite(kl.Robot.load(true_path), DURATION, seed, noise=noise).save(log_path)
    patch = work / "identified.toml"
    ident, _, _ = identify(nominal, [log_path], patch)
    damping, friction, armature = nominal_joints(nominal)
    mass, com = true_payload(nominal, hidden)

    def worst(est, true):
        return float(np.max(np.abs(np.asarray(est) / np.asarray(true) - 1.0)))
    row = {"seed": seed, "delay_true_ms": hidden.delay * 1e3, "delay_ms": ident.delay * 1e3,
           "damping_err": worst(ident.damping, damping * hidden.friction_scale),
           "coulomb_err": worst(ident.frictionloss, friction * hidden.friction_scale),
           "armature_err": worst(ident.armature, armature * hidden.armature_scale),
           "payload_mass_err": abs(ident.payload_mass / mass - 1.0),
           "payload_com_err": float(np.linalg.norm(ident.payload_com - com) / np.linalg.norm(com)),
           "residual_rms": ident.residual_rms}
    metric = "rms_joint_error_rad"
    row["track_true"], q_true = _tracking(true_path, "arm-track", metric)
    row["track_identified"], q_ident = _tracking(patch, "arm-track", metric)
    row["track_nominal"], q_nominal = _tracking(_nominal_file(nominal, work), "arm-track", metric)
    row["track_err"] = abs(row["track_identified"] / row["track_true"] - 1.0)
    # How far the runs' joint trajectories lie from the true plant's [rad RMS]: the tracking
    # errors' sizes alone can be alike (friction x2 and x0.5 both near the nominal's).
    row["gap_nominal"] = float(np.sqrt(np.mean((q_nominal - q_true) ** 2)))
    row["gap_identified"] = float(np.sqrt(np.mean((q_ident - q_true) ** 2)))
    return row


def _nominal_file(nominal, work: Path) -> Path:
    from .patch import robot_data, write

    return write(robot_data(nominal, work / "nominal.toml"), work / "nominal.toml",
                 ["the nominal file of the acceptance"])


def run_arm(seeds, noise=None) -> list[dict]:
    nominal = kl.Robot.load("ur5", UR5_JOINTS)
    rows = []
    for seed in seeds:
        for case, hidden in arm_cases(seed).items():
            with tempfile.TemporaryDirectory() as tmp:
                row = {"case": case, **arm_row(nominal, hidden, seed, Path(tmp), noise)}
            rows.append(row)
            print(json.dumps(row), file=sys.stderr, flush=True)
    return rows


def table(rows: list[dict], columns: list[str]) -> str:
    head = "| " + " | ".join(columns) + " |\n|" + "---|" * len(columns) + "\n"
    def fmt(v):
        return f"{v:.3g}" if isinstance(v, float) else str(v)
    return head + "".join("| " + " | ".join(fmt(r[c]) for c in columns) + " |\n" for r in rows)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m kiloloop.ident.acceptance")
    ap.add_argument("--family", choices=("arm", "aerial"), default="arm")
    ap.add_argument("--seeds", type=int, default=5)
    ap.add_argument("--json", default=None)
    ap.add_argument("--encoder-noise", action="store_true",
                    help=f"an arm's logs with white encoder noise {ENCODER_NOISE}")
    args = ap.parse_args(argv)
    if args.family == "arm":
        rows = run_arm(range(args.seeds), ENCODER_NOISE if args.encoder_noise else None)
        cols = ["case", "seed", "delay_true_ms", "delay_ms", "damping_err", "coulomb_err",
                "armature_err", "payload_mass_err", "payload_com_err", "track_nominal",
                "track_true", "track_identified", "track_err", "gap_nominal", "gap_identified"]
    else:
        from .multirotor_acceptance import run_aerial, COLUMNS as cols

        rows = run_aerial(range(args.seeds))
    print(table(rows, cols))
    if args.json:
        Path(args.json).write_text(json.dumps(rows, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
