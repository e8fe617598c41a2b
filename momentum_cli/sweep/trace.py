"""Tracing a problem's numbers through build and compile, once for every variant.

In: a varied parameter's value for one variant (the *base*). Out: `Traced`, a float
that is that value (so build, compile and analyse run exactly as for the base
variant) and also carries how it was computed from the parameters (an `expr.E` tree
over `Known` leaves named by the parameters). Every comparison it takes part in is
recorded as a `Guard`: a decision the structure depends on (a zero term dropped, a
coefficient of 1 folded away), re-checked for every variant, so a variant that
would have gone another way is solved on its own, never mixed in.
"""
from __future__ import annotations

import operator

from ..expr import Const, E, Known, add, fn, mul, neg, power

PREFIX = "\x00param:"  # the parameters' leaves: a name no file can write


class Guard:
    """`lhs OP rhs` was `outcome` for the base variant."""

    __slots__ = ("lhs", "op", "rhs", "outcome")

    def __init__(self, lhs: E, op: str, rhs: E, outcome: bool):
        self.lhs, self.op, self.rhs, self.outcome = lhs, op, rhs, outcome


class _Recorder:
    on = False
    guards: list = []
    seen: set = set()


REC = _Recorder()


def start() -> None:
    REC.on, REC.guards, REC.seen = True, [], set()


def stop() -> list:
    REC.on = False
    out, REC.guards, REC.seen = REC.guards, [], set()
    return out


class paused:
    """Comparisons made by the sweep's own code are not decisions of the structure."""

    def __enter__(self):
        self.was, REC.on = REC.on, False

    def __exit__(self, *exc):
        REC.on = self.was
        return False


class keeping:
    """While inside, a traced 0 or 1 keeps its terms (expr.keeps): the structure stays
    that of a generic value, so derivatives at a special one (e = 1, a mass of 1 kg, a
    `0 m/s`) are exact. For the sensitivities; the sweep folds and guards instead."""

    def __enter__(self):
        self.was, Traced.keep = Traced.keep, True

    def __exit__(self, *exc):
        Traced.keep = self.was
        return False


def leaf(name: str, value: float) -> "Traced":
    return Traced(value, Known(PREFIX + name, float(value)))


def expr_of(x) -> E:
    return x.expr if isinstance(x, Traced) else Const(float(x))


def _guard(a, op: str, b, outcome: bool) -> bool:
    if REC.on:
        key = (op, id(expr_of(a)) if isinstance(a, Traced) else float(a),
               id(expr_of(b)) if isinstance(b, Traced) else float(b))
        if key not in REC.seen:
            REC.seen.add(key)
            REC.guards.append(Guard(expr_of(a), op, expr_of(b), outcome))
    return outcome


def _num(o) -> bool:
    return isinstance(o, (float, int)) and not isinstance(o, bool)


class Traced(float):
    """A float that remembers its expression in the parameters."""

    __slots__ = ("expr",)
    keep = False  # while True (`keeping`), expr never folds a traced 0 or 1 away

    def __new__(cls, value, expr: E):
        self = float.__new__(cls, value)
        self.expr = expr
        return self

    def __reduce__(self):  # pickled (to a worker) as the plain number it is
        return (float, (float(self),))

    # arithmetic: the base value as float does it, the expression alongside
    def __add__(self, o):
        return Traced(float(self) + float(o), add(self.expr, expr_of(o))) if _num(o) \
            else NotImplemented

    def __radd__(self, o):
        return Traced(float(o) + float(self), add(expr_of(o), self.expr)) if _num(o) \
            else NotImplemented

    def __sub__(self, o):
        return Traced(float(self) - float(o), add(self.expr, neg(expr_of(o)))) if _num(o) \
            else NotImplemented

    def __rsub__(self, o):
        return Traced(float(o) - float(self), add(expr_of(o), neg(self.expr))) if _num(o) \
            else NotImplemented

    def __mul__(self, o):
        return Traced(float(self) * float(o), mul(self.expr, expr_of(o))) if _num(o) \
            else NotImplemented

    def __rmul__(self, o):
        return Traced(float(o) * float(self), mul(expr_of(o), self.expr)) if _num(o) \
            else NotImplemented

    def __truediv__(self, o):
        return Traced(float(self) / float(o), mul(self.expr, power(expr_of(o), -1.0))) \
            if _num(o) else NotImplemented

    def __rtruediv__(self, o):
        return Traced(float(o) / float(self), mul(expr_of(o), power(self.expr, -1.0))) \
            if _num(o) else NotImplemented

    def __pow__(self, o):
        if not _num(o):
            return NotImplemented
        if isinstance(o, Traced):
            return Traced(float(self) ** float(o),
                          fn("exp", mul(o.expr, fn("ln", self.expr))))
        return Traced(float(self) ** float(o), power(self.expr, float(o)))

    def __rpow__(self, o):
        if not _num(o):
            return NotImplemented
        return Traced(float(o) ** float(self), fn("exp", mul(self.expr, Const(
            __import__("math").log(float(o))))))

    def apply(self, name: str) -> "Traced":
        """A function of the file's (`sin`, `ln`...), as `expr.fn` folds a constant."""
        from ..expr import FUNCS, Fn

        return Traced(float(FUNCS[name](float(self))), Fn(name, self.expr))

    @staticmethod
    def hypot(x, y) -> "Traced":
        """math.hypot(x, y) with the expression sqrt(x^2 + y^2)."""
        import math

        ex, ey = expr_of(x), expr_of(y)
        return Traced(math.hypot(float(x), float(y)),
                      power(add(mul(ex, ex), mul(ey, ey)), 0.5))

    def __neg__(self):
        return Traced(-float(self), neg(self.expr))

    def __pos__(self):
        return self

    def __abs__(self):
        return Traced(abs(float(self)), fn("abs", self.expr))

    # comparisons: decisions, recorded
    def _cmp(self, o, op, sym):
        if not _num(o):
            return NotImplemented
        return _guard(self, sym, o, op(float(self), float(o)))

    def __eq__(self, o):
        return self._cmp(o, operator.eq, "==")

    def __ne__(self, o):
        return self._cmp(o, operator.ne, "!=")

    def __lt__(self, o):
        return self._cmp(o, operator.lt, "<")

    def __le__(self, o):
        return self._cmp(o, operator.le, "<=")

    def __gt__(self, o):
        return self._cmp(o, operator.gt, ">")

    def __ge__(self, o):
        return self._cmp(o, operator.ge, ">=")

    def __bool__(self):
        return _guard(self, "!=", 0.0, float(self) != 0.0)

    __hash__ = float.__hash__
