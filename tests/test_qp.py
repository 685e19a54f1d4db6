"""kl.qp against quadprog and OSQP on seeded random feasible problems, plus degenerate, infeasible
and bad-input cases.

Problems are built around a point x0: equalities b = A x0, inequalities d = C x0 + slack with
many slacks exactly 0 (so those rows tend to be active), bounds lb <= x0 <= ub with some sides
tight and some infinite; H = M M'/n + 0.1 I is positive definite, so the optimum is unique.
"""
import numpy as np
import pytest

import kiloloop as kl

quadprog = pytest.importorskip("quadprog")

QpStatus = kl.qp.QpStatus
# (n, equalities, inequalities, bounds): n up to 30, up to 60 constraints besides the bounds.
SHAPES = [(2, 0, 3, True), (4, 1, 6, False), (6, 2, 10, True), (8, 0, 20, True), (12, 0, 16, True),
          (12, 6, 16, True), (15, 3, 30, False), (20, 5, 40, True), (30, 10, 50, True),
          (30, 0, 60, False)]
PER_SHAPE = 1100  # 11,000 problems in all


def _batch(rng, k, n, me, mi, bounds):
    """k random feasible problems of one shape, generated at once."""
    for p, _ in _batch_with_points(rng, k, n, me, mi, bounds):
        yield p


def _batch_with_points(rng, k, n, me, mi, bounds):
    """As _batch, with the feasible point x0 each problem was built around."""
    M = rng.standard_normal((k, n, n))
    H = M @ M.transpose(0, 2, 1) / n + 0.1 * np.eye(n)
    g = 3.0 * rng.standard_normal((k, n))
    x0 = rng.standard_normal((k, n))
    A = rng.standard_normal((k, me, n))
    b = np.einsum("kij,kj->ki", A, x0)
    C = rng.standard_normal((k, mi, n))
    # Tight (zero-slack) rows and bound sides: about half of n - me of them on average, so that
    # x0 is rarely a degenerate vertex with more than n active constraints (quadprog gives up on
    # those; the degenerate tests below cover them).
    tight = min(0.5, 0.5 * (n - me) / max(1, mi + (2 * n if bounds else 0)))
    slack = np.where(rng.random((k, mi)) < tight, 0.0, rng.random((k, mi)))
    d = np.einsum("kij,kj->ki", C, x0) + slack
    if bounds:
        lb = x0 - np.where(rng.random((k, n)) < tight, 0.0, rng.random((k, n)))
        ub = x0 + np.where(rng.random((k, n)) < tight, 0.0, rng.random((k, n)))
        lb[rng.random((k, n)) < 0.2] = -np.inf
        ub[rng.random((k, n)) < 0.2] = np.inf
    else:
        lb = ub = None
    for i in range(k):
        yield dict(H=H[i], g=g[i], A_eq=A[i] if me else None, b_eq=b[i] if me else None,
                   C=C[i] if mi else None, d=d[i] if mi else None,
                   lb=None if lb is None else lb[i], ub=None if ub is None else ub[i]), x0[i]


def _quadprog(p):
    """quadprog.solve_qp(G, a, C, b, meq): min 1/2 x'Gx - a'x  s.t.  C'x >= b, equalities first."""
    n = len(p["g"])
    cols, rhs = [], []
    if p["A_eq"] is not None:
        cols.append(p["A_eq"].T), rhs.append(p["b_eq"])
    if p["C"] is not None:
        cols.append(-p["C"].T), rhs.append(-p["d"])  # C x <= d  ->  -C x >= -d
    eye = np.eye(n)
    for bound, sign in ((p["lb"], 1.0), (p["ub"], -1.0)):
        if bound is not None:
            finite = np.isfinite(bound)
            cols.append(sign * eye[:, finite]), rhs.append(sign * bound[finite])
    Cq = np.hstack(cols) if cols else np.zeros((n, 0))
    bq = np.concatenate(rhs) if rhs else np.zeros(0)
    meq = 0 if p["A_eq"] is None else len(p["b_eq"])
    return quadprog.solve_qp(p["H"], -p["g"], Cq, bq, meq)[0]


