"""Minimal aerial robot files written at test time: example-robot-data's multirotors (iris, hector,
borinot with its 2-joint arm, hextilt with its 5-joint arm; their URDFs referenced where the
package installed it, not copied; a URDF carries no rotor data, so each rotor table below is typed
from its vendor's simulation model, the source in a comment) and multirotors whose URDFs are
written here (a hexarotor and an octorotor with a 2-joint arm and a body CoM away from the base
origin, a hexarotor with tilted rotors). Only geometry and rotor data are typed in: everything else
is derived by kiloloop.

    python tests/aerial_test_robots.py DIR   writes DIR/iris.toml, DIR/hexa_arm.toml, ...
"""
from __future__ import annotations

import math
import sys
from pathlib import Path


def example_robot_data_share() -> Path:
    """<site-packages>/cmeel.prefix/share (holds example-robot-data/robots/...)."""
    from importlib.metadata import files

    for f in files("example-robot-data") or ():
        parts = f.parts
        if "example-robot-data" in parts and "share" in parts:
            path = Path(f.locate())
            while path.name != "share":
                path = path.parent
            return path
    raise RuntimeError("example-robot-data is not installed")


# PX4 / Gazebo iris (sitl_gazebo models/iris/iris.sdf): motorConstant 5.84e-06 N/(rad/s)^2,
# momentConstant 0.06 m, maxRotVelocity 1100 rad/s -> thrust_max 5.84e-6 * 1100^2 = 7.07 N;
# timeConstantUp 0.0125 s, timeConstantDown 0.025 s (the slower one is typed: one first-order
# lag here). Rotor poses and turning directions as in example-robot-data's iris_simple.urdf
# (rotor_0, rotor_1 counter-clockwise props; rotor_2, rotor_3 clockwise).
IRIS_ROTORS = [((0.13, -0.22, 0.023), 1), ((-0.13, 0.20, 0.023), 1),
               ((0.13, 0.22, 0.023), -1), ((-0.13, -0.20, 0.023), -1)]
IRIS_THRUST_MAX = 5.84e-6 * 1100.0 ** 2   # [N]
IRIS_MOMENT_CONSTANT = 0.06               # [m]
IRIS_TIME_CONSTANT = 0.025                # [s]


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
    d = Path(directory)
    d.mkdir(parents=True, exist_ok=True)
    share = example_robot_data_share()
    urdf = share / "example-robot-data/robots/iris_description/robots/iris_simple.urdf"
    path = d / "iris.toml"
    path.write_text(
        'name = "iris"\nkind = "aerial"\n'
        f'urdf = "{urdf}"\npackage_dirs = ["{share}"]\n\n'
        '[vehicle]\nbase = "iris__base_link"\n\n'
        + _rotor_tables(IRIS_ROTORS, IRIS_THRUST_MAX, IRIS_MOMENT_CONSTANT, IRIS_TIME_CONSTANT))
    return path


def _quat_z(x, y, z, w) -> tuple:
    """The z axis of the rotation (x, y, z, w): a rotor's thrust axis from its frame."""
    n = math.sqrt(x * x + y * y + z * z + w * w)
    x, y, z, w = x / n, y / n, z / n, w / n
    return (round(2 * (x * z + w * y), 9), round(2 * (y * z - w * x), 9),
            round(1 - 2 * (x * x + y * y), 9))


def _write_erd(directory, name, urdf_rel, base, rotors, thrust_max, c, tau, ee=None) -> Path:
    """A robot file on an example-robot-data URDF (referenced, not copied)."""
    d = Path(directory)
    d.mkdir(parents=True, exist_ok=True)
    share = example_robot_data_share()
    path = d / f"{name}.toml"
    path.write_text(
        f'name = "{name}"\nkind = "aerial"\n'
        f'urdf = "{share / "example-robot-data/robots" / urdf_rel}"\n'
        f'package_dirs = ["{share}"]\n\n'
        f'[vehicle]\nbase = "{base}"\n' + (f'ee = "{ee}"\n' if ee else "") + "\n"
        + _rotor_tables(rotors, thrust_max, c, tau))
    return path


# Hector quadrotor (hector_description/quadrotor_base.urdf: the body alone, 1.477 kg). Rotor data
# from eagle-mpc's hector model (PepMS/eagle-mpc config/multirotor/hector.yaml): "+" layout at
# 0.1525 m, max_thrust 5 N, cm / cf = 1e-6 / 6.6e-5 m; its `z` is the spin's sign in eagle-mpc's
# yaw row (+cm/cf), the opposite of ours (a rotor turning counter-clockwise drags the body
# clockwise), so spin = -z. No time constant there: the Gazebo motor plugin's (PX4) 0.025 s.
HECTOR_ROTORS = [((0.1525, 0.0, 0.0), 1), ((0.0, 0.1525, 0.0), -1),
                 ((-0.1525, 0.0, 0.0), 1), ((0.0, -0.1525, 0.0), -1)]
