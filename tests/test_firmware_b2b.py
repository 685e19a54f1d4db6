"""The firmware path end to end (`kiloloop b2b`): a SIL run logs every controller input and
output, `kiloloop export` writes the robot as one header, the firmware example builds against the
installed -fno-exceptions -fno-rtti core and replays the log; every output must equal the SIL
run's bit for bit, and the exported model's mass matrix, gravity and Coriolis must equal the
URDF-loaded model's (==). One build directory for the session (the source tree's
build/firmware: the core is built once, by conftest's firmware_prefix, shared with the embed
example; each robot's firmware is one translation unit).
"""
import re
from pathlib import Path

import pytest

from kiloloop.firmware.b2b import run_b2b
from kiloloop.firmware.families import FAMILIES
from kiloloop.firmware.recording import record_sil_run, write_log
from kiloloop.robot import Robot

import robot_files
import quadruped_robots
import aerial_test_robots
from build_flags import object_flags, unity_sources

ROOT = Path(__file__).resolve().parents[1]
WORK = ROOT / "build" / "firmware"
DURATION = 0.3  # [s] 300 ticks: short, and past every controller's start-up transient


def _check(prefix, robot, duration=DURATION, chains=1):
    result = run_b2b(robot, duration=duration, work=WORK, prefix=prefix, echo=lambda *_: None)
    ticks = int(round(duration * 1000))
    assert result.ticks == ticks
    assert result.replay_output == f"bit-identical: {ticks} ticks", result.replay_output
    assert result.identical
    assert result.model_chains >= chains and result.model_identical


@pytest.mark.parametrize("robot", ["ur5", "quadruped", "aerial_manipulator"])
def test_b2b_our_robots(firmware_prefix, robot):
    _check(firmware_prefix, robot)


def test_b2b_go1(firmware_prefix, tmp_path):
    path = quadruped_robots.go1_robot_file(tmp_path)
    if path is None:
        pytest.skip("example-robot-data is not installed")
    _check(firmware_prefix, path)


@pytest.mark.parametrize("name", ["ur3", "panda"])
def test_b2b_example_robot_data_arms(firmware_prefix, tmp_path, name):
    rel, root, tip = {"ur3": ("ur_description/urdf/ur3_robot.urdf", "base_link", "tool0"),
                      "panda": ("panda_description/urdf/panda.urdf", "panda_link0",
                                "panda_link8")}[name]
    arm = robot_files.minimal_arm(tmp_path, robot_files.erd_urdf(rel), root, tip, name)
    _check(firmware_prefix, arm)


def test_b2b_aerial_test_robots(firmware_prefix, tmp_path):
    from kiloloop.robot.robot_file import Robot

    # Four of them (a firmware build each): a rigid quadrotor, a hexarotor with an arm and its CoM
    # off the base origin, tilted rotors with a 3-joint arm, eight rotors.
    robots = aerial_test_robots.write_all(tmp_path)
    for path in (robots[name] for name in ("iris", "borinot", "hextilt", "octo_arm")):
        # A multirotor without an arm (iris, hector) is rigid: no joint-space dynamics to compare
        # (its outputs are compared)
        rigid = Robot.load(path).section("vehicle").get("ee") is None
        _check(firmware_prefix, path, duration=0.1, chains=0 if rigid else 1)


def test_two_sil_runs_give_the_same_log_hash(tmp_path):
    family = FAMILIES["quadruped"]
    robot = Robot.load("quadruped")
    hashes = [write_log(record_sil_run(robot, family, duration=0.2, seed=3), 2, tmp_path / f"{k}.log")
              for k in range(2)]
    assert hashes[0] == hashes[1]
    other = write_log(record_sil_run(robot, family, duration=0.2, seed=3,
                                     sets={"controller.kp_position": "[20.0, 20.0, 250.0]"}),
                      2, tmp_path / "other.log")
    assert other != hashes[0]  # the hash does see a changed run


def test_the_firmware_core_is_compiled_without_exceptions(firmware_prefix):
    """What the replays run through. With the wheel's kit (make build installs it): the kit's
    libkiloloop_core.a is, byte for byte, the archive build/py linked into kiloloop._core, every
    object of it compiled -fno-exceptions (RTTI kept for the bindings: CMakeLists.txt,
    KILOLOOP_CORE_RTTI; the PIL cross cores are -fno-rtti too); without a kit, the core built in
    build/firmware/core with -fno-exceptions -fno-rtti. Either way every core source is in it and
    the URDF loader, init time only, keeps exceptions."""
    from kiloloop.firmware.build import kit_prefix
    kit = kit_prefix()
    build_dir = ROOT / "build" / ("py" if kit is not None else "firmware/core")
    if not (build_dir / "build.ninja").is_file():
        pytest.skip(f"{build_dir} is not a Ninja build directory (built elsewhere)")
    flags = object_flags(build_dir)
    assert flags.get("kiloloop_core"), sorted(flags)
    assert all("-fno-exceptions" in f for f in flags["kiloloop_core"])
    if kit is not None:
        assert firmware_prefix == kit
        archive = (kit / "lib" / "libkiloloop_core.a").read_bytes()
        assert archive == (build_dir / "libkiloloop_core.a").read_bytes()
        ninja = (build_dir / "build.ninja").read_text()
        module_link = re.search(r"^build _core[^\n]*\.so: [^\n]*", ninja, re.MULTILINE).group(0)
        assert "libkiloloop_core.a" in module_link
    else:
        assert all("-fno-rtti" in f for f in flags["kiloloop_core"])
    # A unity build: every core source is in one of those objects' units.
    units = unity_sources(build_dir)
    sources = [p for p in (ROOT / "cpp" / "src").rglob("*.cpp") if not p.name.endswith("_test.cpp")]
    assert len(sources) > 30 and all(f'"{p.resolve()}"' in units for p in sources)
    assert flags.get("kiloloop_urdf") and not any("-fno-exceptions" in f
                                                  for f in flags["kiloloop_urdf"])
    assert any(firmware_prefix.glob("lib*/cmake/kiloloop/kiloloopConfig.cmake"))
