"""The aerial MuJoCo plant: masses from the URDF, rotors as thrust actuators with the overlay's
first-order lag, drag torque and efficiency, free flight, sensors."""
import numpy as np
import pytest

from kiloloop.sil.aerial_plant import AerialPlant
from kiloloop.sil.aerial_family import load_robot


@pytest.fixture
def plant():
    return AerialPlant.from_robot(load_robot(), damping=0.0, frictionloss=0.0)


def test_masses_and_start_state(plant):
    assert plant.total_mass == pytest.approx(1.8, abs=1e-12)
    assert plant.nq == 3 and plant.joint_names == ["arm_yaw", "arm_shoulder", "arm_elbow"]
    pos, quat = plant.base_pose()
    np.testing.assert_allclose(pos, [0, 0, 1]) and np.testing.assert_allclose(quat, [1, 0, 0, 0])
    np.testing.assert_allclose(plant.rotor_thrust(), 1.8 * 9.81 / 4)  # starts in hover
    np.testing.assert_allclose(plant.imu()["accel"], [0, 0, 9.81], atol=1e-9)


def test_hover_thrust_holds_the_vehicle(plant):
    plant.set_thrust(np.full(4, 1.8 * 9.81 / 4))
    plant.set_torque(np.zeros(3))
    plant.step(500)
    pos, _ = plant.base_pose()
    assert np.linalg.norm(pos - [0, 0, 1]) < 1e-9


def test_rotor_lag_is_first_order_with_the_overlay_time_constant(plant):
    f0 = 1.8 * 9.81 / 4
    plant.set_thrust(np.full(4, f0 + 2.0))
    plant.step(30)  # one time constant (30 ms)
    rise = (plant.rotor_thrust() - f0) / 2.0
    np.testing.assert_allclose(rise, 1 - np.exp(-1), atol=0.01)


def test_drag_torque_and_efficiency(plant):
    f0 = 1.8 * 9.81 / 4
    fast = AerialPlant.from_robot(load_robot(), damping=0.0, frictionloss=0.0, motor_lag=False)
    # Clockwise rotors (spin -1: 0 and 3) up, counter-clockwise down: their drag yaws the body
    # counter-clockwise, a pure yaw torque 4 * 0.016 * 0.5 N m.
    fast.set_thrust(f0 + np.array([0.5, -0.5, -0.5, 0.5]))
    fast.step(1)
    _, omega = fast.base_velocity()
    yaw_acc = omega[2] / fast.timestep
    assert yaw_acc > 0
    # Against M^-1 tau for a pure yaw torque 4 * 0.016 * 0.5 N m (MuJoCo's own mass matrix: the
    # arm's free yaw joint makes this more than 1 / J_zz of the body).
    import mujoco
    M = np.zeros((fast.model.nv, fast.model.nv))
    mujoco.mj_fullM(fast.model, fast.data, M)
    tau = np.zeros(fast.model.nv)
    tau[fast._free_d + 5] = 4 * 0.016 * 0.5
    assert yaw_acc == pytest.approx(np.linalg.solve(M, tau)[fast._free_d + 5], rel=0.02)
    plant.set_efficiency(0, 0.7)
    plant.set_thrust(np.full(4, f0))
    plant.step(300)
    np.testing.assert_allclose(plant.rotor_thrust()[0], 0.7 * f0, rtol=1e-3)