HECTOR_THRUST_MAX = 5.0                   # [N]
HECTOR_MOMENT_CONSTANT = 1e-6 / 6.6e-5    # [m]
HECTOR_TIME_CONSTANT = 0.025              # [s]

# Borinot with flying_arm_2 (borinot_description: 2.647 kg body, CoM 2.4 cm off the base origin
# sideways and 2 cm up, a 2-joint arm of 0.26 kg below). Its URDF has no rotor links; the rotors
# from its source (PepMS/hidro_robots robots/borinot/xacro/definition.urdf.xacro: six rotors at
# 0.185 m, 5 cm above the base origin, cw/ccw alternating; common/xacro/multicopter.xacro's
# Gazebo motor model: motorConstant 3.847e-6 N/(rad/s)^2, maxRotVelocity 2236 rad/s ->
# thrust_max 3.847e-6 * 2236^2 = 19.2 N, momentConstant 0.016894 m, timeConstantUp/Down
# 0.005 s). ccw (Gazebo's turningDirection) is our spin +1.
BORINOT_ROTORS = [((0.0, -0.185, 0.05), -1), ((0.0, 0.185, 0.05), 1),
                  ((0.1602146997, 0.0925, 0.05), -1), ((-0.1602146997, -0.0925, 0.05), 1),
                  ((0.1602146997, -0.0925, 0.05), 1), ((-0.1602146997, 0.0925, 0.05), -1)]
BORINOT_THRUST_MAX = 3.847e-6 * 2236.0 ** 2   # [N]
BORINOT_MOMENT_CONSTANT = 0.016894178436859097  # [m]
BORINOT_TIME_CONSTANT = 0.005                 # [s]

# Hextilt with flying_arm_5 (hextilt_description: a hexarotor with tilted rotors, 1.02 kg body,
# a 5-joint arm of 0.67 kg). Rotors from eagle-mpc (PepMS/eagle-mpc yaml/hextilt/platform/
# hextilt.yaml): translations and orientations (x, y, z, w; the thrust axis is the frame's z),
# max_thrust 10.34 N (1100 rad/s), cm = 1.6e-2 cf (0.016 m); spin = -spin_direction (eagle-mpc's
# yaw row is +cm/cf * spin_direction, see hector). No time constant there: the Gazebo motor
# plugin's (PX4) 0.025 s.
HEXTILT_ROTORS = [(p, -s, _quat_z(*q)) for p, q, s in [
    ((0.3907966465836527, 0.0299377136375720, -0.0427554860579147),
     (0.2995615231515963, 0.0831219092134935, 0.0262082373043233, 0.9500877698156101), -1),
    ((0.2213251438331876, 0.3234709668364263, -0.0427554860579147),
     (-0.3009888436523893, -0.0777950765858490, 0.4523468856138499, 0.8359042631373822), 1),
    ((-0.2213251438331875, 0.3234709668364264, -0.0427554860579147),
     (0.0777950765858490, 0.3009888436523893, 0.8359042631373822, 0.4523468856138501), -1),
    ((-0.3907966465836527, 0.0299377136375721, -0.0427554860579147),
     (-0.0831219092134935, -0.2995615231515963, 0.9500877698156101, 0.0262082373043234), 1),
    ((-0.1694715027504653, -0.3534086804739983, -0.0427554860579147),
     (-0.2217664465657472, 0.2178669344388960, 0.8096960258330590, -0.4977408842017598), -1),
    ((0.1694715027504649, -0.3534086804739985, -0.0427554860579147),
     (-0.2178669344388958, 0.2217664465657473, -0.4977408842017603, 0.8096960258330587), 1)]]
HEXTILT_THRUST_MAX = 10.3437818   # [N]
HEXTILT_MOMENT_CONSTANT = 0.016   # [m]
HEXTILT_TIME_CONSTANT = 0.025     # [s]


def write_hector(directory) -> Path:
    return _write_erd(directory, "hector", "hector_description/robots/quadrotor_base.urdf",
                      "base_link", HECTOR_ROTORS, HECTOR_THRUST_MAX, HECTOR_MOMENT_CONSTANT,
                      HECTOR_TIME_CONSTANT)


def write_borinot(directory) -> Path:
    return _write_erd(directory, "borinot", "borinot_description/urdf/borinot_flying_arm_2.urdf",
                      "borinot__base_link", BORINOT_ROTORS, BORINOT_THRUST_MAX,
                      BORINOT_MOMENT_CONSTANT, BORINOT_TIME_CONSTANT, ee="flying_arm_2__ee")


def write_hextilt(directory) -> Path:
    return _write_erd(directory, "hextilt", "hextilt_description/urdf/hextilt_flying_arm_5.urdf",
                      "hextilt__base_link", HEXTILT_ROTORS, HEXTILT_THRUST_MAX,
                      HEXTILT_MOMENT_CONSTANT, HEXTILT_TIME_CONSTANT, ee="flying_arm_5__gripper")


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
