"""A user's repository outside the kiloloop tree, as issue 30's acceptance describes it: robot
files for example-robot-data's UR10, Go1 and iris (minimal: nothing tuned) and one scenario file
each (arm joint waypoints; a quadruped velocity profile with a push; aerial position setpoints
with a rotor fault). Written at test time: the URDFs' paths depend on where the wheel put them."""
from __future__ import annotations

from pathlib import Path

from aerial_test_robots import write_iris
from quadruped_robots import go1_robot_file
from robot_files import erd_urdf, minimal_arm

UR10_MISSION = '''name = "ur10_waypoints"
robot = "robots/ur10.toml"
duration = 5.0
[reference]
joint = { t = [0.0, 1.5, 3.5], q = [[0.0, -1.6, 1.6, -1.6, -1.6, 0.0], [0.5, -1.2, 1.2, -1.4, -1.4, 0.3], [-0.3, -1.8, 1.9, -1.7, -1.6, -0.2]] }
[criteria]
"max(joint_error)" = "< 0.001"
"max(ee_error)" = "< 0.002"
"final(joint_error)" = "< 1e-4"
'''
GO1_MISSION = '''name = "go1_walk_and_push"
robot = "robots/go1.toml"
duration = 6.0
seed = 2
[reference]
velocity = { t = [0, 1, 6], vx = [0, 0.4, 0.4] }
[[events]]
t = 3.0
kind = "push"
impulse = [0.0, 2.0, 0.0]
[criteria]
"max(fell)" = "< 0.5"
"rms(roll, 1.0)" = "< 3.0"
"rms(pitch, 1.0)" = "< 3.0"
"rms(velocity_error, 2.0, 2.9)" = "< 0.1"
"final(height)" = "> 0.15"
'''
IRIS_MISSION = '''name = "iris_setpoints_rotor_fault"
robot = "robots/iris.toml"
duration = 7.0
[reference]
position = { t = [0, 1, 3], xyz = [[0, 0, 1], [0, 0, 1], [0.5, 0, 1.2]] }
[[events]]
t = 4.0
kind = "rotor_fault"
rotor = 0
efficiency = 0.85
[criteria]
"max(diverged)" = "< 0.5"
"max(position_error, 6.0)" = "< 0.05"
"rms(attitude_error, 1.0)" = "< 5.0"
'''


def write(repo: Path) -> dict[str, Path]:
    """The repository: robots/ and three test_*.toml scenario files; name -> scenario path."""
    robots = repo / "robots"
    robots.mkdir(parents=True, exist_ok=True)
    minimal_arm(robots, erd_urdf("ur_description/urdf/ur10_robot.urdf"), "base_link", "tool0",
                "ur10")
    go1_robot_file(robots)
    write_iris(robots)
    out = {}
    for name, text in (("ur10", UR10_MISSION), ("go1", GO1_MISSION), ("iris", IRIS_MISSION)):
        out[name] = repo / f"test_{name}.toml"
        out[name].write_text(text)
    return out
