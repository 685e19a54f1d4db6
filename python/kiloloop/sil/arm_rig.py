"""SIL rig for arms: the MuJoCo plant built from a robot file + the 1 kHz loop + video.

One shape for every family (plant / rig / adapter / scenario): this file builds the plant from
the robot (only the controlled chain actuated, everything else welded, meshes resolved), derives
what needs the plant's geometry (reach, a well-conditioned work pose) and runs the loop; the
adapters (sil/arm_adapters.py) map measurements onto one compiled controller; the scenarios
script the motion and judge the log. No control logic here.
"""
from __future__ import annotations

import mujoco
import numpy as np

import kiloloop as kl

from ..robot import arm as arm_defaults
from . import native as native_loop
from .log import SignalLog
from .loop import LoopSettings, run_loop
from .plant import MujocoPlant
from .video import maybe_recorder

# Work pose search: seeded candidates around the start pose, scored by the conditioning of the
# position Jacobian, kept clear of the floor. Deterministic (fixed seed) for a given robot file.
WORK_POSE_CANDIDATES = 400
WORK_POSE_SEED = 20261123
FLOOR_CLEARANCE = 0.1  # [m] of the reach: every link origin stays this far above z = 0


def build_plant(robot, *, scene=None, visual: bool = False, timestep=None, damping=None,
                frictionloss=None, armature=None) -> MujocoPlant:
    """The MuJoCo plant of an arm's robot file, resting at the derived start pose."""
    model = robot.model()
    sim = robot.sim
    sim.setdefault("ee", {}).setdefault("body", robot.section("chain")["tip"])
    plant = MujocoPlant(robot.urdf, sim, timestep=timestep, damping=damping,
                        frictionloss=frictionloss, armature=armature, scene=scene,
                        joints=list(model.joint_names),
                        locked=robot.section("chain").get("locked", {}),
                        package_dirs=robot.package_dirs, visual=visual)
    plant.q0 = arm_defaults.start_pose(robot, model)
    plant.reset()
    return plant


def reach(plant: MujocoPlant) -> float:
    """[m] joint anchor to joint anchor along the chain, then to the end-effector site: an upper
    bound on how far the site gets from the first joint (constant for revolute chains)."""
    m, d = plant.model, plant.data
    jid = [m.joint(n).id for n in plant.joint_names]
    mujoco.mj_kinematics(m, d)
    points = [d.xanchor[j] for j in jid] + [d.site_xpos[m.site(plant.ee_site).id]]
    return float(sum(np.linalg.norm(b - a) for a, b in zip(points[:-1], points[1:])))


def _conditioning(plant, q, scratch, jacp) -> tuple[float, np.ndarray]:
    """(inverse condition number of the 3 x n position Jacobian of the end-effector site,
    heights [m] of the moving bodies' origins) at q."""
    m = plant.model
    scratch.qpos[plant._qadr] = q
    mujoco.mj_kinematics(m, scratch)
    mujoco.mj_comPos(m, scratch)
    mujoco.mj_jacSite(m, scratch, jacp, None, m.site(plant.ee_site).id)
    s = np.linalg.svd(jacp[:, plant._dadr], compute_uv=False)
    moving = _moving_bodies(m)
    return (float(s[-1] / s[0]) if s[0] > 0 else 0.0), scratch.xpos[moving, 2].copy()


def _moving_bodies(m) -> np.ndarray:
    """Ids of bodies that some joint moves (a body below a jointed body moves too)."""
    moves = np.zeros(m.nbody, dtype=bool)
    for b in range(1, m.nbody):
        moves[b] = m.body_jntnum[b] > 0 or moves[m.body_parentid[b]]
    return np.nonzero(moves)[0]


def work_pose(robot, model, plant: MujocoPlant) -> np.ndarray:
    """[rad] a well-conditioned pose near the start pose. The start pose itself when the robot file
    gives it ([sim.joints] q0 or [chain] q0) or when its position
    Jacobian is well conditioned (inverse condition number above 0.2); else the best of seeded
    candidates (start pose plus offsets within the limits, capped at 1 rad per joint) in which no
    moving link origin drops below min(its start height, 10 % of the reach) (the floor is z = 0),
    preferring conditioning, then closeness to the start pose."""
    q_start = arm_defaults.start_pose(robot, model)
    if arm_defaults.start_pose_given(robot):
        return q_start  # the robot file chose it
    scratch = mujoco.MjData(plant.model)
    jacp = np.zeros((3, plant.model.nv))
    score0, z0 = _conditioning(plant, q_start, scratch, jacp)
    if score0 > 0.2:
        return q_start
    z_min = np.minimum(z0, FLOOR_CLEARANCE * reach(plant)) - 1e-9
    down, up = arm_defaults.joint_range(model, q_start)
    rng = np.random.default_rng(WORK_POSE_SEED)
    best, best_score = q_start, score0
    for _ in range(WORK_POSE_CANDIDATES):
        q = q_start + rng.uniform(-down, up)
        score, z = _conditioning(plant, q, scratch, jacp)
        if np.any(z < z_min):
            continue
        score -= 0.01 * float(np.linalg.norm(q - q_start))
        if score > best_score:
            best, best_score = q, score
    return best


