"""Newton's fast paths equal the slow ones: a start stopped where it met a root found
before (solve.EARLY_STOP) solves every example exactly as one run to its end, and the
step solve without the inverse (linalg._step_dense) gives the bits and the singular
decisions of the one with it (_step_dense_full) on every Newton step of every example."""
from pathlib import Path

import pytest
from helpers import solve_outcome

from momentum_cli import linalg, solve
from momentum_cli.expr import Var, diff

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


def _outcome(path, monkeypatch, early, steps=None):
    monkeypatch.setattr(solve, "EARLY_STOP", early)
    calls = []
    inner = solve._newton
    monkeypatch.setattr(solve, "_newton", lambda *a, **k: calls.append(1) or inner(*a, **k))
    if steps is not None:
        dense = linalg._step_dense
        monkeypatch.setattr(linalg, "_step_dense",
                            lambda J, r, n: steps.append(([list(row) for row in J], list(r)))
                            or dense(J, r, n))
    return solve_outcome(path), bool(calls)


@pytest.fixture(scope="module")
def recorded():
    """Every example with a Newton block, solved with the fast paths; the (J, r) of every
    Newton step taken on them."""
    mp = pytest.MonkeyPatch()
    steps, fast = [], {}
    try:
        for path in sorted(EXAMPLES.glob("*.mom")):
            out, newton = _outcome(path, mp, True, steps)
            if newton:
                fast[path.name] = out
    finally:
        mp.undo()
    return fast, steps


def test_early_stop_solves_every_example_as_the_full_runs(recorded, monkeypatch):
    fast, _ = recorded
    assert len(fast) >= 10  # the examples with nonlinear blocks
    for name, out in fast.items():
        assert _outcome(EXAMPLES / name, monkeypatch, False)[0] == out, name


def test_step_without_the_inverse_is_the_step_with_it(recorded, monkeypatch):
    _, steps = recorded
    assert len(steps) > 100
    full = linalg._step_dense_full
    long_way = []
    monkeypatch.setattr(linalg, "_step_dense_full", lambda *a: long_way.append(1) or full(*a))
    for J, r in steps:
        assert repr(linalg._step_dense(J, r, len(r))) == repr(full(J, r, len(r))), (J, r)
    assert len(long_way) < len(steps) / 10  # the bound decides nearly every step


def _roots(F, names, starts, early):
    """`solve._newton`'s loop: Newton from each start, roots merged by `_close`."""
    J = [[diff(f, n) for n in names] for f in F]
    roots = []
    for x0 in starts:
        known = [y for y, _ in roots] if early else ()
        r = solve._newton_from(F, J, names, {}, x0, (None, None), known)
        if r is not None and not any(solve._close(r[0], y) for y, _ in roots):
            roots.append(r)
    return sorted(roots)


@pytest.mark.parametrize("gap", [0.0, 1e-10, 1e-9, 1e-8, 3e-8, 1e-7, 3e-7, 1e-6, 1e-4, 0.1])
@pytest.mark.parametrize("at", [1.0, -3.0, 1e-6, 250.0])
def test_early_stop_keeps_close_roots_apart(gap, at):
    """Two roots `gap` apart (relative; 0: a double root, met linearly): the same roots,
    the same iterations, with and without the early stop."""
    x = Var("x")
    F = [(x - at) * (x - at * (1 + gap))]
    starts = [[at * s + d] for s in (0.5, 2.0, -1.0, 1.5) for d in (0.0, 0.3, -0.7)]
    assert repr(_roots(F, ["x"], starts, True)) == repr(_roots(F, ["x"], starts, False))


@pytest.mark.parametrize("c", [1.0, 1.0 - 1e-8, 1.0 - 1e-6, 0.999, 0.5, 0.0])
def test_early_stop_keeps_a_circle_and_a_line_apart(c):
    """A unit circle cut by the line y = c: two roots that merge into one as the line
    turns tangent."""
    x, y = Var("x"), Var("y")
    F = [x * x + y * y - 1.0, y - c]
    starts = [[u, v] for u in (0.7, -0.7, 2.0, -0.3, 0.01) for v in (0.5, 1.3, -2.0)]
    assert repr(_roots(F, ["x", "y"], starts, True)) == \
        repr(_roots(F, ["x", "y"], starts, False))


@pytest.mark.parametrize("seed", range(3))
def test_step_near_the_singular_bound(seed):
    """Matrices from well to badly conditioned (a row nearly another, by 10^-k): the
    bound's fast answer or the long way, both equal to equilibrate + _gauss_jordan."""
    import random

    from tests.test_newton_step import _reference

    rng = random.Random(seed)
    for _ in range(300):
        n = rng.randint(2, 6)
        J = [[rng.uniform(-1, 1) * 10.0 ** rng.randint(-3, 3) for _ in range(n)]
             for _ in range(n)]
        k = rng.randint(0, 17)
        i, j = rng.sample(range(n), 2)
        J[j] = [v * (1 + 10.0 ** -k * rng.uniform(-1, 1)) + 10.0 ** -k * rng.uniform(-1, 1)
                for v in J[i]]
        r = [rng.uniform(-1, 1) for _ in range(n)]
        assert repr(linalg._step_dense(J, r, n)) == repr(_reference(J, r)), (J, r)


@pytest.mark.parametrize("seed", range(4))
def test_early_stop_on_random_systems(seed):
    """Random systems of two and three unknowns (quadratic, some with a cosine term): the
    roots and their iterations with and without the early stop."""
    import random

    from momentum_cli.expr import Const, Fn

    rng = random.Random(seed)
    for _ in range(15):
        n = rng.choice([2, 3])
        xs = [Var(f"x{i}") for i in range(n)]
        F = []
        for _k in range(n):
            f = Const(rng.uniform(-2, 2))
            for i in range(n):
                f = f + rng.uniform(-2, 2) * xs[i]
                if rng.random() < 0.5:
                    f = f + rng.uniform(-1, 1) * xs[i] * xs[rng.randrange(n)]
            if rng.random() < 0.2:
                f = f + 0.3 * Fn("cos", xs[0])
            F.append(f)
        starts = [[rng.uniform(-3, 3) for _ in range(n)] for _ in range(8)]
        names = [v.name for v in xs]
        assert repr(_roots(F, names, starts, True)) == repr(_roots(F, names, starts, False))
