"""`kiloloop bench`: the C++ core benchmark (ours vs raw KDL) plus SIL timing figures.

The per-call latencies come from the compiled `kiloloop_bench_core` program installed with the
package (timing in C++, allocation counting in its own process); this module runs it, then
measures the SIL loop in Python: real-time factor of arm-track and the cost of one SIL tick
relative to one raw `mj_step` of the same MuJoCo model.
"""
from __future__ import annotations

import json
import platform
import subprocess
import sys
import time
from importlib.resources import files
from pathlib import Path

import mujoco
import numpy as np

import kiloloop as kl


def core_benchmark(quick: bool) -> dict:
    exe = Path(str(files("kiloloop") / "bin" / "kiloloop_bench_core"))
    urdf = kl.models_dir() / "ur5" / "ur5.urdf"
    quadruped = kl.models_dir() / "quadruped" / "quadruped.urdf"
    cmd = [str(exe), str(urdf), "--quadruped", str(quadruped), "--json"] + (["--quick"] if quick else [])
    out = subprocess.run(cmd, check=True, capture_output=True, text=True)
    return json.loads(out.stdout)


def _raw_mj_step_seconds(plant, steps: int) -> float:
    """Per-step cost of plain mj_step on the plant's model, holding the last torques."""
    model, data = plant.model, mujoco.MjData(plant.model)
    data.qpos[:] = plant.data.qpos
    data.ctrl[:] = plant.data.ctrl
    mujoco.mj_forward(model, data)
    start = time.perf_counter()
    for _ in range(steps):
        mujoco.mj_step(model, data)
    return (time.perf_counter() - start) / steps


def _python_step_seconds(calls: int) -> float:
    """Cost of one ComputedTorqueController.step call through the bindings (UR5)."""
    model = kl.RobotModel.from_urdf(str(kl.models_dir() / "ur5" / "ur5.urdf"))
    ctrl = kl.ComputedTorqueController(model)
    inp, out = ctrl.make_input(), ctrl.make_output()
    inp.q[:] = [0.0, -1.57, 1.57, -1.57, -1.57, 0.0]
    inp.q_ref[:] = inp.q + 0.01
    step = ctrl.step
    start = time.perf_counter()
    for _ in range(calls):
        step(inp, out)
    return (time.perf_counter() - start) / calls


def sil_benchmark(quick: bool, robot=None) -> dict:
    """arm-track on an arm robot file (default: kiloloop's UR5): whole scenario, bare loop, and
    the raw mj_step it costs."""
    from .. import scenarios
    from ..scenarios import arm_track
    from ..scenarios.arm_controllers import controller
    from ..sil.arm_adapters import JointTracking
    from ..sil.rig import Rig

    duration = 1.0 if quick else arm_track.DURATION
    robot_obj, settings = scenarios.prepare(arm_track, robot)
    start = time.perf_counter()
    result = scenarios.run(arm_track, settings, robot_obj, duration=duration)
    wall = time.perf_counter() - start
    ticks = result.metrics["ticks"]

    # The same loop without scenario set-up (URDF load, MjSpec compile) and post-processing.
    rig = Rig(robot_obj)
    plant = rig.plant
    raw_step = _raw_mj_step_seconds(plant, ticks)
    s = result.settings
    points = np.vstack([s["q_start"], s["waypoint_1"], s["waypoint_2"]])
    plant.q0 = points[0]
    plant.reset()
    traj = kl.QuinticTrajectory(points, np.array([0.0, s["t_1"], s["t_2"]]))
    reference = JointTracking(controller(robot_obj, rig.model, "computed_torque", points[0]), traj)
    start = time.perf_counter()
    rig.run(duration, reference)
    loop_wall = time.perf_counter() - start
    tick_cost = loop_wall / ticks
    # Tracking figures of both joint controllers on the same trajectory (full duration).
    tracking = {}
    for controller in ("computed_torque", "pd_gravity"):
        r = scenarios.run_named("arm-track", robot_obj, {"controller": controller})
        tracking[controller] = {k: r.metrics[k] for k in ("max_joint_error_rad", "max_ee_error_m")}
    return {
        "scenario": "arm-track",
        "robot": robot_obj.name,
        "tracking": tracking,
        "sim_seconds": duration,
        "ticks": ticks,
        "physics_dt": plant.timestep,
        "scenario_wall_s": wall,
        "real_time_factor_scenario": duration / wall,
        "real_time_factor_loop": duration / loop_wall,
        "tick_cost_us": tick_cost * 1e6,
        "raw_mj_step_us": raw_step * 1e6,
        "tick_over_mj_step": tick_cost / raw_step,
        "python_controller_step_us": _python_step_seconds(20000 if quick else 100000) * 1e6,
    }


