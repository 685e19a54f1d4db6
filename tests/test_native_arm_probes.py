"""The native pieces that replaced arm-press's and arm-rrt's per-tick Python: the press adapter's
world force (cpp/sil/press_adapter.hpp) against arm_scene.tip_force_world, and the contact-count
and geom-distance probes (cpp/sil/native_loop.hpp) against arm_scene.contacts_with / min_distance
called per tick by the Python loop, on the straight path through arm-rrt's box."""
import numpy as np
import pytest

import kiloloop as kl
from kiloloop import scenarios
from kiloloop.sil import arm_scene, native
from kiloloop.sil.arm_adapters import JointTrackingTick
from kiloloop.sil.arm_rig import ArmRig, controller, link_capsules
from kiloloop.sil.log import SignalLog

pytestmark = pytest.mark.skipif(not native.available(), reason="built without the native loop")

arm_rrt = scenarios.get("arm-rrt")
arm_press = scenarios.get("arm-press")


def test_press_adapter_force_and_reference():
    robot = kl.Robot.load("ur5")
    tip = arm_scene.ToolTip(parent=robot.section("chain")["tip"])
    rig = ArmRig(robot, scene=tip)
    q0 = np.array(scenarios.prepare(arm_press)[1]["q0"])
    plant = rig.plant
    plant.q0 = q0
    plant.reset()
    T0 = kl.Dynamics(rig.model).forward_kinematics(q0)
    settle, slide, slide_time = 0.02, 0.05, 0.1
    adapter = native.press_adapter(kl.CartesianImpedanceController(rig.model), T0[:3, 3], T0[:3, :3],
                                   10.0, settle, slide, slide_time)
    addresses = tip.measurement_addresses(plant.model)
    assert adapter.measurement_size == 2 * plant.nq + len(addresses) == 2 * plant.nq + 7
    r = native.rollout(plant, adapter, 0.2, extra_measurement=addresses)
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


def _straight_rrt_run(native_loop: bool):
    robot, settings = scenarios.prepare(arm_rrt)
    settings = dict(settings, planner="straight")
    probe = ArmRig(robot)
    model = probe.model
    capsules = link_capsules(robot, model)
    settings = arm_rrt.derive_targets(robot, model, capsules, probe.plant, settings)
    trajectory, _, _ = arm_rrt.plan(model, capsules, settings, 1)
    T = probe.T_world_root()

    def scene(spec):
        center = T[:3, :3] @ np.asarray(settings["box_center"], float) + T[:3, 3]
        arm_scene.add_box(spec, "obstacle", center, settings["box_half_extents"])

    rig = ArmRig(robot, scene=scene)
    plant = rig.plant
    q_start = np.asarray(settings["q_start"], float)
    plant.q0 = q_start
    plant.reset()
    box = plant.model.geom("obstacle").id
    links = arm_scene.robot_geoms(plant)
    tick = JointTrackingTick(controller(robot, model, "computed_torque", q_start), trajectory)
    duration = trajectory.end_time
    if native_loop:
        return native.run(plant, tick.native_adapter(), duration, observe=native.Observe("q_true"),
                          probes=[native.contact_count("box_contacts", [box]),
                                  native.geom_distance("box_distance", box, links)])

    def observe(p, log: SignalLog) -> None:
        log.record("q_true", p.q())
        log.record("box_contacts", arm_scene.contacts_with(p, box))
        log.record("box_distance", arm_scene.min_distance(p, box, links))

    return rig.run(tick, duration, observe=observe, native=False)


def test_contact_and_distance_probes_equal_the_python_observe():
    a, b = _straight_rrt_run(True), _straight_rrt_run(False)
    for name in ("q_true", "box_contacts", "box_distance", "tau"):
        assert a[name].shape == b[name].shape, name
        assert np.array_equal(a[name], b[name]), f"{name}: max diff {np.abs(a[name] - b[name]).max()}"
    # The straight path goes through the box: contacts, and links inside it.
    assert np.sum(a["box_contacts"] > 0) > 100
    assert a["box_distance"].min() < 0.0
