"""The zoo's robots: every robot of the three families in example-robot-data, each as the minimal
robot file a new user writes (name, kind, urdf, package_dirs and the family's naming table:
[chain] root and tip, [legs] base and feet, [vehicle] base and ee; an aerial file adds its
[[rotors]], which no URDF carries). Nothing here is tuned per robot: the names are the URDFs' own,
the rotor data are the vendors' or their simulation models' (source named beside each).

One table for every harness that runs real robots: `make zoo` (bench/zoo.py), `make robot-matrix`
(scripts/robot_matrix.py), `make quadruped-robots` (bench/quadruped_robots.py) and the tests.

Left out of example-robot-data (not one of the three families as kiloloop defines them, or no
single chain of a fixed-base arm): humanoids and bipeds (talos, romeo, icub, g1, cassie, bolt,
simple_humanoid, human, alex*), hands (allegro, finger_edu), pr2 and centauro (mobile
manipulators with a torso), asr_twodof and double_pendulum (2-DoF, below an arm's 6), solo (8-DoF
solo: no abduction joints, not an abduction / hip / knee leg), quadruped_description (a 3-DoF
test leg), tiago (its arm sits on a prismatic torso lift: as a chain from the torso link the
lift is locked, see ARMS below). What is included and why: the comment of each table.
"""
from __future__ import annotations

import math
import sys
import sysconfig
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field
from pathlib import Path


@dataclass(frozen=True)
class Rotor:
    """One rotor as an aerial robot file's [[rotors]] table has it (docs/robots.md): position [m]
    in the base link frame, or `link`, the URDF's rotor link (a fixed child of the base whose
    joint origin is the rotor's position); thrust axis (unit, base frame); spin +1 counter-clockwise
    about the axis (drag torque along -axis); thrust_max [N]; torque_coefficient [m] (drag torque
    per N of thrust); time_constant [s] (first-order motor lag; None where the source gives
    none: the plant then has no lag and the gains assume robot/aerial.py's default)."""
    spin: int
    thrust_max: float
    torque_coefficient: float
    position: tuple[float, float, float] | None = None
    link: str | None = None
    axis: tuple[float, float, float] | None = None
    time_constant: float | None = None


@dataclass(frozen=True)
class ZooRobot:
    """One robot of the zoo: its URDF under example-robot-data/robots and its family's naming
    table (the only per-robot data a minimal file holds besides rotors)."""
    name: str
    kind: str                       # arm | quadruped | aerial
    urdf: str                       # path under example-robot-data/robots
    table: dict                     # {"chain": {...}} | {"legs": {...}} | {"vehicle": {...}}
    rotors: tuple[Rotor, ...] = field(default_factory=tuple)


def _arm(name, urdf, root, tip):
    return ZooRobot(name, "arm", urdf, {"chain": {"root": root, "tip": tip}})


def _quadruped(name, urdf, base, feet):
    return ZooRobot(name, "quadruped", urdf, {"legs": {"base": base, "feet": list(feet)}})


# Arms: a fixed-base serial chain of 5-7 revolute joints, root -> tip as the URDF names them.
# The seven of scripts/robot_matrix.py, plus kinova (Jaco 2, 6-DoF, continuous joints 1, 4, 6
# with +-2 pi limits), baxter's left arm (7-DoF; its torso, head and right arm off the chain:
# locked and folded in as rigid mass), tiago's arm (7-DoF from torso_lift_link: the torso lift,
# head, wheels locked). tiago_pro's arms: the same as tiago's (one is enough; 2x the run time).
_UNITREE_FEET = ("FL_foot", "FR_foot", "RL_foot", "RR_foot")
ARMS = [
    _arm("ur3", "ur_description/urdf/ur3_robot.urdf", "base_link", "tool0"),
    _arm("ur5", "ur_description/urdf/ur5_robot.urdf", "base_link", "tool0"),
    _arm("ur10", "ur_description/urdf/ur10_robot.urdf", "base_link", "tool0"),
    _arm("panda", "panda_description/urdf/panda.urdf", "panda_link0", "panda_link8"),
    _arm("xarm7", "xarm_description/urdf/xarm7.urdf", "link_base", "link7"),
    _arm("z1", "z1_description/urdf/z1.urdf", "link00", "link06"),
    _arm("so100", "so_arm_description/urdf/so100.urdf", "base", "gripper"),
    _arm("kinova", "kinova_description/robots/kinova.urdf", "j2s6s200_link_base",
         "j2s6s200_end_effector"),
    _arm("baxter_left", "baxter_description/urdf/baxter.urdf", "left_arm_mount", "left_gripper"),
    _arm("tiago_arm", "tiago_description/robots/tiago_no_hand.urdf", "torso_lift_link",
         "arm_tool_link"),
]

