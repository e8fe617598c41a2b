"""gradient.py: all first derivatives in one reverse sweep, checked against closed forms
written here and against `expr.diff` term by term."""
from __future__ import annotations

import math

import pytest

from momentum_cli.expr import Const, Known, Var, add, diff, evaluate, fn, mul, power, variables
from momentum_cli.gradient import gradient


def test_closed_form():
    """f = x^2 y + sin(x) / y + ln(y): df/dx = 2 x y + cos(x) / y,
    df/dy = x^2 - sin(x) / y^2 + 1 / y."""
    x, y = Var("x"), Var("y")
    f = add(add(mul(power(x, 2.0), y), mul(fn("sin", x), power(y, -1.0))), fn("ln", y))
    vx, vy = 0.7, 1.9
    g = gradient(f, {"x": vx, "y": vy})
    assert g["x"] == pytest.approx(2 * vx * vy + math.cos(vx) / vy, rel=1e-14)
    assert g["y"] == pytest.approx(vx ** 2 - math.sin(vx) / vy ** 2 + 1 / vy, rel=1e-14)


def test_shared_subtrees_and_zeros_as_diff():
    """A subtree used twice counts twice; a known zero factor hides its partners (as
    `evaluate` and `variables` do); a zero value of an unknown does not."""
    x, y, z = Var("x"), Var("y"), Var("z")
    s = add(mul(x, y), fn("exp", z))  # shared below
    f = add(add(mul(s, s), mul(Known("k", 0.0), z)), mul(Const(3.0), mul(x, mul(y, z))))
    f = add(f, fn("abs", add(x, Const(-5.0))))
    vals = {"x": 1.3, "y": 0.0, "z": -0.4}
    g = gradient(f, vals)
    for v in sorted(variables(f)):
        assert g.get(v, 0.0) == pytest.approx(evaluate(diff(f, v), vals), rel=1e-13,
                                              abs=1e-15), v
