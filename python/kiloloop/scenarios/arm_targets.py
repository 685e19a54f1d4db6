"""What the arm scenarios derive from the plant's geometry: the reach, a well-conditioned work
pose (PoseProbe), joint-space targets clear of the floor, a Cartesian line the IK can follow and
the links' collision capsules for planning. The rig (sil/rig.py, sil/arm_family.py) builds the plant
and runs the loop; the targets a scenario derives live with the scenarios."""
from __future__ import annotations

import mujoco
import numpy as np

import kiloloop as kl

from ..errors import InputError
from ..robot import arm as arm_defaults
from ..sil.plant import MujocoPlant

# Work pose search: seeded candidates around the start pose, scored by the conditioning of the
# end-effector Jacobian, kept clear of the floor. Deterministic (fixed seed) for a given robot file.
WORK_POSE_CANDIDATES = 400
WORK_POSE_SEED = 20261123
FLOOR_CLEARANCE = 0.02  # of the reach: the links' geometry stays this far above the floor
WORK_HEIGHT = 0.2       # of the reach: the work pose's tool height above the first joint


def reach(plant: MujocoPlant) -> float:
    """[m] joint anchor to joint anchor along the chain, then to the end-effector site: an upper
    bound on how far the site gets from the first joint (constant for revolute chains)."""
    m, d = plant.model, plant.data
    jid = [m.joint(n).id for n in plant.joint_names]
    mujoco.mj_kinematics(m, d)
    points = [d.xanchor[j] for j in jid] + [d.site_xpos[m.site(plant.ee_site).id]]
    return float(sum(np.linalg.norm(b - a) for a, b in zip(points[:-1], points[1:])))


def _moving_bodies(m) -> np.ndarray:
    """Ids of bodies that some joint moves (a body below a jointed body moves too)."""
    moves = np.zeros(m.nbody, dtype=bool)
    for b in range(1, m.nbody):
        moves[b] = m.body_jntnum[b] > 0 or moves[m.body_parentid[b]]
    return np.nonzero(moves)[0]


class PoseProbe:
    """Geometry of the plant at trial configurations, on scratch data (the simulation is never
    touched): Jacobian conditioning, the links' clearance to the floor, the tool's height."""

    def __init__(self, plant: MujocoPlant):
        self.plant, m = plant, plant.model
        self.data = mujoco.MjData(m)
        self.reach = reach(plant)
        self.site = m.site(plant.ee_site).id
        self.base_z = float(plant.data.xanchor[m.joint(plant.joint_names[0]).id][2])
        moving = set(_moving_bodies(m).tolist()) - self.height_fixed_bodies(plant)
        floor = [g for g in range(m.ngeom) if m.geom(g).name == "floor"]
        self.floor = floor[0] if floor else None
        self.geoms = [g for g in range(m.ngeom) if m.geom_bodyid[g] in moving
                      and m.geom_contype[g] == 0 and m.geom_conaffinity[g] > 0]
        self._jacp, self._jacr = np.zeros((3, m.nv)), np.zeros((3, m.nv))
        self._fromto = np.zeros(6)

    @staticmethod
    def height_fixed_bodies(plant) -> set:
        """Bodies that only a vertical first joint moves (a UR shoulder): their height never
        changes, so their clearance to the floor is no choice of the pose."""
        m, d = plant.model, plant.data
        first = m.joint(plant.joint_names[0]).id
        if m.jnt_type[first] != mujoco.mjtJoint.mjJNT_HINGE or abs(abs(d.xaxis[first][2]) - 1) > 1e-9:
            return set()
        out = set()
        for b in range(1, m.nbody):
            joints, a = set(), b
            while a > 0:
                joints.update(range(m.body_jntadr[a], m.body_jntadr[a] + m.body_jntnum[a]))
                a = m.body_parentid[a]
            if joints == {first}:
                out.add(b)
        return out

    def at(self, q) -> None:
        self.data.qpos[self.plant.qpos_addresses] = q
        mujoco.mj_kinematics(self.plant.model, self.data)
        mujoco.mj_comPos(self.plant.model, self.data)

    def conditioning(self) -> float:
        """Inverse condition number of the site's 6 x n Jacobian, angular rows scaled by a third
        of the reach [m] so that both halves weigh alike (a chain under 6 joints: its rank)."""
        p = self.plant
        mujoco.mj_jacSite(p.model, self.data, self._jacp, self._jacr, self.site)
        J = np.vstack([self._jacp[:, p.dof_addresses], self._jacr[:, p.dof_addresses] * (self.reach / 3.0)])
        sv = np.linalg.svd(J, compute_uv=False)
        return float(sv[min(J.shape) - 1] / sv[0]) if sv[0] > 0 else 0.0

    def floor_clearance(self) -> float:
        """[m] smallest distance from a moving link's geometry to the floor (inf without one)."""
        if self.floor is None or not self.geoms:
            return np.inf
        m, dmax = self.plant.model, self.reach
        return min(mujoco.mj_geomDistance(m, self.data, g, self.floor, dmax, self._fromto)
                   for g in self.geoms)

    def tool_height(self) -> float:
        """[m] the end-effector site above the first joint's anchor."""
        return float(self.data.site_xpos[self.site][2]) - self.base_z


