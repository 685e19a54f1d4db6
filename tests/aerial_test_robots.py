"""Minimal aerial robot files written at test time: example-robot-data's multirotors (iris, hector,
borinot with its 2-joint arm, hextilt with its arm cut after the third joint), as the zoo writes
them (python/kiloloop/bench/zoo_robots.py: their URDFs referenced where the package installed
them; a URDF carries no rotor data, so each rotor table there is typed from its vendor's
simulation model, the source in a comment), and multirotors whose URDFs are written here (a
hexarotor and an octorotor with a 2-joint arm and a body CoM away from the base origin, a hexarotor
with tilted rotors). Only geometry and rotor data are typed in: everything else is derived by
kiloloop.

    python tests/aerial_test_robots.py DIR   writes DIR/iris.toml, DIR/hexa_arm.toml, ...
"""
from __future__ import annotations

import math
import sys
from pathlib import Path

from kiloloop.bench import zoo_robots


# example-robot-data's iris: the zoo's robot file (python/kiloloop/bench/zoo_robots.py: PX4
# rotor data, rotor positions from the URDF's rotor links), the one table of real robots.
IRIS_THRUST_MAX = zoo_robots.IRIS_THRUST_MAX   # [N]


def _rotor_tables(rotors, thrust_max, c, tau) -> str:
    out = []
    for (p, spin, *axis) in rotors:
        out.append("[[rotors]]\n"
                   f"position = [{p[0]!r}, {p[1]!r}, {p[2]!r}]\n"
                   + (f"axis = [{axis[0][0]!r}, {axis[0][1]!r}, {axis[0][2]!r}]\n" if axis else "")
                   + f"spin = {spin}\nthrust_max = {thrust_max!r}\n"
                   f"torque_coefficient = {c!r}\ntime_constant = {tau!r}\n")
    return "\n".join(out)


def write_iris(directory) -> Path:
    path = zoo_robots.robot_file("iris", directory)
    if path is None:
        raise RuntimeError("example-robot-data is not installed")
    return path


def _zoo_file(name: str, directory) -> Path:
    path = zoo_robots.robot_file(name, directory)
    if path is None:
        raise RuntimeError("example-robot-data is not installed")
    return path


# example-robot-data's other multirotors, as the zoo writes them (python/kiloloop/bench/
# zoo_robots.py: rotor data typed from their sources, each named there): hector (thrust/weight
# 1.38, no arm), borinot (a hexarotor with a 2-joint arm, its CoM off the base origin), hextilt
# (tilted rotors, its 5-joint arm cut after the third joint).
def write_hector(directory) -> Path:
    return _zoo_file("hector", directory)


def write_borinot(directory) -> Path:
    return _zoo_file("borinot", directory)


def write_hextilt(directory) -> Path:
    return _zoo_file("hextilt", directory)


def multirotor_urdf(n_rotors: int, arm_joints: int, com=(0.0, 0.0, 0.0), radius=0.3,
                    body_mass=1.6) -> str:
    """A multirotor body (mass, CoM at `com`) with rotor arms as fixed links (their mass part of
    the body) and an arm of `arm_joints` pitch/roll joints below, ending at ee_link."""
    cx, cy, cz = com
    links = [f"""<link name="base_link"><inertial><origin xyz="{cx} {cy} {cz}"/>
      <mass value="{body_mass}"/><inertia ixx="0.02" ixy="0" ixz="0" iyy="0.022" iyz="0" izz="0.04"/>
      </inertial><collision><geometry><box size="0.25 0.25 0.08"/></geometry></collision></link>"""]
    for i in range(n_rotors):
        a = 2 * math.pi * (i + 0.5) / n_rotors
        x, y = radius * math.cos(a), radius * math.sin(a)
        links.append(f"""<joint name="motor{i}_mount" type="fixed"><parent link="base_link"/>
      <child link="motor{i}"/><origin xyz="{x:.6f} {y:.6f} 0.02"/></joint>
      <link name="motor{i}"><inertial><mass value="0.05"/>
      <inertia ixx="1e-5" ixy="0" ixz="0" iyy="1e-5" iyz="0" izz="1e-5"/></inertial>
      <collision><geometry><cylinder radius="0.12" length="0.01"/></geometry></collision></link>""")
    parent = "base_link"
    for j in range(arm_joints):
        link = f"arm_link{j + 1}"
        axis = "0 1 0" if j % 2 == 0 else "1 0 0"
        origin = "0.05 0.02 -0.06" if j == 0 else "0 0 -0.16"
        links.append(f"""<joint name="arm_joint{j + 1}" type="revolute"><parent link="{parent}"/>
      <child link="{link}"/><origin xyz="{origin}"/><axis xyz="{axis}"/>
      <limit lower="-2.0" upper="2.0" velocity="6" effort="3"/></joint>
      <link name="{link}"><inertial><origin xyz="0 0 -0.08"/><mass value="0.12"/>
      <inertia ixx="2.7e-4" ixy="0" ixz="0" iyy="2.7e-4" iyz="0" izz="1.5e-5"/></inertial>
      <collision><origin xyz="0 0 -0.08"/><geometry><cylinder radius="0.012" length="0.16"/>
      </geometry></collision></link>""")
        parent = link
    if arm_joints:
        links.append(f"""<joint name="ee_fixed" type="fixed"><parent link="{parent}"/>
      <child link="ee_link"/><origin xyz="0 0 -0.16"/></joint>
      <link name="ee_link"><inertial><mass value="0.03"/>
      <inertia ixx="5e-6" ixy="0" ixz="0" iyy="5e-6" iyz="0" izz="5e-6"/></inertial></link>""")
    return '<?xml version="1.0"?>\n<robot name="test_multirotor">\n' + "\n".join(links) + \
        "\n</robot>\n"