def _objective(p, x):
    return 0.5 * x @ p["H"] @ x + p["g"] @ x


def _violation(p, x):
    v = 0.0
    if p["A_eq"] is not None:
        v = max(v, np.abs(p["A_eq"] @ x - p["b_eq"]).max())
    if p["C"] is not None:
        v = max(v, (p["C"] @ x - p["d"]).max())
    if p["lb"] is not None:
        v = max(v, (p["lb"] - x).max())
    if p["ub"] is not None:
        v = max(v, (x - p["ub"]).max())
    return max(v, 0.0)


def _kkt_residual(p, res):
    """|H x + g + A' lambda + C' mu + z|, relative to the size of H x and g."""
    x = res.x
    r = p["H"] @ x + p["g"] + res.bound_multipliers
    if p["A_eq"] is not None:
        r += p["A_eq"].T @ res.eq_multipliers
    if p["C"] is not None:
        r += p["C"].T @ res.ineq_multipliers
        assert res.ineq_multipliers.min() >= 0.0
    return np.abs(r).max() / (1.0 + np.abs(p["H"] @ x).max() + np.abs(p["g"]).max())


def _check_against_quadprog(p, res, tag):
    """Optimal, feasible, KKT with our multipliers, and the same optimum as quadprog. Returns
    False where quadprog itself gives up (it reports degenerate vertices as inconsistent)."""
    assert res.status == QpStatus.OPTIMAL, tag
    assert abs(res.objective - _objective(p, res.x)) <= 1e-9 * max(1.0, abs(res.objective)), tag
    assert _violation(p, res.x) <= 1e-9, f"{tag}: violation {_violation(p, res.x)}"
    assert _kkt_residual(p, res) <= 1e-9, f"{tag}: KKT residual {_kkt_residual(p, res)}"
    try:
        xq = _quadprog(p)
    except ValueError:
        return False
    f, fq = _objective(p, res.x), _objective(p, xq)
    assert abs(f - fq) <= 1e-7 * max(1.0, abs(fq)), f"{tag}: objective {f} vs quadprog {fq}"
    assert np.abs(res.x - xq).max() <= 1e-6 * (1.0 + np.abs(xq).max()), f"{tag}: x differs"
    return True


@pytest.mark.parametrize("shape", SHAPES, ids=lambda s: "n{}_eq{}_in{}_{}".format(*s))
def test_random_feasible_problems_match_quadprog(shape):
    n, me, mi, bounds = shape
    seed = 1000 + 7 * n + 3 * me + mi
    print(f"seed {seed}: {PER_SHAPE} problems n={n} eq={me} ineq={mi} bounds={bounds}")
    rng = np.random.default_rng(seed)
    solver = kl.qp.DenseQpSolver(n, me, mi, warm_start=True)
    iterations, compared = [], 0
    for i, p in enumerate(_batch(rng, PER_SHAPE, n, me, mi, bounds)):
        res = solver.solve(**p)
        compared += _check_against_quadprog(p, res, f"seed {seed} problem {i}")
        iterations.append(res.iterations)
    print(f"  iterations: mean {np.mean(iterations):.1f}, max {max(iterations)}; compared with "
          f"quadprog on {compared} (it reported the rest inconsistent; KKT checked on all)")
    assert compared >= 0.9 * PER_SHAPE


