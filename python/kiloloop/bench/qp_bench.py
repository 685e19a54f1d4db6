"""QP benchmark: kl.qp against quadprog, DAQP, OSQP and proxsuite on quadruped stance-force QPs.

The problems are a synthetic 1 kHz trot (a problem family for timing, not a robot model): 12
contact forces f (3 per foot), feet near (+-0.2, +-0.15, -0.3) m from the CoM, mass about 17 kg;

    minimize  1/2 |A f - w|^2_S + 1/2 alpha |f|^2 + 1/2 beta |f - f_prev|^2
    H = A'SA + (alpha + beta) I,   g = -A'S w - beta f_prev          (12 x 12)
    friction pyramid |fx|, |fy| <= mu fz (16 rows C f <= 0), mu = 0.8
    stance feet: fz_min <= fz <= fz_max, |fx|, |fy| <= mu fz_max; swing feet: lb = ub = 0 (bounds)

A = [I I I I; [p_1]x ... [p_4]x] maps forces to the CoM wrench, w is the desired wrench
[m a; m (g + a_z); torques] with smooth motion plus noise, f_prev the previous tick's solution, and
diagonal pairs of feet swing in turn with short four-foot phases between them.

Every solver gets every problem in its own input convention (prepared before timing), and each
tick calls them in a seeded random order from Python, timing each call with perf_counter_ns:
  ours (warm)   kl.qp.DenseQpSolver(warm_start=True).solve, one solver for the whole run
  ours (cold)   the same with warm_start=False
  ours C++      kl.qp._time_solves(repeats=1): a fresh solver's first solve, timed in C++
                (steady_clock around DenseQpSolver::solve, no Python inside)
  quadprog      quadprog.solve_qp (swing forces as equalities, stance bounds as rows; the swing
                feet's friction rows are left out: with them quadprog reports many of these
                degenerate problems inconsistent, counted separately)
  daqp          daqp.solve (bounds as simple bounds, swing ones with sense 5 = equality)
  osqp          set up once; per tick update(Px, q, l, u) + solve, warm-started; eps 1e-9,
                polishing on, termination checked every iteration
  proxsuite     dense QP set up once; per tick update(...) + solve from its default initial
                guess (warm-started from the previous result it misreports some problems as
                primal infeasible, counted separately); eps_abs 1e-9; rows' lower bounds -1e20
Each peer's objective 1/2 x'Hx + g'x is checked against ours (relative 1e-6). Where a solver
reports its own time (daqp, OSQP, proxsuite), that C-level figure is listed too, next to ours C++.
"""
from __future__ import annotations

import argparse
import contextlib
import json
import os
import platform
import sys
import time
from importlib import metadata

import numpy as np

import kiloloop as kl

MU = 0.8
FZ_MIN, FZ_MAX = 10.0, 250.0  # [N]
MASS = 17.0  # [kg] nominal; each run draws a payload within +-1 kg
GRAVITY = 9.81
FEET = np.array([[0.2, 0.15, -0.3], [0.2, -0.15, -0.3], [-0.2, 0.15, -0.3], [-0.2, -0.15, -0.3]])
S_WEIGHTS = np.array([1.0, 1.0, 1.0, 10.0, 10.0, 10.0])  # force [1/N^2], torque [1/(N m)^2]
ALPHA, BETA = 1e-3, 1e-2
OBJ_RTOL = 1e-6
SEED = 2024


def _skew(p):
    return np.array([[0.0, -p[2], p[1]], [p[2], 0.0, -p[0]], [-p[1], p[0], 0.0]])


def _friction_rows():
    """(16, 12): +-fx - mu fz <= 0, +-fy - mu fz <= 0 per foot."""
    C = np.zeros((16, 12))
    for foot in range(4):
        for k, (axis, sign) in enumerate([(0, 1.0), (0, -1.0), (1, 1.0), (1, -1.0)]):
            C[4 * foot + k, 3 * foot + axis] = sign
            C[4 * foot + k, 3 * foot + 2] = -MU
    return C


def _swing_feet(tick):
    """Trot: FL+RR, then FR+RL swing for 150 ticks each, four feet down for 20 between."""
    phase = tick % 340
    if phase < 20 or 170 <= phase < 190:
        return ()
    return (0, 3) if phase < 170 else (1, 2)


