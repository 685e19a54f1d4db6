"""Where a native rollout given its own MjData starts (native.start_state): a new or reset MjData
starts at the plant's state, as the plant's own data would; a data set up and forwarded by the
caller keeps its state."""
import mujoco
import numpy as np
import pytest

import kiloloop as kl
from kiloloop.robot import Robot
from kiloloop.sil import batch, native
from kiloloop.scenarios.arm_controllers import controller
from kiloloop.sil.arm_adapters import JointTracking
from kiloloop.sil.rig import Rig

pytestmark = pytest.mark.skipif(not native.available(), reason="built without the native loop")

DURATION = 0.05  # [s]


@pytest.fixture(scope="module")
def ur5():
    robot = Robot.load("ur5")
    return robot, Rig(robot)


def make(ur5, data):
    """A rollout holding the start pose (a constant quintic) with its own controller."""
    robot, rig = ur5
    q0 = rig.plant.q0
    traj = kl.QuinticTrajectory(np.array([q0, q0]), np.array([0.0, 1.0]))
    reference = JointTracking(controller(robot, rig.model, "computed_torque", q0), traj)
    return rig.rollout(DURATION, reference, data=data)


def test_a_new_mjdata_starts_where_the_plant_is(ur5):
    _, rig = ur5
    assert np.abs(rig.plant.q0 - rig.plant.model.qpos0[rig.plant.qpos_addresses]).max() > 1.0
    copied = mujoco.MjData(rig.plant.model)
    mujoco.mj_copyData(copied, rig.plant.model, rig.plant.data)
    reset = mujoco.MjData(rig.plant.model)
    mujoco.mj_forward(rig.plant.model, reset)
    mujoco.mj_resetData(rig.plant.model, reset)
    rollouts = batch.run([make(ur5, None), make(ur5, copied),
                          make(ur5, mujoco.MjData(rig.plant.model)), make(ur5, reset)], threads=2)
    own, reference = rollouts[0].log(), rollouts[1].log()
    assert np.allclose(reference["q"][0], rig.plant.q0, atol=1e-12)
    for r in rollouts[1:]:  # the same run as on the plant's own data, bit for bit
        assert r.ok and r.warnings == 0
        for name in own:
            assert np.array_equal(r.log()[name], own[name]), name


def test_a_data_the_caller_set_keeps_its_state(ur5):
    _, rig = ur5
    data = mujoco.MjData(rig.plant.model)
    mujoco.mj_copyData(data, rig.plant.model, rig.plant.data)
    q = rig.plant.q0 + 0.05
    data.qpos[rig.plant.qpos_addresses] = q
    mujoco.mj_forward(rig.plant.model, data)
    assert native.start_state(rig.plant, data) is data
    r = make(ur5, data)
    r.run()
    assert r.ok
    assert np.allclose(r.log()["q"][0], q, atol=1e-12)  # the first measurement: its own pose
    assert not np.allclose(rig.plant.q(), q)             # the plant's data untouched
