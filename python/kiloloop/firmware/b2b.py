"""`kiloloop b2b ROBOT`: SIL run (every controller input and output logged) -> export -> firmware
build (-fno-exceptions -fno-rtti) -> replay -> "bit-identical: N ticks", plus the exported model's
dynamics against the URDF-loaded model's (mass matrix, gravity, Coriolis at seeded states, ==).
"""
from __future__ import annotations

import re
import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from . import build
from .export import write_export
from .families import family_of
from .recording import record_sil_run, write_log

MODEL_CHECK_STATES = 16
MODEL_CHECK_SEED = 20261123


@dataclass
class B2bResult:
    robot: str
    ticks: int
    log_sha256: str
    replay_output: str       # the firmware's own line(s)
    identical: bool
    model_identical: bool
    model_chains: int        # chains compared


def _slug(name: str) -> str:
    return re.sub(r"[^A-Za-z0-9_.-]", "_", name)


def model_chains(robot, model) -> list[tuple[str, str]]:
    """Chains whose dynamics are compared: the controller's chain, or (a tree model) the URDF's
    root link to each leaf link."""
    if model.has_chain:
        return [(model.root_name, model.tip_name)]
    import xml.etree.ElementTree as ET

    joints = ET.parse(robot.urdf).getroot().findall("joint")
    parents = {j.find("parent").get("link") for j in joints}
    children = {j.find("child").get("link") for j in joints}
    roots = parents - children
    leaves = sorted(children - parents)
    return [(root, leaf) for root in sorted(roots) for leaf in leaves]


def check_model(exe: Path, robot, chains, work: Path) -> tuple[bool, int]:
    """The firmware's exported description vs kl.RobotModel.from_urdf: M, g, C qd with ==."""
    import kiloloop as kl

    rng = np.random.default_rng(MODEL_CHECK_SEED)
    compared = 0
    for root, tip in chains:
        model = kl.RobotModel.from_urdf(robot.urdf_doc.model_source(), root, tip)
        n = model.nq
        if n == 0:
            continue  # a rigid branch (a sensor link): no dynamics to compare
        dyn = kl.Dynamics(model)
        compared += 1
        states = rng.uniform(-1.5, 1.5, size=(MODEL_CHECK_STATES, 2, n))
        states_path, out_path = work / "states.bin", work / "dynamics.bin"
        states.astype("<f8").tofile(states_path)
        proc = build.run_firmware(exe, "model-check", root, tip, states_path, out_path)
        if proc.returncode != 0:
            raise build.BuildError(f"model-check {root} -> {tip}: {proc.stderr.strip()}")
        got = np.fromfile(out_path, dtype="<f8").reshape(MODEL_CHECK_STATES, n * n + 2 * n)
        for k, (q, qd) in enumerate(states):
            M = got[k, : n * n].reshape(n, n, order="F")
            g, c = got[k, n * n: n * n + n], got[k, n * n + n:]
            if not (np.array_equal(M, dyn.mass_matrix(q)) and np.array_equal(g, dyn.gravity(q))
                    and np.array_equal(c, dyn.coriolis(q, qd))):
                print(f"  model {root} -> {tip}: differs at state {k}", file=sys.stderr)
                return False, compared
    return True, compared


@dataclass
class Recorded:
    """A SIL run logged and its robot exported: what a replay, here or on a target, needs."""
    robot: object            # kiloloop.Robot
    family: object           # firmware.families.Family
    here: Path               # <work>/<robot>: log, export, builds
    log: Path
    log_sha256: str
    ticks: int
    header: Path             # the export's robot_export.hpp
    model: object            # the controller's kl.RobotModel (the model check's reference)


def record_and_export(robot_arg, *, duration: float | None = None, seed: int | None = None,
                      sets: dict | None = None, work=None, echo=print,
                      scenario: str | None = None, what_for: str = "b2b",
                      subdir: str = "") -> Recorded:
    """The SIL run, every controller input and output logged (<work>/<robot>[/<subdir>]/b2b.log),
    and the robot with its controller settings exported (export/ beside the log). scenario: a
    scenario file whose run is recorded (default: the family's built-in b2b scenario); duration
    and seed None: the file's own, else 1 s and 0. subdir: a run of its own (a PIL target's),
    which a b2b run of the same robot at the same time does not overwrite."""
    from .. import _core
    from ..robot import Robot

    robot = Robot.load(robot_arg)
    family = family_of(robot)
    work = Path(work) if work else build.default_work()
    here = work / _slug(robot.name) / subdir if subdir else work / _slug(robot.name)
    if scenario is None:
        duration = 1.0 if duration is None else duration
        seed = 0 if seed is None else seed
    what = scenario or family.scenario
    echo(f"{what_for} {robot.name} ({family.name}): SIL {what}"
         + (f", {duration:g} s" if duration is not None else "")
         + (f", seed {seed}" if seed is not None else ""))
    rec = record_sil_run(robot, family, duration=duration, seed=seed, sets=sets,
                         scenario=scenario)
    log = here / "b2b.log"
    digest = write_log(rec, _core.firmware.FAMILY[family.name], log)
    echo(f"  SIL log: {rec.ticks} ticks, sha256 {digest[:16]}..  ({log})")
    c = rec.controller
    header = write_export(robot, family, c.model, c.config, here / "export",
                          {"scenario": what, "seed": seed, "duration": duration})
    echo(f"  export: {header}")
    return Recorded(robot, family, here, log, digest, rec.ticks, header, c.model)


def run_b2b(robot_arg, *, duration: float | None = None, seed: int | None = None,
            sets: dict | None = None, work=None, prefix=None, echo=print,
            scenario: str | None = None) -> B2bResult:
    """SIL run -> log -> export -> firmware build -> replay, for one robot. `prefix`: an install of
    the firmware core to build against; by default the installed kit, else (a source tree
    without a wheel install) built or updated in `work` first (build.host_core). scenario,
    duration, seed: as record_and_export's."""
    source = build.source_root()
    work = Path(work) if work else build.default_work()
    r = record_and_export(robot_arg, duration=duration, seed=seed, sets=sets, work=work,
                          echo=echo, scenario=scenario)
    prefix = Path(prefix) if prefix else build.host_core(source, work)
    exe = build.build_firmware(source, prefix, r.header.parent, r.here / "build")
    echo(f"  firmware: {exe} (-fno-exceptions -fno-rtti)")
    proc = build.run_firmware(exe, "replay", r.log)
    if proc.returncode not in (0, 1):
        raise build.BuildError(f"replay failed: {proc.stderr.strip()}")
    line = proc.stdout.strip()
    model_ok, chains = check_model(exe, r.robot, model_chains(r.robot, r.model), r.here)
    if chains:
        echo(f"  model: mass matrix, gravity, Coriolis at {MODEL_CHECK_STATES} states on "
             f"{chains} chain(s) equal to the URDF-loaded model's: {'yes' if model_ok else 'NO'}")
    else:  # a rigid vehicle: its mass and inertia reach the outputs, which the replay compares
        echo("  model: no movable joints, no joint-space dynamics to compare")
    echo(line)
    return B2bResult(r.robot.name, r.ticks, r.log_sha256, line, proc.returncode == 0 and
                     line.startswith("bit-identical"), model_ok, chains)
