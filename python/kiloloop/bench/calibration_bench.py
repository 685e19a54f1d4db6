"""Kinematic calibration figures: a UR5 whose true geometry is perturbed (lengths +-1 mm, angles
+-0.2 deg, base +-2 mm / +-0.5 deg, tool point +-1 mm), measured at 60 random configurations with
0.1 mm (1 sigma per axis) noise on a point 5 cm out from the flange, identified by
`kl.calibrate_kinematics`, and checked on 50 held-out configurations. Run by `kiloloop bench` and
by tests/test_calibration.py (which asserts the same figures).
"""
from __future__ import annotations

import numpy as np

import kiloloop as kl

TOOL_POINT = np.array([0.0, 0.0, 0.05])  # [m] tracker target in tool0
NOISE = 1e-4                             # [m] 1 sigma per axis


def perturbed(nominal, rng):
    """The "true" arm: every parameter of the parameterization moved by a seeded random amount."""
    n = nominal.nq
    x = nominal.vector.copy()
    mm, deg = 1e-3, np.pi / 180
    x[0:3] += rng.uniform(-2 * mm, 2 * mm, 3)
    x[3:6] += rng.uniform(-0.5 * deg, 0.5 * deg, 3)
    x[6:6 + n] += rng.uniform(-0.2 * deg, 0.2 * deg, n)                                  # alpha
    x[6 + n:6 + 2 * n] += rng.uniform(-mm, mm, n)                                        # a
    x[6 + 2 * n:6 + 3 * n] += rng.uniform(-0.2 * deg, 0.2 * deg, n) * np.array(nominal.has_beta)
    x[6 + 3 * n:6 + 4 * n] += rng.uniform(-0.2 * deg, 0.2 * deg, n)                      # theta
    x[6 + 4 * n:6 + 5 * n] += rng.uniform(-mm, mm, n)                                    # d
    x[6 + 5 * n:] += rng.uniform(-mm, mm, 3)                                             # tool
    truth = kl.KinematicParameters.from_ur_model(_ur5(), TOOL_POINT)
    truth.vector = x
    return truth


def _ur5():
    return kl.RobotModel.from_urdf(str(kl.models_dir() / "ur5" / "ur5.urdf"))


def _measure(truth, m, rng):
    q = rng.uniform(-np.pi, np.pi, (m, truth.nq))
    p_true = np.array([truth.position(qk) for qk in q])
    return q, p_true, p_true + rng.normal(0.0, NOISE, p_true.shape)


def run_calibration_bench(seed: int = 20261122, train: int = 60, held_out: int = 50) -> dict:
    rng = np.random.default_rng(seed)
    nominal = kl.KinematicParameters.from_ur_model(_ur5(), TOOL_POINT)
    truth = perturbed(nominal, rng)
    q, _, p = _measure(truth, train, rng)
    q_test, p_test_true, p_test = _measure(truth, held_out, rng)
    out = {"seed": seed, "train_poses": train, "held_out_poses": held_out, "noise_m": NOISE}
    out["nominal_held_out_rms_m"], out["nominal_held_out_max_m"] = kl.position_residuals(nominal, q_test, p_test)
    for label, beta in (("mdh_beta", True), ("mdh_only", False)):
        config = kl.CalibrationConfig()
        config.identify_beta = beta
        r = kl.calibrate_kinematics(nominal, q, p, config)
        rms, mx = kl.position_residuals(r.parameters, q_test, p_test)
        rms_t, mx_t = kl.position_residuals(r.parameters, q_test, p_test_true)
        out[label] = {"num_parameters": r.num_parameters, "rank": r.rank,
                      "condition_number": r.condition_number, "observability_o1": r.observability_index,
                      "iterations": r.iterations, "train_rms_m": r.rms_residual,
                      "held_out_rms_m": rms, "held_out_max_m": mx,
                      "held_out_rms_vs_truth_m": rms_t, "held_out_max_vs_truth_m": mx_t}
    return out


def print_calibration_bench(r: dict) -> None:
    print(f"Kinematic calibration, UR5 with perturbed geometry, {r['train_poses']} poses, "
          f"{r['noise_m'] * 1e3:g} mm noise (1 sigma/axis), {r['held_out_poses']} held-out poses, seed {r['seed']}")
    print(f"  nominal model on held-out poses: RMS {r['nominal_held_out_rms_m'] * 1e3:.3f} mm, "
          f"max {r['nominal_held_out_max_m'] * 1e3:.3f} mm")
    print(f"  {'parameterization':<22}{'params':>7}{'rank':>6}{'cond':>9}{'O1':>8}"
          f"{'held-out RMS':>14}{'max':>9}{'max vs truth':>14}")
    for label, name in (("mdh_beta", "modified DH + beta"), ("mdh_only", "modified DH only")):
        c = r[label]
        print(f"  {name:<22}{c['num_parameters']:>7}{c['rank']:>6}{c['condition_number']:>9.1f}"
              f"{c['observability_o1']:>8.3f}{c['held_out_rms_m'] * 1e3:>11.3f} mm{c['held_out_max_m'] * 1e3:>6.3f} mm"
              f"{c['held_out_max_vs_truth_m'] * 1e3:>11.3f} mm")
    print("  goal: held-out position residual < 0.5 mm; cond = sigma_max/sigma_min of the column-scaled "
          "identification Jacobian over its observable directions")
