"""arm-press: the UR5 presses on a table with 10 N while sliding 10 cm along x.

Hybrid force/position control (C++): z is force-controlled (the wrench the tool applies on the
table, from a MuJoCo force sensor between the tool tip and the flange), x, y and the orientation
are motion-controlled (selection matrix diag(1, 1, 0, 1, 1, 1) in the world frame). The tool tip
is a 1 cm sphere 3 cm below the flange, starting 1 mm above the table; after `settle` seconds the
reference slides 10 cm along x on a quintic, with the table's Coulomb friction opposing it.
`--set controller=impedance` runs the Cartesian impedance controller instead, with the reference
pushed 10 N / K_z below the surface (no force feedback): for comparison.
"""
from __future__ import annotations

import mujoco
import numpy as np

import kiloloop as kl

from ..sil import arm_scene
from ..sil.log import SignalLog
from ..sil.loop import LoopSettings, Measurement, run_loop
from ..sil.plant import MujocoPlant
from . import ScenarioResult, evaluate

NAME = "arm-press"
DESCRIPTION = "UR5 presses a table with 10 N while sliding 10 cm along x (hybrid force/position)"
DURATION = 3.5  # [s]
DEFAULTS = {
    "controller": "hybrid",         # or "impedance"
    "q0": [0.0, -1.2, 1.6, -1.97, -1.57, 0.0],   # [rad] tool pointing down above the table
    "force": 10.0,                  # [N] pressing force (downwards)
    "slide": 0.10,                  # [m] along +x
    "settle": 0.5,                  # [s] before the slide starts (contact is made and settles)
    "slide_time": 2.0,              # [s]
    "gap": 0.001,                   # [m] tip above the table at the start
    "friction": 0.5,                # Coulomb friction tip-table
    # Table contact softness (MuJoCo solref / solimp; [] = MuJoCo's default). The impedance
    # ramps from 0.5 at the surface to 0.95 at 5 mm, so the contact force grows with penetration
    # (about 1 mm at 10 N: a compliant tool tip). With MuJoCo's default solimp the contact holds
    # 10 N at a few micrometres whatever the depth, the sliding tip creeps out of it and the
    # contact drops out for single steps every ~40 ms (0 N, then ~13 N): see bench/RESULTS.md.
    "solref": [],
    "solimp": [0.5, 0.95, 0.005, 0.5, 2.0],
    "noslip_iterations": 0,         # MuJoCo's no-slip post-processing of friction
    "cone": "elliptic",             # MuJoCo friction cone: "elliptic" or "pyramidal"
    "measure_from": 0.4,            # [s] criteria hold from here on ("after settling")
    # Force-loop gains on the force-controlled axis (z); empty: HybridForcePositionConfig's.
    "kf": [],                       # [-]
    "ki": [],                       # [1/s]
    "kv": [],                       # [N s/m]
    "project_motion_wrench": True,  # HybridForcePositionConfig.project_motion_wrench
}
CRITERIA = {
    "max_force_error_N": ("<", 0.5),
    "max_x_error_m": ("<", 0.002),
    "slide_m": (">", 0.0999),
}


def _quintic(s):
    """Rest-to-rest blend on s in [0, 1]: value, first and second derivative w.r.t. s."""
    s = min(max(s, 0.0), 1.0)
    return (10 * s**3 - 15 * s**4 + 6 * s**5, 30 * s**2 - 60 * s**3 + 30 * s**4,
            60 * s - 180 * s**2 + 120 * s**3)


class PressTick:
    """Maps measurement, force sensor and the slide reference onto the controller (glue only)."""

    def __init__(self, controller, plant, tip, p0, R0, settings):
        self.c, self.plant, self.tip, self.settings = controller, plant, tip, settings
        self.input, self.output = controller.make_input(), controller.make_output()
        self.p0 = p0
        self.input.R_ref = R0
        self.input.wrench_ref = np.array([0.0, 0.0, -settings["force"], 0.0, 0.0, 0.0])

    def reference(self, t):
        st = self.settings
        s, ds, dds = _quintic((t - st["settle"]) / st["slide_time"])
        T = st["slide_time"]
        return (self.p0[0] + st["slide"] * s, st["slide"] * ds / T, st["slide"] * dds / T**2)

    def __call__(self, m: Measurement, log: SignalLog) -> np.ndarray:
        inp = self.input
        inp.t, inp.stamp = m.t, m.stamp
        inp.q[:], inp.qd[:] = m.q, m.qd
        x, xd, xdd = self.reference(m.t)
        inp.p_ref[:] = [x, self.p0[1], self.p0[2]]
        inp.twist_ref[0], inp.accel_ref[0] = xd, xdd
        force = arm_scene.tip_force_world(self.plant, self.tip)  # sampled with q (same stamp)
        inp.wrench_measured[:3] = force
        status = self.c.step(inp, self.output)
        log.record("x_ref", x)
        log.record("force", force)
        log.record("tau", self.output.tau)
        log.record("status", int(status))
        return self.output.tau.copy()


