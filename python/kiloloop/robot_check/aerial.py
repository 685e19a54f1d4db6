"""`kiloloop robot check` on an aerial robot: rotors, allocation, hover, what robot/aerial.py
derived, and the plant built from the robot file."""
from __future__ import annotations

import math

import numpy as np

import kiloloop as kl

from ..robot import aerial
from ..sil.aerial_plant import AerialPlant


def summary(robot, model_) -> list[str]:
    """Lines for `kiloloop robot check`: rotors, allocation, hover, derived gains, the plant."""
    cfg = aerial.config(robot)
    ctrl = kl.AerialController(aerial.model(robot), cfg)
    alloc = ctrl.allocation
    plant = AerialPlant.from_robot(robot)
    rank = np.linalg.matrix_rank(alloc.effectiveness)
    hover = ctrl.hover_thrust
    bw = aerial.bandwidths(robot)
    alpha = aerial.roll_pitch_authority(robot)
    given = set(aerial.controller_settings(robot))
    src = lambda k: "given" if k in given else "derived"  # noqa: E731
    return [
        "  derived:",
        f"    rotors                     {alloc.n}; allocation rank {rank} of 6 "
        f"({'lateral force rows held at zero' if alloc.uses_lateral_rows else 'T, tau rows'})",
        f"    mass [kg]                  {ctrl.total_mass:.4g} (body {ctrl.body_mass:.4g}); "
        f"body CoM {_fmt(ctrl.body_com)} m; vehicle CoM {_fmt(ctrl.vehicle_com)} m",
        f"    hover thrust [N]           {hover:.4g} total; collective share per rotor "
        f"{_fmt(np.asarray(alloc.collective_share) * hover)}; thrust/weight "
        f"{alloc.max_collective / hover:.3g}",
        f"    rotor time constant [s]    {aerial.time_constant(robot):.4g} (reaction lead "
        f"{cfg.reaction_lead:.4g} s, {src('reaction_lead')})",
        f"    roll/pitch authority       {alpha:.4g} rad/s^2 at hover (the rotors' margin on the "
        f"rigid inertia): the attitude bandwidth's bound 2 sqrt(alpha / tilt limit) = "
        f"{2 * math.sqrt(alpha / aerial.tilt_limit(robot)):.4g} rad/s",
        f"    attitude bandwidth [rad/s] {bw['attitude']:.4g} ({src('attitude_bandwidth')}): "
        f"kp {_fmt(cfg.attitude.gains.kp)}, kd {_fmt(cfg.attitude.gains.kd)}",
        f"    position bandwidth [rad/s] {bw['position']:.4g} ({src('position_bandwidth')}): "
        f"kp {_fmt(cfg.position.kp)}, kd {_fmt(cfg.position.kd)}, ki {_fmt(cfg.position.ki)}",
        f"    arm                        {ctrl.nq} joints" + (
            f", kp {_fmt(cfg.arm_kp)}, kd {_fmt(cfg.arm_kd)}" if ctrl.nq else " (no arm)"),
        f"  plant: {plant.model.nbody - 1} bodies, {plant.nq} arm joints, "
        f"{plant.n_rotors} rotors; mass {plant.total_mass:.4g} kg",
    ] + [f"    note: {n}" for n in plant.notes]


def _fmt(x) -> str:
    return "[" + ", ".join(f"{v:.4g}" for v in np.atleast_1d(np.asarray(x, dtype=float))) + "]"