def stance_problems(ticks: int, seed: int = SEED) -> list[dict]:
    """A seeded sequence of stance-force QPs; f_prev is our previous solution."""
    rng = np.random.default_rng(seed)
    mass = MASS + rng.uniform(-1.0, 1.0)
    C = _friction_rows()
    problems, f_prev = [], np.tile([0.0, 0.0, mass * GRAVITY / 4], 4)
    for tick in range(ticks):
        t = tick * 1e-3
        feet = FEET + np.array([-0.05 * np.sin(2 * np.pi * 1.5 * t), 0.0, 0.0])
        feet = feet + 0.005 * rng.standard_normal(feet.shape)
        A = np.zeros((6, 12))
        for i in range(4):
            A[:3, 3 * i:3 * i + 3] = np.eye(3)
            A[3:, 3 * i:3 * i + 3] = _skew(feet[i])
        # Brisk motion: lateral pushes and body torques large enough that friction and fz limits
        # bind on some ticks.
        acc = np.array([3.0 * np.sin(2 * np.pi * t), 4.0 * np.cos(2 * np.pi * 0.7 * t), 0.0])
        acc = acc + 1.0 * rng.standard_normal(3)
        torque = np.array([8.0 * np.sin(2 * np.pi * 2 * t), 6.0 * np.cos(2 * np.pi * 1.3 * t), 2.0])
        torque = torque + 2.0 * rng.standard_normal(3)
        w = np.concatenate([mass * (acc + [0.0, 0.0, GRAVITY]), torque])
        AtS = A.T * S_WEIGHTS
        H = AtS @ A + (ALPHA + BETA) * np.eye(12)
        H = 0.5 * (H + H.T)
        g = -AtS @ w - BETA * f_prev
        lb = np.tile([-MU * FZ_MAX, -MU * FZ_MAX, FZ_MIN], 4)
        ub = np.tile([MU * FZ_MAX, MU * FZ_MAX, FZ_MAX], 4)
        swing = _swing_feet(tick)
        for i in swing:
            lb[3 * i:3 * i + 3] = ub[3 * i:3 * i + 3] = 0.0
        p = dict(H=H, g=g, C=C, d=np.zeros(16), lb=lb, ub=ub, swing=swing)
        res = kl.qp.solve(H, g, C=C, d=p["d"], lb=lb, ub=ub)
        if res.status != kl.qp.QpStatus.OPTIMAL:
            raise RuntimeError(f"stance problem {tick} not solved: {res.status}")
        f_prev = res.x
        problems.append(p)
    return problems


def _objective(p, x):
    return 0.5 * x @ p["H"] @ x + p["g"] @ x


def _violation(p, x):
    return max(0.0, (p["C"] @ x - p["d"]).max(), (p["lb"] - x).max(), (x - p["ub"]).max())


# --- one adapter per solver: prepare(p) -> args (untimed), call(args) -> x or None (timed) --------

class _Ours:
    def __init__(self, warm):
        self.name = "ours (warm)" if warm else "ours (cold)"
        self.how = f"DenseQpSolver(warm_start={warm}).solve from Python"
        self.solver = kl.qp.DenseQpSolver(12, 0, 16, warm_start=warm)
        self.iterations = []

    def prepare(self, p):
        return (p["H"], p["g"], p["C"], p["d"], p["lb"], p["ub"])

    def call(self, a):
        res = self.solver.solve(a[0], a[1], None, None, a[2], a[3], a[4], a[5])
        self.iterations.append(res.iterations)
        return res.x if res.status == kl.qp.QpStatus.OPTIMAL else None


class _OursCpp:
    """One cold solve timed inside C++ (its own clock); the Python-side time is not used."""
    name, how = "ours C++", "a fresh solver's first solve, timed in C++ around DenseQpSolver::solve"

    def __init__(self):
        self.own_ns = []

    def prepare(self, p):
        return (p["H"], p["g"], None, None, p["C"], p["d"], p["lb"], p["ub"])

    def call(self, a):
        self.own_ns.append(int(kl.qp._time_solves(*a, repeats=1, warm_start=False)[0]))
        return None