_CONES = {"elliptic": mujoco.mjtCone.mjCONE_ELLIPTIC, "pyramidal": mujoco.mjtCone.mjCONE_PYRAMIDAL}


def _make_controller(model, settings):
    if settings["controller"] == "hybrid":
        config = kl.HybridForcePositionConfig()
        config.project_motion_wrench = bool(settings["project_motion_wrench"])
        for key in ("kf", "ki", "kv"):
            if len(settings[key]):
                gains = np.array(getattr(config, key))
                gains[2] = float(settings[key][0])  # the z (force) axis
                setattr(config, key, gains)
        return kl.HybridForcePositionController(model, config)
    if settings["controller"] == "impedance":
        return kl.CartesianImpedanceController(model)
    raise ValueError(f"controller: expected 'hybrid' or 'impedance', got {settings['controller']!r}")


def run(settings: dict, seed: int = 0, duration: float | None = None) -> ScenarioResult:
    del seed  # deterministic
    urdf, overlay = kl.model_files("ur5")
    model = kl.RobotModel.from_urdf(str(urdf))
    q0 = np.asarray(settings["q0"], dtype=float)
    tip = arm_scene.ToolTip(friction=settings["friction"])
    # Where the tip starts decides where the table goes: its top `gap` below the tip sphere.
    probe = MujocoPlant(urdf, overlay, scene=tip)
    probe.reset(q0)
    tip_z = probe.data.xpos[probe.model.body(tip.body).id][2] - tip.radius
    top = tip_z - settings["gap"]
    p_ee0 = probe.ee_pose()[0]

    def scene(spec):
        spec.option.cone = _CONES[settings["cone"]]
        spec.option.noslip_iterations = int(settings["noslip_iterations"])
        tip(spec)
        arm_scene.add_table(spec, "table", [p_ee0[0], p_ee0[1], top], [0.4, 0.4],
                            friction=settings["friction"],
                            solref=settings["solref"] or None, solimp=settings["solimp"] or None)

    plant = MujocoPlant(urdf, overlay, scene=scene)
    plant.reset(q0)
    controller = _make_controller(model, settings)
    T0 = kl.Dynamics(model).forward_kinematics(q0)
    p0, R0 = T0[:3, 3].copy(), T0[:3, :3].copy()
    if settings["controller"] == "impedance":
        # No force loop: the spring alone presses, its set point F / K_z below the surface.
        k_z = kl.CartesianImpedanceConfig().stiffness[2]
        p0 = p0 - np.array([0.0, 0.0, settings["gap"] + settings["force"] / k_z])
    tick = PressTick(controller, plant, tip, p0, R0, settings)

    def observe(p: MujocoPlant, log: SignalLog) -> None:
        log.record("ee", p.ee_pose()[0])

    log = run_loop(plant, tick, LoopSettings(duration=DURATION if duration is None else duration),
                   observe=observe)
    t = log["t"]
    after = t >= settings["measure_from"]
    fz = -log["force"][:, 2]  # pressing force, positive down
    x_err = log["x_ref"] - log["ee"][:, 0]
    metrics = {
        "max_force_error_N": float(np.abs(fz[after] - settings["force"]).max()),
        "rms_force_error_N": float(np.sqrt(np.mean((fz[after] - settings["force"]) ** 2))),
        "mean_force_N": float(fz[after].mean()),
        "max_x_error_m": float(np.abs(x_err[after]).max()),
        "slide_m": float(log["ee"][-1, 0] - log["ee"][0, 0]),
        "max_tangential_force_N": float(np.abs(log["force"][after][:, :2]).max()),
        "failed_ticks": int(np.sum(log["status"] < 0)),
        "saturated_ticks": int(np.sum(log["status"] == int(kl.Status.SATURATED))),
        "ticks": int(len(t)),
    }
    log.put("force_z", fz)
    log.put("x_err_mm", x_err * 1e3)
    return ScenarioResult(NAME, metrics, evaluate(CRITERIA, metrics), log, dict(settings))


def plot_signals():
    return [("pressing force (MuJoCo sensor)", "force_z", None, "N"),
            ("x error", "x_err_mm", None, "mm"),
            ("joint torque", "tau", None, "N m")]