def _degenerate(rng, kind, n=8):
    """A feasible problem with one kind of degeneracy added."""
    p, x0 = next(_batch_with_points(rng, 1, n, 2, 10, True))
    C, d = p["C"], p["d"]
    if kind == "duplicated_rows":
        C, d = np.vstack([C, C[:3], 2.0 * C[3:5]]), np.concatenate([d, d[:3], 2.0 * d[3:5]])
    elif kind == "parallel_rows":  # same normals, other offsets, some tighter (x0 stays feasible)
        offset = C[:4] @ x0 + rng.random(4) * (d[:4] - C[:4] @ x0) * (rng.random(4) < 0.5)
        C, d = np.vstack([C, 3.0 * C[:4], -C[:2]]), np.concatenate([d, 3.0 * offset, -C[:2] @ x0 + 1.0])
    elif kind == "row_duplicates_bound":
        j = int(np.flatnonzero(np.isfinite(p["ub"]))[0]) if np.isfinite(p["ub"]).any() else 0
        p["ub"][j] = p["ub"][j] if np.isfinite(p["ub"][j]) else 1.0
        C, d = np.vstack([C, np.eye(n)[j]]), np.concatenate([d, [p["ub"][j]]])
    elif kind == "equality_as_two_rows":
        a, b = p["A_eq"][0], p["b_eq"][0]
        C, d = np.vstack([C, a, -a]), np.concatenate([d, [b, -b]])
    elif kind == "duplicated_equalities":
        p["A_eq"] = np.vstack([p["A_eq"], p["A_eq"][0], -2.0 * p["A_eq"][1]])
        p["b_eq"] = np.concatenate([p["b_eq"], [p["b_eq"][0], -2.0 * p["b_eq"][1]]])
    elif kind == "active_at_unconstrained_optimum":
        x_unc = np.linalg.solve(p["H"], -p["g"])
        C = np.vstack([C[:2], C[2:6]])
        d = C @ x_unc  # every row exactly tight at the start
        p["A_eq"] = p["b_eq"] = None
        p["lb"], p["ub"] = x_unc - np.abs(rng.random(n)), x_unc
    elif kind == "fixed_variables":  # lb == ub for some variables, on a feasible point
        x = np.linalg.lstsq(p["A_eq"], p["b_eq"], rcond=None)[0]
        p["lb"], p["ub"] = x - rng.random(n), x + rng.random(n)
        p["lb"][:2] = p["ub"][:2] = x[:2]
        d = C @ x + np.where(rng.random(len(d)) < 0.5, 0.0, rng.random(len(d)))
    p["C"], p["d"] = C, d
    return p


DEGENERATE_KINDS = ["duplicated_rows", "parallel_rows", "row_duplicates_bound",
                    "equality_as_two_rows", "duplicated_equalities",
                    "active_at_unconstrained_optimum", "fixed_variables"]


@pytest.mark.parametrize("kind", DEGENERATE_KINDS)
def test_degenerate_problems(kind):
    seed = 77 + DEGENERATE_KINDS.index(kind)
    print(f"seed {seed}: 300 problems, {kind}")
    rng = np.random.default_rng(seed)
    quadprog_failures = 0
    for i in range(300):
        p = _degenerate(rng, kind)
        res = kl.qp.solve(**p)
        tag = f"seed {seed} {kind} problem {i}"
        assert res.status == QpStatus.OPTIMAL, tag
        assert _violation(p, res.x) <= 1e-9, tag
        assert _kkt_residual(p, res) <= 1e-9, tag
        try:
            xq = _quadprog(p)
        except ValueError:  # quadprog can give up on dependent constraints; KKT above decides
            quadprog_failures += 1
            continue
        f, fq = _objective(p, res.x), _objective(p, xq)
        assert abs(f - fq) <= 1e-7 * max(1.0, abs(fq)), tag
    print(f"  quadprog failed on {quadprog_failures} of 300")


def test_unconstrained_optimum_feasible_takes_no_iterations():
    H = np.diag([1.0, 2.0, 4.0])
    g = np.array([-1.0, -4.0, 8.0])
    res = kl.qp.solve(H, g, C=np.eye(3), d=[1.0, 2.0, 0.0], lb=[-5.0] * 3)
    assert res.status == QpStatus.OPTIMAL and res.iterations == 0 and res.n_active == 0
    np.testing.assert_allclose(res.x, [1.0, 2.0, -2.0], rtol=0, atol=1e-15)