class _Quadprog:
    name, how = ("quadprog", "solve_qp(G, a, C, b, meq): swing forces as equalities, stance bounds "
                 "as rows, swing feet's friction rows left out (implied by f = 0)")

    def __init__(self):
        import quadprog

        self.solve_qp = quadprog.solve_qp

    @staticmethod
    def full_form(p):
        """Every friction row kept: degenerate at the swing feet (0 <= 0 with f = 0)."""
        eye = np.eye(12)
        fixed, free = np.flatnonzero(p["lb"] == p["ub"]), np.flatnonzero(p["lb"] != p["ub"])
        Cq = np.hstack([eye[:, fixed], -p["C"].T, eye[:, free], -eye[:, free]])
        bq = np.concatenate([p["lb"][fixed], -p["d"], p["lb"][free], -p["ub"][free]])
        return (p["H"], -p["g"], Cq, bq, len(fixed))

    def prepare(self, p):
        eye = np.eye(12)
        fixed, free = np.flatnonzero(p["lb"] == p["ub"]), np.flatnonzero(p["lb"] != p["ub"])
        rows = [4 * foot + k for foot in range(4) if foot not in p["swing"] for k in range(4)]
        Cq = np.hstack([eye[:, fixed], -p["C"][rows].T, eye[:, free], -eye[:, free]])
        bq = np.concatenate([p["lb"][fixed], -p["d"][rows], p["lb"][free], -p["ub"][free]])
        return (p["H"], -p["g"], Cq, bq, len(fixed))

    def call(self, a):
        try:
            return self.solve_qp(*a)[0]
        except ValueError:  # "constraints are inconsistent, no solution"
            return None


class _Daqp:
    name, how = "daqp", "daqp.solve(H, f, A, bupper, blower, sense): swing bounds with sense 5 (equality)"

    def __init__(self):
        import daqp

        self.solve = daqp.solve
        self.own_ns = []

    def prepare(self, p):
        bupper = np.concatenate([p["ub"], p["d"]])
        blower = np.concatenate([p["lb"], np.full(16, -1e30)])
        sense = np.zeros(28, dtype=np.int32)
        sense[:12][p["lb"] == p["ub"]] = 5
        return (p["H"], p["g"], np.ascontiguousarray(p["C"]), bupper, blower, sense)

    def call(self, a):
        x, _, exitflag, info = self.solve(*a)
        self.own_ns.append(int(1e9 * (info["setup_time"] + info["solve_time"])))
        return np.asarray(x) if exitflag == 1 else None


class _Osqp:
    name, how = ("osqp", "set up once; per problem update(Px, q, l, u) + solve, warm-started; "
                 "eps_abs = eps_rel = 1e-9, polishing, check_termination = 1")

    def __init__(self, first):
        import osqp
        from scipy import sparse

        self.osqp = osqp
        rows, cols = np.triu_indices(12)
        order = np.lexsort((rows, cols))  # CSC order of the upper triangle: by column, then row
        self.triu = (rows[order], cols[order])
        P = sparse.csc_matrix((first["H"][self.triu], self.triu), shape=(12, 12))
        A = sparse.csc_matrix(np.vstack([first["C"], np.eye(12)]))
        self.own_ns = []
        self.solver = osqp.OSQP()
        self.solver.setup(P, first["g"], A, *self._bounds(first), eps_abs=1e-9, eps_rel=1e-9,
                          polishing=True, max_iter=100000, check_termination=1, verbose=False)

    @staticmethod
    def _bounds(p):
        return np.concatenate([np.full(16, -np.inf), p["lb"]]), np.concatenate([p["d"], p["ub"]])

    def prepare(self, p):
        lo, hi = self._bounds(p)
        return (p["H"][self.triu], p["g"], lo, hi)

    def call(self, a):
        self.solver.update(Px=a[0], q=a[1], l=a[2], u=a[3])
        r = self.solver.solve(raise_error=False)
        self.own_ns.append(int(1e9 * r.info.run_time))  # update + solve + polish
        return r.x if r.info.status_val == self.osqp.SolverStatus.OSQP_SOLVED else None


