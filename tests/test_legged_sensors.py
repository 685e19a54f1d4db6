"""The quadruped rig's realistic sensors: the C++ measurement stages (cpp/sil/
legged_sensor_stages.hpp) the native loop runs, called through the bindings: seeded IMU bias,
quantized q and qd from encoder differences; the rig hands the controller no orientation with them. The IMU
model's statistics are tested in C++ (cpp/sil/imu_model_test.cpp)."""
import numpy as np
import pytest

from kiloloop.sil import native
from kiloloop.sil.legged_sensors import LeggedSensorSettings, stages

pytestmark = pytest.mark.skipif(not native.available(), reason="native SIL models not built")

N = 12
GYRO, ACCEL = np.array([0.1, -0.2, 0.3]), np.array([0.0, 0.5, 9.81])


def run(seed, n, q_of_k=lambda k: np.full(N, 0.3), qd=np.zeros(N), settings=None):
    chain = stages(settings or LeggedSensorSettings(ideal=False), joints=N, imu_offset=2 * N,
                   encoder_resolution=np.deg2rad(0.1), seed=seed)
    for s in chain:
        s.configure(2 * N + 10)
    out = []
    for k in range(n):
        y = np.concatenate([q_of_k(k), qd, GYRO, ACCEL, [1.0, 0.0, 0.0, 0.0]])
        for s in chain:
            y = s.apply(k * 0.001, y)
        out.append(y)
    return np.array(out)


def test_ideal_has_no_stages():
    assert stages(LeggedSensorSettings(ideal=True), joints=N, imu_offset=2 * N,
                  encoder_resolution=0.0, seed=0) == []


def test_imu_carries_a_seeded_bias():
    n = 20000
    s = LeggedSensorSettings(ideal=False)
    a, b, c = run(3, n), run(3, n), run(4, n)
    np.testing.assert_array_equal(a, b)
    # The mean error is the bias (turn-on + walk), not zero: it differs between seeds by about
    # the turn-on sigma, far more than the white noise's standard error.
    mean_a = a[:, 2 * N:2 * N + 3].mean(axis=0) - GYRO
    mean_c = c[:, 2 * N:2 * N + 3].mean(axis=0) - GYRO
    white = s.gyro_noise_density / np.sqrt(0.001) / np.sqrt(n)
    assert np.max(np.abs(mean_a - mean_c)) > 10 * white
    assert np.max(np.abs(mean_a)) < 5 * (s.gyro_turn_on_bias + 10 * white)


def test_joint_velocity_comes_from_encoder_differences():
    s = LeggedSensorSettings(ideal=False)
    v, dt = 0.37, 0.001
    y = run(0, 200, q_of_k=lambda k: np.full(N, 0.2 + v * k * dt), qd=np.full(N, 123.0))
    qd = y[:, N:2 * N]  # the simulator's 123 rad/s is not used
    np.testing.assert_array_equal(qd[0], 0.0)
    steps = qd[1:] * dt / s.velocity_resolution
    np.testing.assert_allclose(steps, np.round(steps), atol=1e-6)
    assert abs(qd[1:, 0].mean() - v) < s.velocity_resolution / (199 * dt) + 1e-12
    q = y[:, :N]
    res = np.deg2rad(0.1)
    np.testing.assert_allclose(q / res, np.round(q / res), atol=1e-9)


def test_a_stage_that_does_not_fit_y_is_refused():
    chain = stages(LeggedSensorSettings(ideal=False), joints=N, imu_offset=2 * N, encoder_resolution=0.0, seed=0)
    with pytest.raises(ValueError, match="imu stage"):
        chain[1].configure(2 * N + 3)
    with pytest.raises(ValueError, match="encoder"):
        native._native.JointEncoderStage(N, 0, N, -1.0, 1e-4, 0.001)
