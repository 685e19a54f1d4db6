"""Sensor and actuator non-idealities (python/kiloloop/sil/nonideal.py): statistics under a seed,
quantization, an exact delay in ticks, saturation, and the identity when disabled."""
import numpy as np
import pytest

from kiloloop.sil.nonideal import MotorDelay, NonIdealities, SensorModel, saturate

SEED = 4242
N = 20000  # samples: the std of a sample std is sigma / sqrt(2 N) = 0.5 % of sigma


def ideal_imu():
    return {"gyro": np.array([0.1, -0.2, 0.3]), "accel": np.array([0.0, 0.5, 9.81]),
            "quat": np.array([np.cos(0.2), 0.0, np.sin(0.2), 0.0])}


def sample(model, n=N, q=None, qd=None):
    q = np.zeros(12) if q is None else q
    qd = np.zeros(12) if qd is None else qd
    return [model.apply(ideal_imu(), q, qd) for _ in range(n)]


def test_imu_noise_statistics():
    print(f"seed={SEED}")
    cfg = NonIdealities(gyro_sigma=0.02, accel_sigma=0.05)
    out = sample(SensorModel(cfg, seed=SEED))
    ref = ideal_imu()
    for key, sigma in (("gyro", cfg.gyro_sigma), ("accel", cfg.accel_sigma)):
        err = np.array([imu[key] for imu, _, _ in out]) - ref[key]
        np.testing.assert_allclose(err.std(axis=0), sigma, rtol=0.05, err_msg=f"{key} seed={SEED}")
        # zero mean: within 4 standard errors
        assert np.all(np.abs(err.mean(axis=0)) < 4 * sigma / np.sqrt(N)), key
        # independent axes
        corr = np.corrcoef(err.T)
        assert np.max(np.abs(corr - np.eye(3))) < 0.05, key
    # quat_sigma 0 by default: the orientation passes through exactly
    for imu, _, _ in out[:10]:
        np.testing.assert_array_equal(imu["quat"], ref["quat"])


def test_orientation_noise_is_a_small_body_rotation():
    print(f"seed={SEED}")
    sigma = 0.01
    out = sample(SensorModel(NonIdealities(quat_sigma=sigma), seed=SEED), n=5000)
    ref = ideal_imu()["quat"]
    angles = []
    for imu, _, _ in out:
        quat = imu["quat"]
        assert np.linalg.norm(quat) == pytest.approx(1.0, abs=1e-12)
        # the angle of ref^-1 * quat is 2 acos(|<ref, quat>|); its rms is sigma * sqrt(3)
        angles.append(2 * np.arccos(min(1.0, abs(ref @ quat))))
    assert np.sqrt(np.mean(np.square(angles))) == pytest.approx(sigma * np.sqrt(3), rel=0.05)


def test_same_seed_same_stream_and_reset():
    a = sample(SensorModel(seed=SEED), n=50)
    b_model = SensorModel(seed=SEED)
    b = sample(b_model, n=50)
    for (ia, _, _), (ib, _, _) in zip(a, b):
        np.testing.assert_array_equal(ia["gyro"], ib["gyro"])
        np.testing.assert_array_equal(ia["accel"], ib["accel"])
    b_model.reset(seed=SEED)
    again = sample(b_model, n=1)[0][0]
    np.testing.assert_array_equal(again["gyro"], a[0][0]["gyro"])
    other = sample(SensorModel(seed=SEED + 1), n=1)[0][0]
    assert not np.array_equal(other["gyro"], a[0][0]["gyro"])


def test_encoder_quantization_step():
    step = np.deg2rad(0.1)
    model = SensorModel(NonIdealities(), seed=SEED)
    assert model.settings.encoder_resolution == pytest.approx(step)
    print(f"seed={SEED}")
    q = np.random.default_rng(SEED).uniform(-3, 3, size=12)
    _, q_meas, _ = model.apply(ideal_imu(), q, np.zeros(12))
    # on the grid, within half a step of the truth
    np.testing.assert_allclose(q_meas / step, np.round(q_meas / step), rtol=0, atol=1e-9)
    assert np.all(np.abs(q_meas - q) <= step / 2 + 1e-12)
    # a slow ramp moves the reading in whole steps only
    ramp = np.linspace(0.0, 10 * step, 1001)
    readings = np.array([model.quantize(np.array([x]))[0] for x in ramp])
    jumps = np.diff(readings)
    jumps = jumps[jumps != 0]
    assert len(jumps) == 10
    np.testing.assert_allclose(jumps, step, rtol=1e-9)