def rig_sil_timing(scenario: str, rig, command, quick: bool, **run_kwargs) -> dict:
    """Runs a SIL rig for a few simulated seconds, Python's set-up of the run included: real-time
    factor, tick cost against one raw mj_step of the same model (both wall clock; the native
    bench has CPU-time figures of the loop alone), and the rig's controller's step called from
    Python. run_kwargs go to rig.run."""
    duration = 2.0 if quick else 10.0
    start = time.perf_counter()
    log = rig.run(duration, command, **run_kwargs)
    wall = time.perf_counter() - start
    ticks = len(log["t"])
    raw = _raw_mj_step_seconds(rig.plant, ticks)
    controller = rig.controller
    if hasattr(controller, "make_input"):
        inp, out = controller.make_input(), controller.make_output()
    else:
        inp, out = kl.QuadrupedInput(), kl.QuadrupedOutput()
    calls = 2000 if quick else 20000
    start = time.perf_counter()
    for k in range(calls):
        inp.t = inp.stamp = k * 0.001
        controller.step(inp, out)
    step_py = (time.perf_counter() - start) / calls
    return {"scenario": scenario, "sim_seconds": duration, "ticks": ticks,
            "physics_dt": rig.plant.timestep, "real_time_factor": duration / wall,
            "tick_cost_us": wall / ticks * 1e6, "raw_mj_step_us": raw * 1e6,
            "tick_over_mj_step": (wall / ticks) / raw, "python_controller_step_us": step_py * 1e6}


def quadruped_sil_benchmark(quick: bool) -> dict:
    """Real-time factor of quadruped-trot (non-idealities on) through the rig and its tick cost
    vs raw mj_step."""
    from ..scenarios import parse_settings, quadruped_trot
    from ..scenarios.quadruped_settings import rig_from_settings

    settings = parse_settings(quadruped_trot.DEFAULTS, None)
    rig = rig_from_settings(settings, seed=0)
    return rig_sil_timing("quadruped-trot", rig, quadruped_trot.trot_command(settings["speed"]), quick)


def _print_core(core: dict) -> None:
    m = core["machine"]
    print(f"C++ core, UR5, {core['calls']} calls each  [{m['cpu']}, {m['nproc']} cores, "
          f"{m['compiler']}, {m['build']}]")
    print(f"  {'call':<28}{'median':>8}{'p99':>8}{'max':>9}{'alloc':>7}   "
          f"{'raw KDL':<24}{'median':>8}{'p99':>8}{'ratio':>7}")
    for r in core["results"]:
        raw = r.get("raw_name")
        tail = (f"{raw:<24}{r['raw_median_ns']:>8}{r['raw_p99_ns']:>8}{r['ratio_median']:>7.2f}"
                if raw else "")
        print(f"  {r['name']:<28}{r['median_ns']:>8}{r['p99_ns']:>8}{r['max_ns']:>9}"
              f"{r['allocations_per_call']:>7.2f}   {tail}")
    print("  times in ns; ratio = ours/raw medians (goal <= 1.2); alloc = heap allocations per call")


def _print_sil(sil: dict) -> None:
    print(f"SIL {sil['scenario']} ({sil['sim_seconds']} s simulated, {sil['ticks']} ticks, "
          f"physics dt {sil['physics_dt'] * 1e3:g} ms)")
    print(f"  real-time factor, whole scenario   {sil['real_time_factor_scenario']:8.1f} x")
    print(f"  real-time factor, loop only        {sil['real_time_factor_loop']:8.1f} x")
    print(f"  SIL tick cost                      {sil['tick_cost_us']:8.1f} us")
    print(f"  raw mj_step cost                   {sil['raw_mj_step_us']:8.1f} us")
    print(f"  SIL tick / raw mj_step             {sil['tick_over_mj_step']:8.2f}")
    print(f"  controller step via Python         {sil['python_controller_step_us']:8.2f} us")
    print(f"  arm-track tracking ({arm_track_duration()} s):   max joint error    max EE error")
    for controller, m in sil["tracking"].items():
        print(f"    {controller:<30} {m['max_joint_error_rad']:10.3e} rad {m['max_ee_error_m'] * 1e3:9.4f} mm")


def arm_track_duration() -> float:
    from ..scenarios import arm_track

    return arm_track.DURATION


def print_rig_sil(q: dict) -> None:
    print(f"SIL {q['scenario']} ({q['sim_seconds']} s simulated, non-idealities on, physics dt "
          f"{q['physics_dt'] * 1e3:g} ms)")
    print(f"  real-time factor                   {q['real_time_factor']:8.1f} x")
    print(f"  SIL tick cost                      {q['tick_cost_us']:8.1f} us")
    print(f"  raw mj_step cost                   {q['raw_mj_step_us']:8.1f} us")
    print(f"  SIL tick / raw mj_step             {q['tick_over_mj_step']:8.2f}")
    print(f"  controller step via Python         {q['python_controller_step_us']:8.2f} us")