# Quadrupeds: every 12-DoF abduction / hip / knee quadruped (base link and feet FL FR RL RR).
QUADRUPEDS = [
    _quadruped("a1", "a1_description/urdf/a1.urdf", "trunk", _UNITREE_FEET),
    _quadruped("go1", "go1_description/urdf/go1.urdf", "trunk", _UNITREE_FEET),
    _quadruped("go2", "go2_description/urdf/go2.urdf", "base", _UNITREE_FEET),
    _quadruped("b1", "b1_description/urdf/b1.urdf", "trunk", _UNITREE_FEET),
    _quadruped("laikago", "laikago_description/urdf/laikago.urdf", "trunk", _UNITREE_FEET),
    _quadruped("solo12", "solo_description/robots/solo12.urdf", "base_link",
               ("FL_FOOT", "FR_FOOT", "HL_FOOT", "HR_FOOT")),
    _quadruped("anymal_b", "anymal_b_simple_description/robots/anymal.urdf", "base",
               ("LF_FOOT", "RF_FOOT", "LH_FOOT", "RH_FOOT")),
    _quadruped("anymal_c", "anymal_c_simple_description/urdf/anymal.urdf", "base",
               ("LF_FOOT", "RF_FOOT", "LH_FOOT", "RH_FOOT")),
    _quadruped("hyq", "hyq_description/robots/hyq_no_sensors.urdf", "trunk",
               ("lf_foot", "rf_foot", "lh_foot", "rh_foot")),
]

# --- Multirotors: rotor data typed from their sources (URDFs carry no rotors). ---

# PX4 / Gazebo iris (sitl_gazebo models/iris/iris.sdf): motorConstant 5.84e-06 N/(rad/s)^2,
# momentConstant 0.06 m, maxRotVelocity 1100 rad/s -> thrust_max 5.84e-6 * 1100^2 = 7.07 N;
# timeConstantUp 0.0125 s, timeConstantDown 0.025 s (the slower one is typed: one first-order
# lag here). Rotor poses: the URDF's rotor links (iris_simple.urdf: iris__rotor_0..3, fixed
# children of iris__base_link); turning directions as in iris.sdf (rotor_0, rotor_1
# counter-clockwise props; rotor_2, rotor_3 clockwise).
IRIS_THRUST_MAX = 5.84e-6 * 1100.0 ** 2   # [N]
IRIS_MOMENT_CONSTANT = 0.06               # [m]
IRIS_TIME_CONSTANT = 0.025                # [s]
IRIS_ROTORS = tuple(Rotor(spin, IRIS_THRUST_MAX, IRIS_MOMENT_CONSTANT, link=f"iris__rotor_{i}",
                          time_constant=IRIS_TIME_CONSTANT)
                    for i, spin in enumerate((1, 1, -1, -1)))

# Hector quadrotor (hector_quadrotor, as crocoddyl's examples/quadrotor.py and eagle-mpc's
# config/multirotor/hector.yaml use it): plus configuration, rotors d_cog = 0.1525 m out on +x,
# +y, -x, -y; cf 6.6e-5, cm 1e-6 -> drag torque per thrust cm / cf = 0.01515 m; max_thrust 5 N
# per rotor. Yaw torques (crocoddyl's tau_f row) -c, +c, -c, +c: spin +1, -1, +1, -1. No motor
# time constant in either source (time_constant omitted).
_HECTOR_D = 0.1525   # [m]
HECTOR_ROTORS = tuple(Rotor(spin, 5.0, 1e-6 / 6.6e-5, position=p) for p, spin in (
    ((_HECTOR_D, 0.0, 0.0), 1), ((0.0, _HECTOR_D, 0.0), -1),
    ((-_HECTOR_D, 0.0, 0.0), 1), ((0.0, -_HECTOR_D, 0.0), -1)))


