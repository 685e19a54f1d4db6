"""example-robot-data's UR10 (ur_description, base_link -> tool0) from the minimal robot file of
the robots-as-data issue: the five arm scenarios meet their criteria with targets derived from
the robot, and the closed-form IK is used on it."""
import pytest

import kiloloop as kl
from kiloloop import scenarios

from robot_files import erd_urdf, minimal_arm


@pytest.fixture(scope="module")
def ur10(tmp_path_factory):
    return minimal_arm(tmp_path_factory.mktemp("ur10"),
                       erd_urdf("ur_description/urdf/ur10_robot.urdf"), "base_link", "tool0",
                       "ur10")


@pytest.mark.parametrize("name", ["arm-track", "arm-line", "arm-rrt", "arm-press", "arm-estop"])
def test_arm_scenario_passes_on_the_ur10(ur10, name):
    r = scenarios.run_named(name, ur10)
    failed = {k: c for k, c in r.criteria.items() if not c["passed"]}
    assert not failed, failed
    assert r.metrics.get("failed_ticks", 0) == 0


def test_the_ur10_uses_the_closed_form_ik(ur10):
    ik = kl.ArmIk(kl.Robot.load(ur10).model())
    assert ik.solver() == "ur_analytic", ik.analytic_reason()


def test_the_derived_box_blocks_the_ur10s_straight_path(ur10):
    straight = scenarios.run_named("arm-rrt", ur10, {"planner": "straight"})
    assert straight.metrics["box_contact_ticks"] > 0 and not straight.passed
