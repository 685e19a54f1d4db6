"""Rotor allocation through the bindings: exact when unsaturated, priorities when saturated
(roll/pitch kept, thrust shifted only as needed, yaw given up first), with the model's rotors."""
import numpy as np

import kiloloop as kl
from kiloloop.sil.aerial_family import rotor_config


def test_unsaturated_wrench_is_reproduced_exactly(rng):
    alloc = kl.RotorAllocation(rotor_config())
    A = np.asarray(alloc.mixer)
    for _ in range(500):
        w = np.array([rng.uniform(10, 22), *rng.uniform(-0.3, 0.3, 2), rng.uniform(-0.04, 0.04)])
        status, f, achieved = alloc.allocate(w)
        assert status == kl.Status.OK
        np.testing.assert_allclose(A @ f, w, atol=1e-12)
        np.testing.assert_allclose(achieved, w, atol=1e-12)
        # Independent oracle: the plain inverse of the mixer.
        np.testing.assert_allclose(f, np.linalg.solve(A, w), atol=1e-12)


def test_saturation_gives_up_yaw_before_roll_pitch(rng):
    config = rotor_config()
    alloc = kl.RotorAllocation(config)
    for _ in range(300):
        # Roll/pitch that fit at some thrust, plus a yaw demand far beyond what is left.
        w = np.array([rng.uniform(24, 30), *rng.uniform(-0.4, 0.4, 2),
                      rng.choice([-1, 1]) * rng.uniform(0.2, 0.5)])
        status, f, achieved = alloc.allocate(w)
        assert status == kl.Status.SATURATED
        assert np.all(f >= config.thrust_min) and np.all(f <= config.thrust_max)
        np.testing.assert_allclose(achieved[1:3], w[1:3], atol=1e-9)   # roll, pitch kept
        assert abs(achieved[3]) < abs(w[3]) and achieved[3] * w[3] >= -1e-12  # yaw reduced


def test_thrust_is_shifted_before_roll_pitch_is_scaled():
    alloc = kl.RotorAllocation(rotor_config())
    status, f, achieved = alloc.allocate(np.array([1.0, 0.5, 0.0, 0.0]))
    assert status == kl.Status.SATURATED
    assert achieved[1] == np.float64(0.5) or abs(achieved[1] - 0.5) < 1e-12
    assert achieved[0] > 1.0