def _axis_of(quaternion_xyzw) -> tuple[float, float, float]:
    """The z axis of a rotor frame given as a quaternion (x, y, z, w): its thrust direction."""
    x, y, z, w = quaternion_xyzw
    n = math.sqrt(x * x + y * y + z * z + w * w)
    x, y, z, w = x / n, y / n, z / n, w / n
    return (round(2 * (x * z + w * y), 12), round(2 * (y * z - w * x), 12),
            round(1 - 2 * (x * x + y * y), 12))


# Hextilt (eagle-mpc, yaml/hextilt/platform/hextilt.yaml, the platform of example-robot-data's
# hextilt_flying_arm_5): six tilted rotors, poses (translation, orientation x y z w) in
# hextilt__base_link; cf 8.54858e-06, cm 1.3677728e-7 (cm / cf = 0.016 m, the Gazebo plugin's
# moment constant); max_thrust 10.3437818 N (1100 rad/s). eagle-mpc's yaw torque is
# spin_direction * cm / cf along the thrust axis, kiloloop's spin +1 is -c along it: spin = -
# spin_direction. No motor time constant in the source.
_HEXTILT = (
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
     (-0.2178669344388958, 0.2217664465657473, -0.4977408842017603, 0.8096960258330587), 1),
)
HEXTILT_ROTORS = tuple(Rotor(-spin_direction, 10.3437818, 1.3677728e-7 / 8.54858e-06,
                             position=p, axis=_axis_of(q)) for p, q, spin_direction in _HEXTILT)

# Borinot (hidro_robots, robots/borinot/xacro/definition.urdf.xacro and
# robots/common/xacro/multicopter.xacro, upstream of example-robot-data's borinot_flying_arm_2):
# six rotors at z = 0.05 m in borinot__base_link, cw / ccw as listed there (ccw: spin +1); the
# Gazebo motor model's motorConstant 3.847e-6 N/(rad/s)^2 and maxRotVelocity 2236 rad/s ->
# thrust_max 3.847e-6 * 2236^2 = 19.23 N; momentConstant 0.016894178436859097 m;
# timeConstantUp = timeConstantDown = 0.005 s.
_BORINOT_THRUST_MAX = 3.847e-6 * 2236.0 ** 2   # [N]
BORINOT_ROTORS = tuple(
    Rotor(spin, _BORINOT_THRUST_MAX, 0.016894178436859097, position=p, time_constant=0.005)
    for p, spin in (((0.0, -0.185, 0.05), -1), ((0.0, 0.185, 0.05), 1),
                    ((0.1602146997, 0.0925, 0.05), -1), ((-0.1602146997, -0.0925, 0.05), 1),
                    ((0.1602146997, -0.0925, 0.05), 1), ((-0.1602146997, 0.0925, 0.05), -1)))

# Multirotors with 0-3 arm joints. hextilt_flying_arm_5's arm has 5 joints: beyond the family's
# size class, its arm is cut after the third joint (ee = flying_arm_5__link_3: the two wrist
# joints off the chain are locked and folded in as rigid mass, as an arm's are).
AERIAL = [
    ZooRobot("iris", "aerial", "iris_description/robots/iris_simple.urdf",
             {"vehicle": {"base": "iris__base_link"}}, IRIS_ROTORS),
    ZooRobot("hector", "aerial", "hector_description/robots/quadrotor_base.urdf",
             {"vehicle": {"base": "base_link"}}, HECTOR_ROTORS),
    ZooRobot("hextilt", "aerial", "hextilt_description/urdf/hextilt_flying_arm_5.urdf",
             {"vehicle": {"base": "hextilt__base_link", "ee": "flying_arm_5__link_3"}},
             HEXTILT_ROTORS),
    ZooRobot("borinot", "aerial", "borinot_description/urdf/borinot_flying_arm_2.urdf",
             {"vehicle": {"base": "borinot__base_link", "ee": "flying_arm_2__ee"}},
             BORINOT_ROTORS),
]

