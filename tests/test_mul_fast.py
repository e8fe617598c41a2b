"""`expr.mul`'s shortcuts for the common shapes build the tree the general rule builds
(the rule is restated here, as it stood before the shortcuts)."""
from __future__ import annotations

import itertools
import math

from momentum_cli.expr import Add, Const, Fn, Known, Mul, Pow, Var, keeps, mul


def general_mul(a, b):
    ta, tb = type(a), type(b)
    if ta is Const:
        if tb is Const:
            return Const(a.value * b.value)
        if a.value == 0.0 and not keeps(a.value):
            return Const(0.0)
        if a.value == 1.0 and not keeps(a.value):
            return b
    elif tb is Const:
        if b.value == 0.0 and not keeps(b.value):
            return Const(0.0)
        if b.value == 1.0 and not keeps(b.value):
            return a
    fs = (a.factors if ta is Mul else (a,)) + (b.factors if tb is Mul else (b,))
    c, rest = 1.0, []
    for f in fs:
        if type(f) is Const:
            c *= f.value
        else:
            rest.append(f)
    if c == 0.0 and not keeps(c):
        return Const(0.0)
    if not rest:
        return Const(c)
    if c == 1.0 and not keeps(c):
        return rest[0] if len(rest) == 1 else Mul(tuple(rest))
    return Mul((Const(c), *rest))


def shape(e):
    """The tree as nested tuples; the identity of leaves that are not constants."""
    t = type(e)
    if t is Const:
        return ("C", math.copysign(1, e.value), repr(e.value))
    if t in (Var, Known):
        return (t.__name__, id(e))
    if t is Add:
        return ("+", *map(shape, e.terms))
    if t is Mul:
        return ("*", *map(shape, e.factors))
    if t is Pow:
        return ("^", shape(e.base), e.exp)
    return ("f", e.name, shape(e.arg))


def test_mul_shortcuts_equal_the_general_rule():
    x, y = Var("x"), Var("y")
    leaves = [x, Known("m", 2.0), Known("z", 0.0), Add((x, y)), Pow(x, 2.0), Fn("sin", y),
              Mul((Const(3.0), y)), Mul((x, y))]
    consts = [Const(v) for v in (0.0, -0.0, 1.0, -1.0, 0.5, 2.0, math.inf, math.nan)]
    nodes = leaves + consts
    for a, b in itertools.product(nodes, nodes):
        assert shape(mul(a, b)) == shape(general_mul(a, b)), (a, b)