def run_benchmarks(quick: bool = False, as_json: bool = False, robot=None) -> int:
    """Every benchmark; with `robot` (an arm robot file) only the SIL loop and tracking on it."""
    if robot is not None:
        return _robot_benchmark(robot, quick, as_json)
    from .aerial_bench import print_aerial_bench, run_aerial_bench
    from .arm_bench import print_arm_bench, run_arm_bench
    from .calibration_bench import print_calibration_bench, run_calibration_bench
    from .ik_bench import print_ik_bench, run_ik_bench
    from .native_bench import print_native_bench, run_native_bench
    from .qp_bench import print_qp_bench, run_qp_bench

    core = core_benchmark(quick)
    sil = sil_benchmark(quick)
    sil_native = run_native_bench(quick)
    quadruped = quadruped_sil_benchmark(quick)
    qp = run_qp_bench(quick)
    limits = None if quick else quadruped_limits()
    ik = run_ik_bench(quick)
    arm = run_arm_bench(quick)
    aerial = run_aerial_bench(quick)
    calibration = run_calibration_bench()
    report = {"python": sys.version.split()[0], "platform": platform.platform(),
              "mujoco": mujoco.__version__, "kiloloop": kl.__version__, "core": core, "sil": sil,
              "sil_native": sil_native, "quadruped_sil": quadruped, "qp": qp, "quadruped_limits": limits, "ik": ik,
              "calibration": calibration, "arm": arm, "aerial": aerial}
    if as_json:
        # numpy scalars (from the peers' results) print as plain numbers
        print(json.dumps(report, default=lambda o: o.item() if hasattr(o, "item") else str(o)))
    else:
        _print_core(core)
        print()
        _print_sil(sil)
        print()
        print_native_bench(sil_native)
        print()
        print_rig_sil(quadruped)
        print()
        print_qp_bench(qp)
        if limits is not None:
            print()
            _print_limits(limits)
        print()
        print_ik_bench(ik)
        print()
        print_calibration_bench(calibration)
        print()
        print_arm_bench(arm)
        print()
        print_aerial_bench(aerial)
    return 0


def quadruped_limits() -> dict:
    """Highest trot speed passing quadruped-trot, largest push recovered / survived."""
    from ..scenarios import quadruped_push, quadruped_trot

    return {"trot": quadruped_trot.max_passing_speed(speeds=(0.5, 0.75, 1.0, 1.25)),
            "push": quadruped_push.max_recovered_impulse()}


def _print_limits(limits: dict) -> None:
    trot, push = limits["trot"], limits["push"]
    print("Quadruped limits (scenario criteria, non-idealities on)")
    seeds = ", ".join(str(k) for k in next(iter(trot["runs"].values()))["seeds"])
    print(f"  highest trot speed passing quadruped-trot   {trot['max_passing_speed']:.2f} m/s   (goal >= 1 m/s; seeds {seeds})")
    for speed, r in trot["runs"].items():
        print(f"    {float(speed):5.2f} m/s  passed={r['passed']!s:<5}  fell={r['fell']:.0f}  "
              f"roll/pitch RMS {r['roll_pitch_rms_deg']:.2f} deg  velocity RMS error {r['velocity_rms_error']:.3f} m/s  (worst seed)")
    seeds = ", ".join(str(k) for k in next(iter(push["runs"].values()))["seeds"])
    print(f"  largest push passing quadruped-push         {push['max_recovered_impulse']:.1f} N s   (goal >= 12 N s; seeds {seeds})")
    print(f"  largest push survived (no fall)             {push['max_survived_impulse']:.1f} N s")
    for impulse, r in push["runs"].items():
        print(f"    {float(impulse):5.1f} N s  passed={r['passed']!s:<5}  fell={r['fell']:.0f}  "
              f"roll peak {r['roll_peak_deg']:.2f} deg  roll after 0.8 s {r['roll_after_recovery_deg']:.2f} deg  (worst seed)")


def _robot_benchmark(robot, quick: bool, as_json: bool) -> int:
    from ..robot import Robot

    r = Robot.load(robot)
    if r.kind != "arm":
        print(f"kiloloop bench --robot: only arm robot files so far ({r.name} is {r.kind})",
              file=sys.stderr)
        return 2
    from .native_bench import print_native_bench, run_native_bench

    sil = sil_benchmark(quick, r)
    sil_native = run_native_bench(quick, r)
    if as_json:
        print(json.dumps({"robot": r.name, "sil": sil, "sil_native": sil_native}))
    else:
        _print_sil(sil)
        print()
        print_native_bench(sil_native)
    return 0