def test_against_osqp_on_a_subset():
    osqp = pytest.importorskip("osqp")
    sparse = pytest.importorskip("scipy.sparse")
    seed = 4242
    print(f"seed {seed}: 1000 problems against OSQP")
    rng = np.random.default_rng(seed)
    worst = 0.0
    count = 0
    for n, me, mi, bounds in SHAPES:
        for p in _batch(rng, 100, n, me, mi, bounds):
            res = kl.qp.solve(**p)
            assert res.status == QpStatus.OPTIMAL
            rows, lo, hi = [], [], []
            if p["A_eq"] is not None:
                rows.append(p["A_eq"]), lo.append(p["b_eq"]), hi.append(p["b_eq"])
            if p["C"] is not None:
                rows.append(p["C"]), lo.append(np.full(mi, -np.inf)), hi.append(p["d"])
            if p["lb"] is not None:
                rows.append(np.eye(n)), lo.append(p["lb"]), hi.append(p["ub"])
            solver = osqp.OSQP()
            solver.setup(sparse.csc_matrix(np.triu(p["H"])), p["g"], sparse.csc_matrix(np.vstack(rows)),
                         np.concatenate(lo), np.concatenate(hi), eps_abs=1e-9, eps_rel=1e-9,
                         polishing=True, max_iter=200000, check_termination=1, verbose=False)
            r = solver.solve(raise_error=False)
            assert r.info.status in ("solved", "solved inaccurate"), r.info.status
            f, fo = _objective(p, res.x), _objective(p, r.x)
            rel = abs(f - fo) / max(1.0, abs(fo))
            worst = max(worst, rel)
            assert rel <= 1e-5, f"seed {seed} problem {count}: {f} vs OSQP {fo}"
            assert f <= fo + 1e-9 * max(1.0, abs(fo)) + 1e3 * _violation(p, r.x) * max(1.0, abs(fo))
            count += 1
    print(f"  {count} problems, worst relative objective difference {worst:.2e}")


def test_infeasible_problems():
    eye = np.eye(3)
    H, g = eye, np.ones(3)
    cases = {
        "x<=0 and x>=1 as rows": dict(C=np.array([[1.0, 0, 0], [-1.0, 0, 0]]), d=[0.0, -1.0]),
        "x<=0 and x>=1 as bounds": dict(lb=[1.0, -np.inf, -np.inf], ub=[0.0, np.inf, np.inf]),
        "row against bound": dict(C=np.array([[1.0, 0, 0]]), d=[0.0], lb=[1.0, -5, -5]),
        "contradictory equalities": dict(A_eq=np.array([[1.0, 1, 0], [2.0, 2, 0]]), b_eq=[1.0, 3.0]),
        "equality against inequalities": dict(A_eq=np.array([[1.0, 1, 0]]), b_eq=[1.0],
                                              C=eye[:2], d=[0.0, 0.0]),
        "empty triangle": dict(C=np.array([[-1.0, 0, 0], [0, -1.0, 0], [1.0, 1.0, 0]]),
                               d=[0.0, 0.0, -1.0]),
        "more independent equalities than variables": dict(A_eq=np.vstack([eye, [1.0, 1.0, 1.0]]),
                                                           b_eq=[1.0, 1.0, 1.0, 0.0]),
    }
    for name, kw in cases.items():
        res = kl.qp.solve(H, g, **kw)
        assert res.status == QpStatus.INFEASIBLE, name
        assert np.all(np.isfinite(res.x)), name
    # Random: a feasible problem plus the mirror of one of its rows, shifted past it.
    seed = 9
    print(f"seed {seed}: 200 random infeasible problems")
    rng = np.random.default_rng(seed)
    for i, p in enumerate(_batch(rng, 200, 10, 2, 12, True)):
        j = i % 12
        p["C"] = np.vstack([p["C"], -p["C"][j]])
        p["d"] = np.concatenate([p["d"], [-p["d"][j] - 0.1 - rng.random()]])
        assert kl.qp.solve(**p).status == QpStatus.INFEASIBLE, f"seed {seed} problem {i}"
        with pytest.raises(ValueError):
            _quadprog(p)  # the oracle agrees