class _Proxsuite:
    name, how = ("proxsuite", "dense QP set up once; per problem update(...) + solve from its default "
                 "initial guess; eps_abs 1e-9, eps_rel 0; rows' lower bounds -1e20 (not -inf)")

    def __init__(self, first, warm=False):
        from proxsuite import proxqp

        self.proxqp = proxqp
        self.qp = proxqp.dense.QP(12, 0, 16, True)
        self.qp.settings.eps_abs = 1e-9
        self.qp.settings.eps_rel = 0.0
        self.qp.settings.verbose = False
        self.qp.settings.compute_timings = True
        self.qp.init(*self.prepare(first))
        self.own_ns = []
        if warm:
            self.qp.settings.initial_guess = proxqp.InitialGuess.WARM_START_WITH_PREVIOUS_RESULT

    def prepare(self, p):
        return (p["H"], p["g"], None, None, p["C"], np.full(16, -1e20), p["d"], p["lb"], p["ub"])

    def call(self, a):
        self.qp.update(*a)
        self.qp.solve()
        self.own_ns.append(int(1e3 * self.qp.results.info.run_time))  # [us]: update + solve
        ok = self.qp.results.info.status == self.proxqp.QPSolverOutput.PROXQP_SOLVED
        return self.qp.results.x.copy() if ok else None


def _pitfalls(problems, solvers):
    """Untimed: how often the forms not used above fail (quadprog with every friction row,
    proxsuite warm-started from its previous result)."""
    notes = {}
    names = {s.name for s in solvers}
    if "quadprog" in names:
        qp = _Quadprog()
        notes["quadprog_full_form_failures"] = sum(qp.call(qp.full_form(p)) is None for p in problems)
    if "proxsuite" in names:
        px = _Proxsuite(problems[0], warm=True)
        notes["proxsuite_warm_start_failures"] = sum(px.call(px.prepare(p)) is None for p in problems)
    return notes


def _version(package):
    try:
        return metadata.version(package)
    except metadata.PackageNotFoundError:
        return None


def _summary(ns):
    ns = np.sort(np.asarray(ns, dtype=np.int64))
    if len(ns) == 0:
        return {"median_us": None, "p99_us": None, "max_us": None}
    p99 = ns[min(len(ns) - 1, int(np.ceil(0.99 * len(ns))) - 1)]  # nearest rank
    return {"median_us": float(np.median(ns)) / 1e3, "p99_us": float(p99) / 1e3,
            "max_us": float(ns[-1]) / 1e3}


@contextlib.contextmanager
def _quiet_stdout():
    """Sends file descriptor 1 to /dev/null (C libraries print there), restoring it after."""
    sys.stdout.flush()
    saved = os.dup(1)
    devnull = os.open(os.devnull, os.O_WRONLY)
    try:
        os.dup2(devnull, 1)
        yield
    finally:
        os.dup2(saved, 1)
        os.close(saved)
        os.close(devnull)


def _timed_loop(problems, solvers, args, times, ref, checks):
    """Each problem: every solver once, in a seeded random order; then the agreement checks."""
    clock = time.perf_counter_ns
    rng = np.random.default_rng(SEED + 1)
    for k, p in enumerate(problems):
        # A fresh order each problem: whoever runs after a solver that evicts caches or lowers the
        # clock (AVX-512) is not always the same one.
        order = rng.permutation(len(solvers))
        xs = {}
        for i in order:
            s = solvers[i]
            t0 = clock()
            x = s.call(args[i][k])
            t1 = clock()
            times[s.name].append(t1 - t0)
            xs[s.name] = x
        f_ref = _objective(p, xs[ref.name])
        for s in solvers:
            if isinstance(s, _OursCpp):
                continue
            x, c = xs[s.name], checks[s.name]
            if x is None:
                c["failures"] += 1
                continue
            rel = abs(_objective(p, x) - f_ref) / max(1.0, abs(f_ref))
            c["max_rel_obj_diff"] = max(c["max_rel_obj_diff"], rel)
            c["max_violation"] = max(c["max_violation"], _violation(p, x))
            c["disagreements"] += rel > OBJ_RTOL