def test_velocity_from_encoder_differences():
    dt = 0.001
    step = np.deg2rad(0.1)
    model = SensorModel(NonIdealities(velocity_from_encoder_diff=True), seed=SEED, control_dt=dt)
    qd_true = 0.5  # [rad/s]
    qds = []
    for k in range(1000):
        q = np.full(12, qd_true * k * dt)
        _, _, qd = model.apply(ideal_imu(), q, np.full(12, qd_true))
        qds.append(qd[0])
    qds = np.array(qds)
    assert qds[0] == 0.0  # no history yet
    # each reading is a whole number of encoder steps per tick; the mean is the true speed
    np.testing.assert_allclose(qds[1:] * dt / step, np.round(qds[1:] * dt / step), atol=1e-9)
    assert np.mean(qds[1:]) == pytest.approx(qd_true, rel=0.01)
    # default: velocity passes through unchanged
    _, _, qd = SensorModel(seed=SEED).apply(ideal_imu(), np.zeros(12), np.full(12, 0.123))
    np.testing.assert_array_equal(qd, np.full(12, 0.123))


@pytest.mark.parametrize("delay,ticks", [(0.0, 0), (0.001, 1), (0.010, 10), (0.035, 35),
                                         (0.0025, 3), (0.0024, 2), (0.0215, 22)])
def test_motor_delay_is_exactly_n_ticks(delay, ticks):
    fifo = MotorDelay(delay, control_dt=0.001)
    assert fifo.ticks == ticks
    assert fifo.delay == pytest.approx(ticks * 0.001)
    out = [fifo.push(np.array([k + 1.0, -(k + 1.0)])) for k in range(60)]
    for k, tau in enumerate(out):
        expected = np.zeros(2) if k < ticks else np.array([k + 1.0 - ticks, -(k + 1.0 - ticks)])
        np.testing.assert_array_equal(tau, expected, err_msg=f"tick {k}")


def test_motor_delay_initial_first_and_reset():
    fifo = MotorDelay(0.003, control_dt=0.001, initial="first")
    out = [fifo.push(np.array([float(k + 1)]))[0] for k in range(6)]
    assert out == [1.0, 1.0, 1.0, 1.0, 2.0, 3.0]
    fifo.reset()
    assert fifo.push(np.array([9.0]))[0] == 9.0
    # the returned command is a copy: the caller may mutate its own array
    fifo = MotorDelay(0.0)
    tau = np.array([1.0])
    got = fifo.push(tau)
    tau[0] = 5.0
    assert got[0] == 1.0
    # a 2 ms delay at a 0.5 ms control period is 4 ticks
    assert MotorDelay(0.002, control_dt=0.0005).ticks == 4


def test_motor_delay_from_settings_and_joint_count():
    fifo = MotorDelay(NonIdealities(motor_delay=0.002), control_dt=0.001, n=3)
    assert fifo.ticks == 2
    out = [fifo.push(np.full(3, k + 1.0)) for k in range(4)]
    np.testing.assert_array_equal(out, [[0, 0, 0], [0, 0, 0], [1, 1, 1], [2, 2, 2]])
    with pytest.raises(ValueError, match="tau"):
        fifo.push(np.zeros(2))
    assert MotorDelay(NonIdealities(enabled=False, motor_delay=0.02)).ticks == 0


def test_saturation():
    effort = np.array([35.0, 35.0, 45.0])
    tau = np.array([50.0, -10.0, -60.0])
    np.testing.assert_array_equal(saturate(tau, effort), [35.0, -10.0, -45.0])
    np.testing.assert_array_equal(saturate(tau, effort, 0.5), [17.5, -10.0, -22.5])
    np.testing.assert_array_equal(saturate(tau, np.inf), tau)
    np.testing.assert_array_equal(NonIdealities(torque_limit_scale=0.5).saturate(tau, effort),
                                  [17.5, -10.0, -22.5])
    with pytest.raises(ValueError):
        saturate(tau, effort, 0.0)


def test_disabled_is_identity():
    cfg = NonIdealities(enabled=False, quat_sigma=0.1, velocity_from_encoder_diff=True,
                        torque_limit_scale=0.1)
    model = SensorModel(cfg, seed=SEED)
    q = np.linspace(-1, 1, 12) + 1e-4
    qd = np.linspace(2, -2, 12)
    for _ in range(3):
        imu, q_meas, qd_meas = model.apply(ideal_imu(), q, qd)
        for key, value in ideal_imu().items():
            np.testing.assert_array_equal(imu[key], value)
        np.testing.assert_array_equal(q_meas, q)
        np.testing.assert_array_equal(qd_meas, qd)
    fifo = MotorDelay.from_settings(cfg)
    assert fifo.ticks == 0
    np.testing.assert_array_equal(fifo.push(np.array([1.0, 2.0])), [1.0, 2.0])
    np.testing.assert_array_equal(cfg.saturate(np.array([100.0]), np.array([35.0])), [100.0])
    # enabled: the default delay is 10 ticks at 1 kHz
    assert MotorDelay.from_settings(NonIdealities()).ticks == 10


@pytest.mark.parametrize("field,value", [("gyro_sigma", -0.1), ("accel_sigma", np.nan),
                                         ("motor_delay", -0.001), ("torque_limit_scale", 0.0),
                                         ("encoder_resolution", np.inf)])
def test_bad_settings_raise(field, value):
    with pytest.raises(ValueError, match=field):
        SensorModel(NonIdealities(**{field: value}))