def work_pose(robot, model, plant: MujocoPlant) -> np.ndarray:
    """[rad] a well-conditioned pose near the start pose. The start pose itself when the robot file
    gives it ([sim.joints] q0 or [chain] q0) or when it is already good: Jacobian inverse condition
    number above 0.2, links FLOOR_CLEARANCE of the reach above the floor and the tool WORK_HEIGHT of
    the reach above the first joint. Else the best of seeded candidates (start pose plus offsets
    within the limits, capped at 1 rad per joint) that meet the last two, preferring conditioning,
    then closeness to the start pose (the start pose when no candidate qualifies)."""
    q_start = arm_defaults.start_pose(robot, model)
    if arm_defaults.start_pose_given(robot):
        return q_start  # the robot file chose it
    probe = PoseProbe(plant)

    def acceptable(q) -> bool:
        probe.at(q)
        return (probe.floor_clearance() >= FLOOR_CLEARANCE * probe.reach
                and probe.tool_height() >= WORK_HEIGHT * probe.reach)

    if acceptable(q_start) and probe.conditioning() > 0.2:
        return q_start
    down, up = arm_defaults.joint_range(model, q_start)
    rng = np.random.default_rng(WORK_POSE_SEED)
    best, best_score = q_start, -np.inf
    for _ in range(WORK_POSE_CANDIDATES):
        q = q_start + rng.uniform(-down, up)
        if not acceptable(q):
            continue
        score = probe.conditioning() - 0.01 * float(np.linalg.norm(q - q_start))
        if score > best_score:
            best, best_score = q, score
    return best


def joint_targets(model, plant: MujocoPlant, q_start, count: int, fraction: float,
                  seed: int = WORK_POSE_SEED) -> list[np.ndarray]:
    """`count` configurations, each `fraction` of every joint's free range (capped at 1 rad) away
    from the previous one in a seeded direction per joint, such that the straight joint-space path
    through them keeps the links min(start clearance, FLOOR_CLEARANCE of the reach) above the floor
    and the Jacobian well conditioned (inverse condition number > 0.05) at each target."""
    probe = PoseProbe(plant)
    q_prev = np.asarray(q_start, dtype=float)
    probe.at(q_prev)
    clearance = min(probe.floor_clearance(), FLOOR_CLEARANCE * probe.reach) - 1e-9
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
                probe.at(q_prev + s * step)
                if probe.floor_clearance() < clearance or (s == 1.0 and
                                                           probe.conditioning() < 0.05):
                    ok = False
                    break
            if ok:
                break
        else:
            raise InputError("no collision-free joint target found near the start pose")
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
# The IK's pose residual [m], [rad] above which a line's sample counts as unreachable (an arm of
# fewer than 6 joints: the least-squares IK converges, off the pose).
IK_RESIDUAL = (1e-4, 1e-3)


def _rotvec_matrix(w) -> np.ndarray:
    R = np.zeros(9)
    w = np.asarray(w, dtype=float)
    angle = float(np.linalg.norm(w))
    q = np.array([1.0, 0, 0, 0])
    if angle > 0:
        mujoco.mju_axisAngle2Quat(q, w / angle, angle)
    mujoco.mju_quat2Mat(R, q)
    return R.reshape(3, 3)


def pose_reached(dyn, q, T) -> bool:
    """True when the chain's tip at q is at the pose T within IK_RESIDUAL."""
    reached = dyn.forward_kinematics(q)
    return bool(np.linalg.norm(reached[:3, 3] - T[:3, 3]) <= IK_RESIDUAL[0]
                and _angle(reached[:3, :3].T @ T[:3, :3]) <= IK_RESIDUAL[1])


