"""`lowered.lower` computes what `expr.evaluate` computes, bit for bit: every equation
of the examples and its derivatives, at the solved values and at perturbed ones."""
from pathlib import Path

import pytest

from momentum_cli.expr import Add, Const, Fn, Mul, Pow, Var, diff, evaluate, variables
from momentum_cli.lowered import MAX_DEPTH, lower
from momentum_cli.run import read_source
from momentum_cli.scene import build
from momentum_cli.solve import solve_scene
from momentum_cli.syntax import parse

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
FILES = ["collar_slides_on_spinning_rod.mom", "seed_pendulum_wall.mom", "disk_climbs_curb.mom",
         "seed_rod_drop_rough.mom", "bounce_find_e.mom"]


def _same(a, b) -> bool:
    return repr(a) == repr(b)  # bit for bit, nan and -0.0 included


@pytest.mark.parametrize("name", FILES)
def test_equations_and_derivatives_match_evaluate(name):
    sol = solve_scene(build(parse(read_source(str(EXAMPLES / name)))), False)
    F = [e.residual for e in sol.system.equations
         if variables(e.residual, set()) <= set(sol.values)]
    rows = [F] + [[diff(f, n) for n in sorted(variables(f, set()))] for f in F]
    fast = lower(rows)
    assert fast is not None
    for scale in (1.0, 1.37, -0.5):
        env = {k: v * scale for k, v in sol.values.items()}
        want = []
        for row in rows:
            out = []
            for e in row:
                try:
                    out.append(evaluate(e, env))
                except (ValueError, ZeroDivisionError, OverflowError) as exc:
                    out.append(type(exc))
            want.append(out)
        try:
            got = fast(env)
        except (ValueError, ZeroDivisionError, OverflowError):
            assert any(isinstance(x, type) for r in want for x in r)
            continue
        assert all(_same(a, b) for r, s in zip(got, want) for a, b in zip(r, s))


def test_zero_factor_hides_partners_and_deep_trees_fall_back():
    x = Var("x")
    hidden = Mul((Const(0.0), Pow(x, -1.0)))  # evaluate: 0.0 without dividing by x = 0
    assert lower([[hidden, Add((x, Fn("sin", x)))]])({"x": 0.0}) == [[0.0, 0.0]]
    deep = x
    for _ in range(MAX_DEPTH + 5):
        deep = Fn("sin", deep)
    assert lower([[deep]]) is None


def test_same_shape_reuses_compiled_code_with_its_own_constants():
    """Two blocks of one shape (a variant of a file) share compiled code, never constants."""
    from momentum_cli import lowered

    def tree(m, e):
        x, y = Var("x"), Var("y")
        return [[Add((Mul((Const(m), x)), Mul((Const(-e), Pow(y, 2.0))), Fn("cos", x)))]]

    env = {"x": 0.3, "y": -1.7}
    a, b = lower(tree(2.5, 0.5)), lower(tree(3.5, 0.9))
    assert len(lowered._CODE) >= 1
    for (m, e), f in (((2.5, 0.5), a), ((3.5, 0.9), b)):
        assert _same(f(env), [[evaluate(tree(m, e)[0][0], env)]])
    assert a.__code__ is b.__code__
