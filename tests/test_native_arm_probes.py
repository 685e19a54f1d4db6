"""The native pieces that replaced arm-press's and arm-rrt's per-tick Python: the press adapter's
world force (cpp/sil/press_adapter.hpp) against arm_scene.tip_force_world, and the contact-count
and geom-distance probes (cpp/sil/native_loop.hpp) against arm_scene.contacts_with / min_distance
on the state each tick starts from, on the straight path through arm-rrt's box."""
import numpy as np
import pytest

import kiloloop as kl
from kiloloop import scenarios
from kiloloop.sil import arm_scene, native
from kiloloop.scenarios.arm_controllers import controller
from kiloloop.scenarios.arm_targets import link_capsules
from kiloloop.sil.arm_adapters import JointTracking, Press
from kiloloop.sil.rig import Rig

pytestmark = pytest.mark.skipif(not native.available(), reason="built without the native loop")

arm_rrt = scenarios.get("arm-rrt")
arm_press = scenarios.get("arm-press")


def test_press_adapter_force_and_reference():
    robot = kl.Robot.load("ur5")
    tip = arm_scene.ToolTip(parent=robot.section("chain")["tip"])
    rig = Rig(robot, scene=tip)
    q0 = np.array(scenarios.prepare(arm_press)[1]["q0"])
    plant = rig.plant
    plant.q0 = q0
    plant.reset()
    T0 = kl.Dynamics(rig.model).forward_kinematics(q0)
    settle, slide, slide_time = 0.02, 0.05, 0.1
    press = Press(kl.CartesianImpedanceController(rig.model), tip, T0[:3, 3], T0[:3, :3], 10.0,
                  settle, slide, slide_time)
    addresses = press.extra_measurement(plant)
    assert press.native_adapter().measurement_size == 2 * plant.nq + len(addresses) == 2 * plant.nq + 7
    r = rig.rollout(0.2, press)
    for k in (0, 30, 60, 150):
        r.advance(k - r.ticks_run)
        # The tick reads the state it starts from: the force Python computes from site_xmat now.
        expected = arm_scene.tip_force_world(plant, tip)
        r.advance(1)
        np.testing.assert_allclose(r.last("force"), expected, rtol=1e-12, atol=1e-15)
        assert np.linalg.norm(expected) > 0.0  # the tip's own weight at least
        s = min(max((k * 0.001 - settle) / slide_time, 0.0), 1.0)
        x = T0[0, 3] + slide * (10 * s**3 - 15 * s**4 + 6 * s**5)
        assert r.last("x_ref")[0] == pytest.approx(x, abs=1e-15)
    log = native.signal_log(r)
    assert set(log.names()) >= {"t", "x_ref", "force", "tau", "status", "q"}


def test_contact_and_distance_probes_equal_the_python_functions():
    robot, settings = scenarios.prepare(arm_rrt)
    settings = dict(settings, planner="straight")
    probe = Rig(robot)
    model = probe.model
    capsules = link_capsules(robot, model)
    settings = arm_rrt.derive_targets(robot, model, capsules, probe.plant, settings)
    trajectory, _, _ = arm_rrt.plan(model, capsules, settings, 1)
    T = probe.T_world_root()

    def scene(spec):
        center = T[:3, :3] @ np.asarray(settings["box_center"], float) + T[:3, 3]
        arm_scene.add_box(spec, "obstacle", center, settings["box_half_extents"])

    rig = Rig(robot, scene=scene)
    plant = rig.plant
    q_start = np.asarray(settings["q_start"], float)
    plant.q0 = q_start
    plant.reset()
    box = plant.model.geom("obstacle").id
    links = arm_scene.robot_geoms(plant)
    reference = JointTracking(controller(robot, model, "computed_torque", q_start), trajectory)
    r = rig.rollout(trajectory.end_time, reference,
                    probes=[native.contact_count("box_contacts", [box]),
                            native.geom_distance("box_distance", box, links)])
    seen = 0
    while not r.finished:
        # The probes read the state the tick starts from: Python's functions on it, now.
        contacts = arm_scene.contacts_with(plant, box)
        distance = arm_scene.min_distance(plant, box, links)
        r.advance(1)
        assert r.last("box_contacts")[0] == contacts, r.ticks_run
        assert r.last("box_distance")[0] == distance, r.ticks_run
        seen += contacts > 0
    # The straight path goes through the box: contacts, and links inside it.
    log = native.signal_log(r)
    assert seen > 100 and np.sum(log["box_contacts"] > 0) == seen
    assert log["box_distance"].min() < 0.0