def line_feasible(model, q0, displacement, rotation, duration: float, samples: int = 50,
                  probe: PoseProbe | None = None) -> bool:
    """True when the IK follows the line from q0 continuously and slowly enough: every sample
    solved within the limits, joint speeds at most half the velocity limits (the quintic time
    scaling peaks at 1.875x the mean speed), and the 6 x n Jacobian (angular rows scaled by the
    start pose's distance from the root) not singular (inverse condition number > 0.02); with a
    probe, the links also stay min(start clearance, FLOOR_CLEARANCE of the reach) above the floor."""
    dyn = kl.Dynamics(model)
    ik = kl.ArmIk(model)
    start = dyn.forward_kinematics(q0)
    length = max(float(np.linalg.norm(start[:3, 3])), 1e-3)
    max_step = 0.5 * np.asarray(model.velocity_limit) * (duration / (samples - 1)) / 1.875
    q = np.asarray(q0, dtype=float)
    if probe is not None:
        probe.at(q)
        clearance = min(probe.floor_clearance(), FLOOR_CLEARANCE * probe.reach) - 1e-9
    for s in np.linspace(0.0, 1.0, samples)[1:]:
        T = start.copy()
        T[:3, 3] += s * np.asarray(displacement, dtype=float)
        T[:3, :3] = _rotvec_matrix(s * np.asarray(rotation, dtype=float)) @ start[:3, :3]
        q_next, status = ik.solve(T, q)
        if int(status) < 0 or np.any(np.abs(q_next - q) > max_step):
            return False
        if not pose_reached(dyn, q_next, T):
            return False
        J = dyn.jacobian(q_next)
        J = np.vstack([J[:3], J[3:] * length])
        sv = np.linalg.svd(J, compute_uv=False)
        if sv[min(J.shape) - 1] < 0.02 * sv[0]:
            return False
        if probe is not None:
            probe.at(q_next)
            if probe.floor_clearance() < clearance:
                return False
        q = q_next
    return True


def _angle(R: np.ndarray) -> float:
    """Rotation angle of R [rad]."""
    s = 0.5 * np.linalg.norm([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]])
    return float(np.arctan2(s, (np.trace(R) - 1.0) / 2.0))


def reachable_motion(model, q0, d, r) -> tuple[np.ndarray, np.ndarray]:
    """(d, r) as given for a chain of 6 joints or more; for fewer, the part of the twist [d; r]
    the chain can make at q0 (projected onto its Jacobian's range, rotations weighed by the tool's
    distance from the root), scaled back to d's length: a 5-joint arm's tool moves in 5 of the 6
    pose dimensions, so a line in an arbitrary direction and rotation leaves its reach."""
    if model.nq >= 6:
        return d, r
    dyn = kl.Dynamics(model)
    length = max(float(np.linalg.norm(dyn.forward_kinematics(q0)[:3, 3])), 1e-3)
    J = dyn.jacobian(q0)
    J = np.vstack([J[:3], J[3:] * length])
    twist = J @ np.linalg.lstsq(J, np.concatenate([d, r * length]), rcond=1e-9)[0]
    d_made, r_made = twist[:3], twist[3:] / length
    scale = np.linalg.norm(d) / max(float(np.linalg.norm(d_made)), 1e-12)
    return d_made * scale, r_made * scale


def line_target(rig, q0, duration: float) -> tuple[np.ndarray, np.ndarray]:
    """(displacement [m], rotation vector [rad]) of a derived Cartesian line from the pose at q0:
    LINE_LENGTH of the reach along the first feasible LINE_DIRECTIONS entry, LINE_ROTATION about
    the first feasible axis (halved up to twice when nothing is feasible); for an arm of fewer
    than 6 joints, the part of each the arm can make (reachable_motion), and no rotation last."""
    probe = PoseProbe(rig.plant)
    length = LINE_LENGTH * probe.reach
    for scale in (1.0, 0.5, 0.25):
        for direction in LINE_DIRECTIONS:
            d = np.asarray(direction, dtype=float)
            d = scale * length * d / np.linalg.norm(d)
            # Fewer than 6 joints: a pure translation last (the rotation may need what is missing).
            for axis in LINE_ROTATION_AXES + (() if rig.model.nq >= 6 else ([0.0, 0.0, 0.0],)):
                r = scale * LINE_ROTATION * np.asarray(axis, dtype=float) / (
                    np.linalg.norm(axis) or 1.0)
                d_made, r_made = reachable_motion(rig.model, q0, d, r)
                if line_feasible(rig.model, q0, d_made, r_made, duration, probe=probe):
                    return d_made, r_made
    raise InputError(f"{rig.robot.name}: no feasible Cartesian line from the work pose")


def link_capsules(robot, model) -> list:
    """Collision capsules of the chain's links (and of what is folded onto them) for planning: the
    robot file's [collision] capsules when it gives them, else capsules bounding the URDF's
    collision primitives and capsules fitted to its collision meshes (kiloloop.meshes)."""
    given = robot.section("collision").get("capsules", {})
    capsules = []
    for link, rows in given.items():
        for row in rows:
            if len(row) != 7:
                raise InputError(f"{robot.path}: collision.capsules.{link}: expected "
                                 f"[x0, y0, z0, x1, y1, z1, radius] per capsule")
            c = kl.LinkCapsule()
            c.link, c.a, c.b, c.radius = link, np.array(row[:3]), np.array(row[3:6]), row[6]
            capsules.append(c)
    if given:
        return capsules
    from ..meshes import capsules_for_urdf

    # Mesh collisions (every real arm's): one capsule fitted around each mesh's vertices.
    fitted = capsules_for_urdf(str(robot.urdf), robot.package_dirs)
    return list(kl.capsules_from_urdf(str(robot.urdf), model, fitted or None))