def test_bad_data_gives_bad_input_status():
    H, g = np.eye(3), np.ones(3)
    C, d = np.ones((2, 3)), np.ones(2)
    nan = np.nan
    cases = {
        "NaN in H": dict(H=np.diag([1.0, nan, 1.0]), g=g),
        "inf in g": dict(H=H, g=[1.0, np.inf, 0.0]),
        "NaN in C": dict(H=H, g=g, C=np.array([[1.0, nan, 0], [0, 0, 1.0]]), d=d),
        "NaN in b_eq": dict(H=H, g=g, A_eq=C[:1], b_eq=[nan]),
        "NaN lower bound": dict(H=H, g=g, lb=[0.0, nan, 0.0]),
        "inf in H": dict(H=np.array([[1.0, 0, np.inf], [0, 1.0, 0], [np.inf, 0, 1.0]]), g=g),
        "denormal H (numerically zero)": dict(H=5e-324 * np.eye(3), g=g),
        "indefinite H": dict(H=np.diag([1.0, -1.0, 1.0]), g=g),
        "singular H": dict(H=np.diag([1.0, 0.0, 1.0]), g=g),
        "asymmetric H": dict(H=np.array([[1.0, 0.5, 0], [0, 1.0, 0], [0, 0, 1.0]]), g=g),
    }
    for name, kw in cases.items():
        res = kl.qp.solve(**kw)
        assert res.status == QpStatus.BAD_INPUT, name
        assert np.all(res.x == 0.0), name
    # Bounds that can never be met: -inf in d, +inf in lb, -inf in ub.
    for name, kw in {"-inf in d": dict(C=C, d=[1.0, -np.inf]),
                     "+inf lower bound": dict(lb=[0.0, np.inf, 0.0]),
                     "-inf upper bound": dict(ub=[0.0, -np.inf, 0.0])}.items():
        res = kl.qp.solve(H, g, **kw)
        assert res.status == QpStatus.INFEASIBLE, name
        assert np.all(res.x == 0.0), name
    # +inf in d drops the row; -inf in lb / +inf in ub are absent bounds.
    res = kl.qp.solve(H, g, C=C, d=[np.inf, np.inf], lb=[-np.inf] * 3, ub=[np.inf] * 3)
    assert res.status == QpStatus.OPTIMAL
    np.testing.assert_allclose(res.x, -g)


def _violation_scaled(p, x):
    """Largest constraint violation relative to the size of the constraint's terms."""
    xi = np.abs(x).max()
    v = 0.0
    for M, r, eq in ((p.get("A_eq"), p.get("b_eq"), True), (p.get("C"), p.get("d"), False)):
        if M is None:
            continue
        M, r = np.asarray(M, float), np.asarray(r, float)
        keep = np.isfinite(r)
        res = M[keep] @ x - r[keep]
        res = np.abs(res) if eq else res
        scale = np.abs(r[keep]) + np.abs(M[keep]).sum(axis=1) * xi
        with np.errstate(over="ignore", invalid="ignore"):
            v = max(v, np.max(res / np.maximum(scale, 1e-300), initial=0.0))
    return v


