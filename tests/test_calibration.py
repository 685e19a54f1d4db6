"""Kinematic calibration: the figures `kiloloop bench` prints, with the issue's bound asserted.
The true arm is a perturbed URDF evaluated by KDL, not the identified parameterization, so the
bound and the with/without-beta comparison are measurements that can fail."""
import numpy as np
import pytest

import kiloloop as kl
from kiloloop.bench.calibration_bench import (TOOL_POINT, UrdfArm, perturbed_urdf,
                                              print_calibration_bench, run_calibration_bench)


@pytest.mark.parametrize("seed", [20261122, 7])
def test_calibrated_ur5_is_within_half_a_millimetre_on_held_out_poses(seed):
    r = run_calibration_bench(seed=seed)
    print_calibration_bench(r)
    c = r["mdh_beta"]
    assert r["nominal_held_out_rms_m"] > 2e-3  # millimetres before calibration
    assert c["held_out_rms_m"] < 0.5e-3 and c["held_out_max_vs_truth_m"] < 0.5e-3
    assert c["rank"] < c["num_parameters"] and c["condition_number"] < 1e4
    # Without beta the tilts between the parallel axes of the perturbed URDF cannot be represented.
    assert r["mdh_only"]["held_out_rms_vs_truth_m"] > c["held_out_rms_vs_truth_m"]


def test_perturbed_urdf_moves_every_joint_origin_and_nothing_else(ur5_urdf, rng):
    xml = ur5_urdf.read_text()
    nominal = UrdfArm(xml)
    same = UrdfArm(perturbed_urdf(xml, rng, xyz=0.0, rpy=0.0))
    moved = UrdfArm(perturbed_urdf(xml, rng))
    assert moved.model.joint_names == nominal.model.joint_names
    worst_same, worst_moved = 0.0, 0.0
    for q in rng.uniform(-np.pi, np.pi, (20, 6)):
        worst_same = max(worst_same, np.linalg.norm(same.position(q) - nominal.position(q)))
        worst_moved = max(worst_moved, np.linalg.norm(moved.position(q) - nominal.position(q)))
    assert worst_same < 1e-12
    assert 1e-3 < worst_moved < 0.05  # millimetres, not a different robot


def test_nominal_parameters_match_the_model(ur5_model, rng):
    k = kl.KinematicParameters.from_ur_model(ur5_model, TOOL_POINT)
    dyn = kl.Dynamics(ur5_model)
    for q in rng.uniform(-np.pi, np.pi, (20, 6)):
        T = dyn.forward_kinematics(q)
        assert np.linalg.norm(k.position(q) - (T[:3, 3] + T[:3, :3] @ TOOL_POINT)) < 1e-12
    assert list(k.has_beta) == [False, False, True, True, False, False]


def test_bad_shapes_raise(ur5_model):
    k = kl.KinematicParameters.from_ur_model(ur5_model)
    with pytest.raises(ValueError, match="q"):
        kl.calibrate_kinematics(k, np.zeros((10, 5)), np.zeros((10, 3)))
    with pytest.raises(ValueError, match="p"):
        kl.calibrate_kinematics(k, np.zeros((10, 6)), np.zeros((9, 3)))
    p = np.zeros((10, 3))
    p[0, 0] = np.nan
    with pytest.raises(ValueError, match="finite"):
        kl.calibrate_kinematics(k, np.zeros((10, 6)), p)
