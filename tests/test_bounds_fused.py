"""The bounds' one-walk derivatives and size (bounds.derivatives_and_size) equal the two
walks they replace, bit for bit (signed zeros included; a NaN's sign, which is not ours,
excepted) and in the same order, on random trees, including trees whose walks fail (a
missing value, a log of a negative number)."""
from __future__ import annotations

import math
import random
import types

from momentum_cli.bounds import _mag, derivatives, derivatives_and_size
from momentum_cli.expr import Add, Const, Fn, Known, Mul, Pow, Var


def _tree(rng: random.Random, depth: int):
    r = rng.random()
    if depth <= 0 or r < 0.3:
        k = rng.randrange(5)
        if k == 0:
            return Const(rng.choice([0.0, -0.0, 1.0, -2.5, 1e-300, rng.uniform(-3, 3)]))
        if k == 1:
            return Known(rng.choice("mnp"), rng.choice([0.0, 0.1, -4.0]))
        return Var(rng.choice(["x", "y", "z", "w", "missing"]))
    k = rng.randrange(4)
    if k == 0:
        return Add(tuple(_tree(rng, depth - 1) for _ in range(rng.randint(2, 4))))
    if k == 1:
        return Mul(tuple(_tree(rng, depth - 1) for _ in range(rng.randint(2, 3))))
    if k == 2:
        return Pow(_tree(rng, depth - 1), rng.choice([2.0, -1.0, 3.0, -2.0]))
    return Fn(rng.choice(["sin", "cos", "ln", "exp", "abs"]),
              _tree(rng, depth - 1))


def _bits(x):
    """A float as its type, repr and sign: signed zeros count; a NaN's sign does not (IEEE
    754 leaves it uninterpreted, and CPython's sum of two NaNs takes one or the other's
    sign depending on how warm the line is: see the last test)."""
    sign = math.copysign(1.0, x) if isinstance(x, float) and x == x else None
    return (type(x), repr(x), sign)


def test_one_walk_equals_two():
    rng = random.Random(11)
    values = {"x": 2.0, "y": -0.5, "z": 0.0, "w": 1e200}
    failures = 0
    for _ in range(3000):
        e = _tree(rng, 4)
        dv, mag = derivatives_and_size(e, values)
        want = derivatives(e, values)
        assert list(dv) == list(want)  # the same unknowns, in the same order
        assert [_bits(v) for v in dv.values()] == [_bits(v) for v in want.values()]
        assert _bits(mag) == _bits(_mag(e, values))
        failures += any(v == math.inf for v in want.values())
    assert failures  # the failing walks were exercised too


def test_slopes_and_size_equal_their_two_walks():
    from momentum_cli.bounds import size_of, slopes, slopes_and_size

    rng = random.Random(5)
    values = {"x": 2.0, "y": -0.5, "z": 0.0, "w": 1e200}
    size = {"x": 3.0, "y": 0.25, "w": 1e10}
    for _ in range(1000):
        e = _tree(rng, 4)
        slope, scale = slopes_and_size(e, values, size)
        want = slopes(e, values)
        assert [(v, _bits(s)) for v, s in slope.items()] == \
            [(v, _bits(s)) for v, s in want.items()]
        assert _bits(scale) == _bits(size_of(e, values, size, want))


def _cold(f):
    """A copy of `f` that the interpreter has not run yet, so not specialized (CPython
    3.11+ rewrites a line's `a + b` into a float-only addition after a few runs)."""
    return types.FunctionType(f.__code__.replace(), f.__globals__, f.__name__,
                              f.__defaults__, f.__closure__)


def test_slopes_and_size_equal_their_two_walks_however_warm():
    """The comparison above held alone but failed after any test that solves every
    example: 2 * 1e200^2 * 0 has a NaN size (inf * 0: a negative NaN on x86) and a NaN
    slope (abs: a positive NaN), and their sum `mag + sum(...)`, in slopes_and_size and
    in size_of alike, is the one NaN or the other depending on whether the interpreter
    has specialized that line (the generic float addition returns its second NaN, the
    specialized one its first). Which line is warm depends on what ran before, so a
    NaN's sign is no result of ours: the comparison counts NaN as NaN, and here it holds
    with either walk warm and the other cold."""
    from momentum_cli.bounds import size_of, slopes, slopes_and_size

    values = {"x": 2.0, "y": -0.5, "z": 0.0, "w": 1e200}
    size = {"x": 3.0, "y": 0.25, "z": 1.0, "w": 1e10}
    nan_tree = Mul((Var("x"), Var("w"), Var("w"), Var("z")))
    plain = Add((Var("x"), Var("y")))  # float sizes and slopes: warms the additions
    for warm_fused in (True, False):
        fused, two = _cold(slopes_and_size), _cold(size_of)
        for _ in range(64):
            if warm_fused:
                fused(plain, values, size)
            else:
                two(plain, values, size, slopes(plain, values))
        slope, scale = fused(nan_tree, values, size)
        want = slopes(nan_tree, values)
        assert math.isnan(scale) and math.isnan(slope["x"])  # the case is exercised
        assert [(v, _bits(s)) for v, s in slope.items()] == \
            [(v, _bits(s)) for v, s in want.items()]
        assert _bits(scale) == _bits(two(nan_tree, values, size, want)), warm_fused