def test_never_optimal_with_a_bad_solution():
    """Issue 12: bounds of -1e308 and a denormal H returned OPTIMAL with x = -inf. Now any status
    comes with a finite x, and OPTIMAL only with x meeting every constraint."""
    H, g = np.eye(3), np.ones(3)
    cases = {
        "d = -1e308": dict(H=H, g=g, C=np.eye(3)[:1], d=[-1e308]),
        "denormal H": dict(H=5e-324 * np.eye(3), g=g),
        "tiny H, x overflows": dict(H=1e-300 * np.eye(3), g=1e10 * g),
        "g = 1e308": dict(H=H, g=1e308 * g),
        "ub = -1e308": dict(H=H, g=g, ub=[-1e308, 0.0, 0.0]),
        "C = 1e200": dict(H=H, g=g, C=np.full((1, 3), 1e200), d=[-1e200]),
        "b_eq = 1e308": dict(H=H, g=g, A_eq=np.ones((1, 3)), b_eq=[1e308]),
        "lb = 1e308": dict(H=H, g=g, lb=[1e308, -np.inf, -np.inf]),
    }
    for name, kw in cases.items():
        res = kl.qp.solve(**kw)
        assert np.all(np.isfinite(res.x)), name
        assert np.isfinite(res.objective), name
        if res.status == QpStatus.OPTIMAL:
            assert _violation_scaled(kw, res.x) <= 1e-8, name
    assert kl.qp.solve(**cases["d = -1e308"]).status != QpStatus.OPTIMAL
    assert kl.qp.solve(**cases["denormal H"]).status == QpStatus.BAD_INPUT
    assert kl.qp.solve(**cases["tiny H, x overflows"]).status == QpStatus.NUMERICAL_ERROR


def test_extreme_values_mixed_into_random_problems():
    """Random feasible problems with one entry replaced by an extreme value: never OPTIMAL with a
    non-finite or violating x."""
    seed = 12
    print(f"seed {seed}: 3000 problems with an extreme entry")
    rng = np.random.default_rng(seed)
    extremes = [np.nan, np.inf, -np.inf, 1e308, -1e308, 5e-324, -5e-324, 1e200, -1e200, 0.0]
    optimal = 0
    for i, p in enumerate(_batch(rng, 3000, 6, 1, 8, True)):
        key = ["H", "g", "A_eq", "b_eq", "C", "d", "lb", "ub"][i % 8]
        arr = np.array(p[key], dtype=float)
        idx = tuple(rng.integers(0, s) for s in arr.shape)
        arr[idx] = extremes[rng.integers(len(extremes))]
        if key == "H":  # keep H symmetric so that the extreme value is what is tested
            arr[idx[::-1]] = arr[idx]
        p[key] = arr
        res = kl.qp.solve(**p)
        tag = f"seed {seed} problem {i}: {key}{idx} = {arr[idx]}"
        assert np.all(np.isfinite(res.x)), tag
        assert np.isfinite(res.objective), tag
        if res.status == QpStatus.OPTIMAL:
            optimal += 1
            assert _violation_scaled(p, res.x) <= 1e-8, tag
            for lo, x in ((p["lb"], res.x), (-p["ub"], -res.x)):
                keep = np.isfinite(lo)
                assert np.all(x[keep] - lo[keep] >= -1e-8 * (np.abs(lo[keep]) + np.abs(x).max())), tag
    print(f"  optimal: {optimal} of 3000")
    assert optimal > 1000


