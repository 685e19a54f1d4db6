"""Layers import downward only (issue 30): robot/ (robot files and what is derived from them)
imports nothing from sil/ (plants, MuJoCo), scenarios/ or anything above them, so that loading a
robot file, building its model and deriving its controller settings do not import MuJoCo; and no
modules of the package import each other in a circle, deferred imports included."""
import ast
import json
import re
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

import kiloloop
from kiloloop import scenarios
from kiloloop.robot import Robot, RobotFileError

PACKAGE = Path(kiloloop.__file__).resolve().parent
# What robot/ sits below: the SIL (plants, MuJoCo), the scenarios and everything that uses them.
ABOVE_ROBOT = ("mujoco", "kiloloop.sil", "kiloloop.scenarios", "kiloloop.sweep", "kiloloop.cli",
               "kiloloop.robot_check", "kiloloop.firmware", "kiloloop.bench", "kiloloop.envs",
               "kiloloop.plot")


def _package_of(path: Path) -> str:
    """The dotted package a module file's relative imports start from."""
    parts = ["kiloloop", *path.relative_to(PACKAGE).with_suffix("").parts]
    return ".".join(parts[:-1])  # a module's package; for __init__.py, the package itself


def imports(source: str, package: str) -> list[tuple[int, str]]:
    """(line, absolute module name) of every import in `source`, at any depth: module level,
    function bodies, methods, conditionals. `from P import name` yields P.name too (name may be
    a module). importlib.import_module and __import__ calls yield '<dynamic>' (not followable)."""
    out = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Import):
            out += [(node.lineno, alias.name) for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")[:len(package.split(".")) - (node.level - 1)]
                module = ".".join(base + ([node.module] if node.module else []))
            else:
                module = node.module
            out.append((node.lineno, module))
            out += [(node.lineno, f"{module}.{alias.name}") for alias in node.names]
        elif isinstance(node, ast.Call):
            f = node.func
            name = f.attr if isinstance(f, ast.Attribute) else getattr(f, "id", "")
            if name in ("import_module", "__import__"):
                out.append((node.lineno, "<dynamic>"))
    return out


def _under(module: str, prefixes) -> bool:
    return any(module == p or module.startswith(p + ".") for p in prefixes)


def test_the_walker_sees_deferred_relative_and_dynamic_imports():
    source = ("import numpy\n"
              "def f():\n"
              "    from ..sil.plant import urdf_joints\n"
              "    from .. import scenarios\n"
              "class C:\n"
              "    def m(self):\n"
              "        import kiloloop.sweep\n"
              "        if True:\n"
              "            from . import schema\n"
              "def g():\n"
              "    importlib.import_module('kiloloop.sil')\n")
    found = imports(source, "kiloloop.robot")
    assert (3, "kiloloop.sil.plant") in found and (4, "kiloloop.scenarios") in found
    assert (7, "kiloloop.sweep") in found and (9, "kiloloop.robot.schema") in found
    assert (11, "<dynamic>") in found
    flagged = {line for line, m in found if m == "<dynamic>" or _under(m, ABOVE_ROBOT)}
    assert flagged == {3, 4, 7, 11}


def test_robot_imports_nothing_from_the_layers_above_it():
    bad = []
    for path in sorted((PACKAGE / "robot").rglob("*.py")):
        for line, module in imports(path.read_text(), _package_of(path)):
            if module == "<dynamic>" or _under(module, ABOVE_ROBOT):
                bad.append(f"{path.relative_to(PACKAGE)}:{line}: {module}")
    assert not bad, "robot/ imports from above it:\n" + "\n".join(bad)


def _import_graph() -> dict[str, set[str]]:
    """Module -> the package's modules it imports (at module level or inside functions), leaving
    out its own parent packages (`from .. import _core` runs kiloloop/__init__.py, which is
    already running: not a circle of the code's making)."""
    graph = {}
    for path in sorted(PACKAGE.rglob("*.py")):
        package = _package_of(path)
        name = package if path.name == "__init__.py" else f"{package}.{path.stem}"
        graph[name] = {m for _, m in imports(path.read_text(), package)}
    for name, targets in graph.items():
        graph[name] = {m for m in targets if m in graph and m != name
                       and not name.startswith(m + ".")}
    return graph


def _circles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected components of more than one module."""
    def reach(start):
        seen, todo = set(), [start]
        while todo:
            for m in graph[todo.pop()] - seen:
                seen.add(m)
                todo.append(m)
        return seen
    reachable = {m: reach(m) for m in graph}
    circles = {tuple(sorted(m2 for m2 in reachable[m] if m in reachable[m2]))
               for m in graph if m in reachable[m]}
    return sorted(list(c) for c in circles if len(c) > 1)


def test_the_circle_finder_finds_a_circle_of_three():
    graph = {"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}
    assert _circles(graph) == [["a", "b", "c"]]


def test_no_modules_import_each_other_in_a_circle():
    """Module-level and deferred imports alike: a circle held together by an import inside a
    function is still a circle (it is how robot/ and sil/, sil/batch.py and sweep.py were tied)."""
    circles = _circles(_import_graph())
    assert not circles, "import circles:\n" + "\n".join(", ".join(c) for c in circles)


_PROBE = """
import json, sys
import numpy as np
import kiloloop.robot
from kiloloop import _core
from kiloloop.robot import Robot, arm, aerial, quadruped
for name in ("ur5", "quadruped", "aerial_manipulator"):
    robot = Robot.load(name)
    model = robot.model()
    if robot.kind == "arm":
        q0 = arm.start_pose(robot, model)
        arm.joint_gains(robot, model, "pd_gravity", q0)
        arm.joint_friction(robot, model)
        robot.with_overrides({"controller.bandwidth": 20.0}).model()
    elif robot.kind == "quadruped":
        ctrl = _core.QuadrupedController(model, quadruped.controller_config(robot))
        quadruped.plant_overlay(robot, ctrl)
    else:
        _core.AerialController(model, aerial.config(robot))
print(json.dumps(sorted(m for m in sys.modules if m == "mujoco" or m.startswith(
    ("mujoco.", "kiloloop.sil", "kiloloop.scenarios")))))
"""


def test_loading_a_robot_file_does_not_import_mujoco():
    out = subprocess.run([sys.executable, "-c", _PROBE], capture_output=True, text=True,
                         timeout=300)
    assert out.returncode == 0, out.stderr
    imported = json.loads(out.stdout.strip().splitlines()[-1])
    assert not imported, f"loading robot files imported {imported}"


# The [scenario.<name>] check left robot/ for the scenarios (which register it with Robot.load
# when imported); `kiloloop robot check` and every scenario run still refuse a bad table.
_UR5 = PACKAGE / "models" / "ur5" / "ur5.urdf"
_BAD_SCENARIO_TABLES = {
    "scenario.arm-dance": '[scenario.arm-dance]\nt_1 = 1\n',
    "scenario.arm-track.nope": '[scenario.arm-track]\nnope = 1\n',
}


def _robot_file(tmp_path, extra: str) -> Path:
    path = tmp_path / "robot.toml"
    path.write_text(f'name = "x"\nkind = "arm"\nurdf = "{_UR5}"\n'
                    f'[chain]\nroot = "base_link"\ntip = "tool0"\n' + extra)
    return path


def test_a_robot_read_before_the_scenarios_is_checked_when_a_scenario_takes_it(tmp_path):
    for key, table in _BAD_SCENARIO_TABLES.items():
        path = _robot_file(tmp_path, table)
        with pytest.raises(RobotFileError, match=f"'{key}'"):
            Robot.load(path)  # kiloloop.scenarios is imported: Robot.load checks the table
        # As Robot.load gives it in a process that has not imported the scenarios yet.
        unchecked = Robot(path=path, data=tomllib.loads(path.read_text()))
        with pytest.raises(RobotFileError, match=re.escape(f"{path}: unknown key '{key}'")):
            scenarios.prepare(scenarios.get("arm-track"), unchecked)


def test_robot_check_refuses_a_bad_scenario_table_in_one_line(tmp_path):
    for key, table in _BAD_SCENARIO_TABLES.items():
        out = subprocess.run([sys.executable, "-m", "kiloloop.cli", "robot", "check",
                              str(_robot_file(tmp_path, table))], capture_output=True, text=True,
                             timeout=300)
        assert out.returncode == 2 and out.stdout == "", out.stdout + out.stderr
        assert out.stderr.strip().splitlines() == [
            f"kiloloop robot check: {tmp_path / 'robot.toml'}: unknown key '{key}'"
            + (" (no such scenario)" if key == "scenario.arm-dance" else "")]