def run_qp_bench(quick: bool) -> dict:
    """Times every solver on the same seeded stance-force problems; see the module docstring."""
    ticks = 400 if quick else 4000
    problems = stance_problems(ticks)
    solvers, skipped = [_Ours(True), _Ours(False), _OursCpp()], {}
    peers = [("quadprog", "quadprog", lambda: _Quadprog()), ("daqp", "daqp", lambda: _Daqp()),
             ("osqp", "osqp", lambda: _Osqp(problems[0])),
             ("proxsuite", "proxsuite", lambda: _Proxsuite(problems[0]))]
    for name, package, make in peers:
        try:
            solvers.append(make())
        except ImportError as e:
            skipped[name] = str(e)
    args = [[s.prepare(p) for p in problems] for s in solvers]
    times = {s.name: [] for s in solvers}
    checks = {s.name: {"failures": 0, "disagreements": 0, "max_rel_obj_diff": 0.0,
                       "max_violation": 0.0} for s in solvers}
    ref = solvers[1]  # ours (cold): the objective every other solver is compared with
    with _quiet_stdout():  # OSQP's C code prints "Polishing not needed ..." on some problems
        _timed_loop(problems, solvers, args, times, ref, checks)
    results = []
    for s in solvers:
        row = {"name": s.name, "how": s.how, "samples": len(problems)}
        if isinstance(s, _OursCpp):
            row.update({"median_us": None, "p99_us": None, "max_us": None})
        else:
            row.update(_summary(times[s.name]))
            row.update(checks[s.name])
        own = getattr(s, "own_ns", None)
        row.update({"own_" + k: v for k, v in _summary(own).items()} if own else
                   {"own_median_us": None, "own_p99_us": None})
        results.append(row)
    iters = np.array(solvers[1].iterations)
    return {
        "problem": "quadruped stance forces: 12 variables, 16 friction rows, 24 bounds (trot)",
        "ticks": ticks, "seed": SEED, "obj_rtol": OBJ_RTOL,
        "iterations_cold": {"mean": float(iters.mean()), "max": int(iters.max())},
        "iterations_warm": {"mean": float(np.mean(solvers[0].iterations)),
                            "max": int(np.max(solvers[0].iterations))},
        "results": results, "skipped": skipped, "pitfalls": _pitfalls(problems, solvers),
        "versions": {pkg: _version(pkg) for pkg in ("quadprog", "daqp", "osqp", "proxsuite")},
        "kiloloop": kl.__version__, "python": platform.python_version(),
        "machine": {"cpu": platform.processor() or platform.machine(), "platform": platform.platform()},
    }


def print_qp_bench(report: dict) -> None:
    def us(v, width=9):
        return f"{v:>{width}.2f}" if v is not None else f"{'-':>{width}}"

    print(f"QP, {report['problem']}; {report['ticks']} problems, seed {report['seed']}")
    print(f"  {'':<14}{'called from Python':^27}{'own clock':^18}")
    print(f"  {'solver':<14}{'median':>9}{'p99':>9}{'max':>9}{'median':>9}{'p99':>9}{'fail':>6}"
          f"{'disagree':>10}{'max rel dobj':>14}{'max viol':>10}")
    for r in report["results"]:
        tail = ""
        if "failures" in r:
            tail = (f"{r['failures']:>6}{r['disagreements']:>10}{r['max_rel_obj_diff']:>14.1e}"
                    f"{r['max_violation']:>10.1e}")
        print(f"  {r['name']:<14}{us(r['median_us'])}{us(r['p99_us'])}{us(r['max_us'])}"
              f"{us(r['own_median_us'])}{us(r['own_p99_us'])}{tail}")
    w, c = report["iterations_warm"], report["iterations_cold"]
    print("  times in us per solve; own clock: the solver's own timer in C/C++ (daqp setup + solve, "
          "osqp run_time, proxsuite run_time, ours steady_clock around solve)")
    print(f"  objective checked against ours (cold), relative {report['obj_rtol']:g}; viol: largest "
          "constraint violation of the solver's x")
    print(f"  our active-set iterations: cold mean {c['mean']:.1f} (max {c['max']}), "
          f"warm mean {w['mean']:.1f} (max {w['max']})")
    for name, why in report["skipped"].items():
        print(f"  skipped {name}: {why}")
    notes = report["pitfalls"]
    if "quadprog_full_form_failures" in notes:
        print(f"  quadprog with the swing feet's friction rows kept: "
              f"{notes['quadprog_full_form_failures']} of {report['ticks']} reported inconsistent")
    if "proxsuite_warm_start_failures" in notes:
        print(f"  proxsuite warm-started from its previous result: "
              f"{notes['proxsuite_warm_start_failures']} of {report['ticks']} not solved "
              "(reported primal infeasible)")


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--json", action="store_true")
    ns = parser.parse_args(argv)
    report = run_qp_bench(ns.quick)
    if ns.json:
        print(json.dumps(report))
    else:
        print_qp_bench(report)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