def test_wrong_shapes_and_dtypes_raise_value_error():
    H, g = np.eye(12), np.zeros(12)
    with pytest.raises(ValueError, match=r"C: expected shape \(m, 12\)"):
        kl.qp.solve(H, g, C=np.ones((4, 11)), d=np.ones(4))
    with pytest.raises(ValueError, match=r"d: expected shape \(4,\)"):
        kl.qp.solve(H, g, C=np.ones((4, 12)), d=np.ones(3))
    with pytest.raises(ValueError, match=r"d: expected shape \(4,\)"):
        kl.qp.solve(H, g, C=np.ones((4, 12)))
    with pytest.raises(ValueError, match=r"A_eq: expected shape \(m, 12\)"):
        kl.qp.solve(H, g, b_eq=np.ones(2))
    with pytest.raises(ValueError, match=r"g: expected shape \(12,\)"):
        kl.qp.solve(H, np.zeros(11))
    with pytest.raises(ValueError, match=r"H: expected shape \(n, n\)"):
        kl.qp.solve(np.ones((3, 4)), np.zeros(3))
    with pytest.raises(ValueError, match=r"lb: expected shape \(12,\)"):
        kl.qp.solve(H, g, lb=np.zeros((12, 1)))
    with pytest.raises(ValueError, match="H: expected a real"):
        kl.qp.solve(H.astype(complex), g)
    with pytest.raises(ValueError, match="g: expected a real"):
        kl.qp.solve(H, ["a"] * 12)
    solver = kl.qp.DenseQpSolver(12, max_eq=2, max_ineq=4)
    with pytest.raises(ValueError, match=r"H: expected shape \(n, n\) with n <= 12"):
        solver.solve(np.eye(13), np.zeros(13))
    with pytest.raises(ValueError, match=r"C: expected shape \(m, 12\) with m <= 4"):
        solver.solve(H, g, C=np.ones((5, 12)), d=np.ones(5))
    with pytest.raises(ValueError):
        kl.qp.DenseQpSolver(0, 0, 0)
    # Lists, integers and Fortran-ordered arrays are accepted.
    res = kl.qp.solve(np.asfortranarray(2 * np.eye(2, dtype=int)), [2, 0], C=[[1, 1]], d=[-3])
    assert res.status == QpStatus.OPTIMAL
    np.testing.assert_allclose(res.x, [-2.0, -1.0])


def test_solver_reuse_with_smaller_problems_and_warm_start():
    seed = 31
    print(f"seed {seed}")
    rng = np.random.default_rng(seed)
    warm = kl.qp.DenseQpSolver(12, 6, 16, warm_start=True)
    cold = kl.qp.DenseQpSolver(12, 6, 16, warm_start=False)
    assert (warm.n, warm.max_eq, warm.max_ineq) == (12, 6, 16)
    p = next(_batch(rng, 1, 12, 2, 16, True))
    it_warm = it_cold = 0
    for k in range(300):
        p["g"] = p["g"] + 0.05 * rng.standard_normal(12)  # a drifting problem, tick to tick
        rw, rc = warm.solve(**p), cold.solve(**p)
        assert rw.status == rc.status == QpStatus.OPTIMAL
        np.testing.assert_allclose(rw.x, rc.x, rtol=0, atol=1e-10)
        it_warm, it_cold = it_warm + rw.iterations, it_cold + rc.iterations
        if k % 50 == 0:  # a smaller problem in the same workspace
            q = next(_batch(rng, 1, 5, 1, 6, False))
            _check_against_quadprog(q, warm.solve(**q), f"seed {seed} small {k}")
    print(f"  iterations: warm {it_warm}, cold {it_cold}")
    assert it_warm < it_cold
    warm.reset_warm_start()
    assert warm.solve(**p).status == QpStatus.OPTIMAL


def test_iteration_limit_status():
    res = kl.qp.solve(np.eye(4), -np.ones(4), ub=np.zeros(4), max_iterations=2)
    assert res.status == QpStatus.ITERATION_LIMIT and res.iterations == 2
    assert np.all(np.isfinite(res.x))


def test_qp_bench_runs_and_every_solver_agrees(capsys):
    from kiloloop.bench.qp_bench import print_qp_bench, run_qp_bench

    report = run_qp_bench(quick=True)
    print_qp_bench(report)
    assert "ours C++" in capsys.readouterr().out
    for row in report["results"]:
        assert row["own_median_us"] is None or row["own_median_us"] > 0
        if "failures" in row:  # ours and every peer: solved, same objective as ours
            assert row["failures"] == 0 and row["disagreements"] == 0, row["name"]