class ArmRig:
    """Plant + model + loop for one arm robot file."""

    def __init__(self, robot, *, scene=None, video: str | None = None, **plant_kwargs):
        self.robot = robot
        self.model = robot.model()
        self.plant = build_plant(robot, scene=scene, visual=bool(video), **plant_kwargs)
        self.video_path = video

    def T_world_root(self) -> np.ndarray:
        """(4, 4) pose of the chain's root link in MuJoCo's world (fixed base: constant)."""
        m, d = self.plant.model, self.plant.data
        b = m.body(self.model.root_name).id
        T = np.eye(4)
        T[:3, :3], T[:3, 3] = d.xmat[b].reshape(3, 3), d.xpos[b]
        return T

    def runs_natively(self, tick, observe=None, native: bool | None = True) -> bool:
        """Whether run() takes the native loop: asked for (native not False), built in
        (native.available()), a tick with a C++ twin, ground truth given as an Observe (or none)
        and no video (frames are captured per tick in Python)."""
        return (native is not False and native_loop.available()
                and hasattr(tick, "native_adapter") and self.video_path is None
                and (observe is None or isinstance(observe, native_loop.Observe)))

    def run(self, tick, duration: float, *, delay_ticks: int = 0, observe=None,
            log: SignalLog | None = None, native: bool | None = True,
            nonideal: native_loop.NonIdeal | None = None) -> SignalLog:
        """The closed loop for `duration` [s]: natively when runs_natively(), else per tick in
        Python; both give the same log (tests/test_native_arm.py). nonideal: joint sensor and
        motor models (sil/native.py), the same C++ code in either loop."""
        if self.runs_natively(tick, observe, native):
            return native_loop.run(self.plant, tick.native_adapter(), duration, log,
                                   delay_ticks=delay_ticks, nonideal=nonideal,
                                   events=tick.native_events(), observe=observe)
        plant, step = self.plant, tick
        if nonideal is not None:
            # The same C++ sensor/motor models and streams as the native loop, called per tick.
            plant = native_loop.noisy_plant(self.plant, nonideal)
            motor = nonideal.motor(self.plant.nq)

            def step(m, lg):
                return motor.push(tick(m, lg))
        recorder = maybe_recorder(self.video_path, self.plant.model,
                                  body=self.plant.model.body(self.model.root_name).id
                                  if self.model.root_name else 1)

        def watch(_p, lg):
            # Ground truth from the plant itself, never through the sensor model.
            if observe is not None:
                observe(self.plant, lg)
            if recorder is not None:
                recorder.capture(self.plant.data)

        try:
            return run_loop(plant, step, LoopSettings(duration=duration,
                                                      delay_ticks=delay_ticks),
                            log=log, observe=watch)
        finally:
            if recorder is not None:
                recorder.close()


def controller(robot, model, law: str, q, *, delay_ticks: int = 0, config=None):
    """A compiled joint controller with gains derived from the robot file (robot/arm.py)."""
    kp, kd = arm_defaults.joint_gains(robot, model, law, q)
    age = float(arm_defaults.controller_settings(robot)["max_measurement_age"])
    if law == "computed_torque":
        c = config or kl.ComputedTorqueConfig()
        c.kp, c.kd = kp, kd
        c.max_measurement_age = age + delay_ticks * 0.001
        return kl.ComputedTorqueController(model, c)
    if law == "pd_gravity":
        c = config or kl.JointPdGravityConfig()
        c.kp, c.kd = kp, kd
        c.max_measurement_age = age + delay_ticks * 0.001
        return kl.JointPdGravityController(model, c)
    raise ValueError(f"controller: expected 'computed_torque' or 'pd_gravity', got {law!r}")