def write_multirotor(directory, name, n_rotors, arm_joints, com=(0.0, 0.0, 0.0), tilt_deg=0.0,
                     radius=0.3, thrust_max=9.0, torque_coefficient=0.016,
                     time_constant=0.03) -> Path:
    """URDF + robot file; tilt_deg tilts rotor axes alternately about their radial direction."""
    d = Path(directory)
    d.mkdir(parents=True, exist_ok=True)
    (d / f"{name}.urdf").write_text(multirotor_urdf(n_rotors, arm_joints, com, radius))
    rotors = []
    for i in range(n_rotors):
        a = 2 * math.pi * (i + 0.5) / n_rotors
        p = (round(radius * math.cos(a), 6), round(radius * math.sin(a), 6), 0.02)
        spin = 1 if i % 2 else -1
        if tilt_deg:
            t = math.radians(tilt_deg) * (1 if i % 2 else -1)
            # Rotate +z by t about the radial direction (cos a, sin a, 0).
            axis = (round(math.sin(t) * math.sin(a), 9), round(-math.sin(t) * math.cos(a), 9),
                    round(math.cos(t), 9))
            rotors.append((p, spin, axis))
        else:
            rotors.append((p, spin))
    text = (f'name = "{name}"\nkind = "aerial"\nurdf = "{name}.urdf"\n\n[vehicle]\n'
            'base = "base_link"\n' + ('ee = "ee_link"\n' if arm_joints else "") + "\n"
            + _rotor_tables(rotors, thrust_max, torque_coefficient, time_constant))
    path = d / f"{name}.toml"
    path.write_text(text)
    return path


def run_passing(name, robot, duration=None, **overrides):
    """Runs scenario `name` on `robot` (overrides as --set strings), prints its metrics, asserts it
    passed naming the failed criteria; returns the result."""
    import json

    from kiloloop import scenarios

    r = scenarios.run_named(name, robot, {k: str(v) for k, v in overrides.items()},
                            duration=duration)
    print(robot.name, name, json.dumps(r.metrics))
    failed = {k: c["value"] for k, c in r.criteria.items() if not c["passed"]}
    assert r.passed, f"{robot.name} {name}: {failed}"
    return r


def write_all(directory) -> dict:
    return {
        "iris": write_iris(directory),
        "hector": write_hector(directory),
        "borinot": write_borinot(directory),
        "hextilt": write_hextilt(directory),
        "hexa_arm": write_multirotor(directory, "hexa_arm", 6, 2, com=(0.03, -0.02, 0.01)),
        "octo_arm": write_multirotor(directory, "octo_arm", 8, 2, com=(-0.025, 0.03, -0.01),
                                     thrust_max=7.0),
        "hexa_tilt": write_multirotor(directory, "hexa_tilt", 6, 2, com=(0.0, 0.0, 0.015),
                                      tilt_deg=20.0),
    }


if __name__ == "__main__":
    for name, path in write_all(sys.argv[1] if len(sys.argv) > 1 else ".").items():
        print(f"{name}: {path}")