ROBOTS: dict[str, ZooRobot] = {r.name: r for r in ARMS + QUADRUPEDS + AERIAL}


def names(kind: str | None = None) -> list[str]:
    """The zoo's robot names, of one kind (arm, quadruped, aerial) or all."""
    return [n for n, r in ROBOTS.items() if kind is None or r.kind == kind]


def erd_share() -> Path | None:
    """The directory package://example-robot-data/... resolves against (the wheel installs its
    robots under site-packages/cmeel.prefix/share/), or None when it is not installed."""
    bases = [Path(sysconfig.get_paths()["purelib"]), *map(Path, sys.path), Path(sys.prefix)]
    for base in bases:
        share = base / "cmeel.prefix" / "share"
        if (share / "example-robot-data" / "robots").is_dir():
            return share
    return None


def urdf_path(name: str, share: Path | None = None) -> Path:
    share = share or erd_share()
    if share is None:
        raise FileNotFoundError("example-robot-data is not installed")
    return share / "example-robot-data" / "robots" / ROBOTS[name].urdf


def _toml(value) -> str:
    if isinstance(value, str):
        return '"' + value.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_toml(v) for v in value) + "]"
    return repr(value)


def _link_position(urdf: Path, base: str, link: str) -> tuple[float, float, float]:
    """[m] the origin of `link` in `base`: the xyz of the fixed joint joining them."""
    for joint in ET.parse(urdf).getroot().iter("joint"):
        parent, child = joint.find("parent"), joint.find("child")
        if child is not None and child.get("link") == link:
            if parent is None or parent.get("link") != base:
                raise ValueError(f"{urdf}: rotor link {link} is not a child of {base}")
            origin = joint.find("origin")
            xyz = (origin.get("xyz") if origin is not None else None) or "0 0 0"
            return tuple(float(v) for v in xyz.split())
    raise ValueError(f"{urdf}: no joint has the rotor link {link} as its child")


def rotor_tables(robot: ZooRobot, urdf: Path) -> str:
    """The [[rotors]] tables of an aerial robot file (positions of rotor links read from urdf)."""
    base = robot.table["vehicle"]["base"]
    out = []
    for r in robot.rotors:
        position = r.position if r.link is None else _link_position(urdf, base, r.link)
        lines = [f"position = {_toml(list(position))}"]
        if r.axis is not None:
            lines.append(f"axis = {_toml(list(r.axis))}")
        lines += [f"spin = {r.spin}", f"thrust_max = {r.thrust_max!r}",
                  f"torque_coefficient = {r.torque_coefficient!r}"]
        if r.time_constant is not None:
            lines.append(f"time_constant = {r.time_constant!r}")
        out.append("[[rotors]]\n" + "\n".join(lines) + "\n")
    return "\n".join(out)


def robot_text(name: str, share: Path | None = None) -> str:
    """The minimal robot file of ROBOTS[name] as TOML text."""
    robot = ROBOTS[name]
    share = share or erd_share()
    urdf = urdf_path(name, share)
    text = (f"name = {_toml(name)}\nkind = {_toml(robot.kind)}\nurdf = {_toml(str(urdf))}\n"
            f"package_dirs = {_toml([str(share)])}\n")
    for table, values in robot.table.items():
        text += f"\n[{table}]\n" + "".join(f"{k} = {_toml(v)}\n" for k, v in values.items())
    if robot.rotors:
        text += "\n" + rotor_tables(robot, urdf)
    return text


def robot_file(name: str, directory) -> Path | None:
    """Writes DIRECTORY/<name>.toml, the minimal robot file of ROBOTS[name]; None without
    example-robot-data."""
    share = erd_share()
    if share is None:
        return None
    path = Path(directory) / f"{name}.toml"
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(robot_text(name, share))
    return path