def joint_targets(model, plant: MujocoPlant, q_start, count: int, fraction: float,
                  seed: int = WORK_POSE_SEED) -> list[np.ndarray]:
    """`count` configurations, each `fraction` of every joint's free range (capped at 1 rad) away
    from the previous one in a seeded direction per joint, such that the straight joint-space path
    through them keeps every moving link origin above min(its start height, 10 % of the reach)
    and the end-effector Jacobian well conditioned (inverse condition number > 0.05) at each."""
    scratch = mujoco.MjData(plant.model)
    jacp = np.zeros((3, plant.model.nv))
    q_prev = np.asarray(q_start, dtype=float)
    _, z0 = _conditioning(plant, q_prev, scratch, jacp)
    z_min = np.minimum(z0, FLOOR_CLEARANCE * reach(plant)) - 1e-9
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(count):
        down, up = arm_defaults.joint_range(model, q_prev)
        for _attempt in range(200):
            sign = rng.choice([-1.0, 1.0], size=model.nq)
            step = np.where(sign > 0, up, -down) * fraction
            q = q_prev + step
            ok = True
            for s in np.linspace(0.0, 1.0, 21)[1:]:
                score, z = _conditioning(plant, q_prev + s * step, scratch, jacp)
                if np.any(z < z_min) or (s == 1.0 and score < 0.05):
                    ok = False
                    break
            if ok:
                break
        else:
            raise ValueError("no collision-free joint target found near the start pose")
        out.append(q)
        q_prev = q
    return out


# Candidate line directions (chain root frame) and rotation axes for derived Cartesian motions,
# tried in order; the first the IK can follow wins.
LINE_DIRECTIONS = ([0.6, 0.8, -0.6], [-0.6, 0.8, -0.6], [0.6, -0.8, -0.6], [0.0, 0.0, 1.0],
                   [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0], [0.0, -1.0, 0.0])
LINE_ROTATION_AXES = ([0.0, 0.6, 0.8], [0.8, 0.0, 0.6], [0.6, 0.8, 0.0])
LINE_LENGTH = 0.2    # of the reach
LINE_ROTATION = 0.5  # [rad]


def _rotvec_matrix(w) -> np.ndarray:
    R = np.zeros(9)
    w = np.asarray(w, dtype=float)
    angle = float(np.linalg.norm(w))
    q = np.array([1.0, 0, 0, 0])
    if angle > 0:
        mujoco.mju_axisAngle2Quat(q, w / angle, angle)
    mujoco.mju_quat2Mat(R, q)
    return R.reshape(3, 3)


def line_feasible(model, q0, displacement, rotation, samples: int = 25,
                  max_joint_step: float = 0.3) -> bool:
    """True when the IK follows the line from q0 continuously: every sample solved within the
    limits, consecutive solutions closer than max_joint_step [rad], position Jacobian not
    singular (inverse condition number > 0.05)."""
    dyn = kl.Dynamics(model)
    ik = kl.ArmIk(model)
    start = dyn.forward_kinematics(q0)
    q = np.asarray(q0, dtype=float)
    for s in np.linspace(0.0, 1.0, samples)[1:]:
        T = start.copy()
        T[:3, 3] += s * np.asarray(displacement, dtype=float)
        T[:3, :3] = _rotvec_matrix(s * np.asarray(rotation, dtype=float)) @ start[:3, :3]
        q_next, status = ik.solve(T, q)
        if int(status) < 0 or np.abs(q_next - q).max() > max_joint_step:
            return False
        sv = np.linalg.svd(dyn.jacobian(q_next)[:3], compute_uv=False)
        if sv[-1] < 0.05 * sv[0]:
            return False
        q = q_next
    return True


def line_target(rig: ArmRig, q0) -> tuple[np.ndarray, np.ndarray]:
    """(displacement [m], rotation vector [rad]) of a derived Cartesian line from the pose at q0:
    LINE_LENGTH of the reach along the first feasible LINE_DIRECTIONS entry, LINE_ROTATION about
    the first feasible axis (halved up to twice when nothing is feasible)."""
    length = LINE_LENGTH * reach(rig.plant)
    for scale in (1.0, 0.5, 0.25):
        for direction in LINE_DIRECTIONS:
            d = np.asarray(direction, dtype=float)
            d = scale * length * d / np.linalg.norm(d)
            for axis in LINE_ROTATION_AXES:
                r = scale * LINE_ROTATION * np.asarray(axis, dtype=float) / np.linalg.norm(axis)
                if line_feasible(rig.model, q0, d, r):
                    return d, r
    raise ValueError(f"{rig.robot.name}: no feasible Cartesian line from the work pose")
