"""Quantities with dimensions: evaluating the file's expressions, units checked.

An expression from the file evaluates to a `Q`: an expression value (scalar `E` or
planar `V2`) and its dimension. Names resolve through a callback, so the same
evaluator serves constants in `build` and unknowns in `compile`.
"""
from __future__ import annotations

import math
from collections.abc import Callable  # (typing's import costs a one-shot run ~3 ms)

from . import syntax as S
from .diagnostics import ProblemError
from .expr import V2, Const, E, add, fn, mul, neg, power
from .records import record
from .units import (
    NONE,
    Dim,
    UnitError,
    describe,
    dim_div,
    dim_mul,
    dim_pow,
    parse_unit,
    reading_for,
    unknown_unit_message,
)


@record(frozen=True)
class Q:
    value: E | V2
    dim: Dim

    @property
    def is_vector(self) -> bool:
        return isinstance(self.value, V2)


Resolver = Callable[[S.Ref, "Dim | None"], Q]

_FUNCS_DIMLESS = {"sin", "cos", "tan", "asin", "acos", "atan", "exp", "ln", "log"}
KNOWN_FUNCS = sorted(_FUNCS_DIMLESS | {"sqrt", "atan2", "abs", "norm", "dot", "cross", "min",
                                       "max"})


# Words of the language that the grammar reads as a unit when they follow a number
# (`restitution 0.5 smooth`): the likely mistake is a missing comma, not a unit.
_KEYWORDS = {"smooth", "rough", "friction", "restitution", "slip", "normal", "at", "on",
             "with", "over", "along", "about", "of", "to", "stiffness", "length", "rotated",
             "down", "up", "left", "right", "into", "contact", "stops", "rolls", "rest"}


def unit_readings(unit: str, span, want: Dim | None = None) -> list[tuple[float, Dim]]:
    """The readings of a unit; an unknown name is answered with units of dimension `want`."""
    if unit.startswith("in:"):  # syntax.IN_UNIT: `2 in mm` that does not end a find item
        raise ProblemError(f"`in {unit[3:]}` gives the unit of a `find` item, at its end", span,
                           code="syntax")
    try:
        readings = parse_unit(unit)
    except OverflowError:  # `ft^-999`: the factor is not a float
        raise ProblemError(f"unit '{unit}' is out of range (an exponent is too large)", span,
                           code="units") from None
    except UnitError as exc:
        from .source import Span

        col = span.column + exc.offset if span else None
        where = Span(span.line, col, span.line, col + 1) if span else None
        notes = []
        if unit in _KEYWORDS:
            notes.append(f"a unit follows its number directly: is a ',' missing before "
                         f"'{unit}'?")
        message = unknown_unit_message(exc.name, want) if exc.name else str(exc)
        raise ProblemError(message, where, code="units", notes=notes) from None
    if not all(math.isfinite(f) and f != 0 for f, _ in readings):
        raise ProblemError(f"unit '{unit}' is out of range (an exponent is too large)", span,
                           code="units")
    return readings


class Evaluator:
    """Evaluates syntax expressions to `Q`, checking dimensions as it goes."""

    def __init__(self, resolve: Resolver):
        self.resolve = resolve

    def __call__(self, node, expect: Dim | None = None) -> Q:
        return self.ev(node, expect)

    def ev(self, node, expect: Dim | None = None) -> Q:
        if isinstance(node, S.Num):
            if not math.isfinite(node.value):
                raise ProblemError("number too large", node.span, code="number")
            if node.unit is None:
                # a bare 0 is zero in any unit
                return Q(Const(0.0), expect) if node.value == 0 and expect else \
                    Q(Const(node.value), NONE)
            factor, dim = reading_for(unit_readings(node.unit, node.unit_span, expect), expect)
            value = node.value * factor
            if not math.isfinite(value):
                raise ProblemError("number too large", node.span, code="number")
            return Q(Const(value), dim)
        if isinstance(node, S.Ref):
            return self.resolve(node, expect)
        if isinstance(node, S.Neg):
            q = self.ev(node.arg, expect)
            return Q(-q.value if q.is_vector else neg(q.value), q.dim)
        if isinstance(node, S.VecLit):
            x = self.ev(node.x, expect)
            y = self.ev(node.y, expect)
            if x.is_vector or y.is_vector:
                raise ProblemError("a vector's components must be scalars", node.span,
                                   code="type")
            dim = _common_dim(x, y, node, "combine the components")
            return Q(V2(x.value, y.value), dim)
        if isinstance(node, S.BinOp):
            return self._binop(node, expect)
        if isinstance(node, S.Call):
            return self._call(node)
        if isinstance(node, S.Mag):
            q = self.ev(node.arg)
            if q.is_vector:
                v = q.value
                return Q(power(add(mul(v.x, v.x), mul(v.y, v.y)), 0.5), q.dim)
            return Q(fn("abs", q.value), q.dim)
        raise ProblemError("cannot evaluate this expression", getattr(node, "span", None))

    def _binop(self, node: S.BinOp, expect: Dim | None) -> Q:
        op = node.op
        if op in "+-":
            a = self.ev(node.left, expect)
            b = self.ev(node.right, expect if expect is not None else a.dim)
            if a.is_vector != b.is_vector:
                raise ProblemError(f"cannot {'add' if op == '+' else 'subtract'} a vector and a "
                                   "scalar", node.span, code="type")
            dim = _common_dim(a, b, node, "add" if op == "+" else "subtract")
            if a.is_vector:
                return Q(a.value + b.value if op == "+" else a.value - b.value, dim)
            return Q(_finite(add(a.value, b.value if op == "+" else neg(b.value)), node, a, b),
                     dim)
        a = self.ev(node.left)
        b = self.ev(node.right)
        if op == "*":
            if a.is_vector and b.is_vector:
                raise ProblemError("cannot multiply two vectors; use dot(a, b) or cross(a, b)",
                                   node.span, code="type")
            dim = dim_mul(a.dim, b.dim)
            if a.is_vector:
                return Q(a.value.scale(b.value), dim)
            if b.is_vector:
                return Q(b.value.scale(a.value), dim)
            return Q(_finite(mul(a.value, b.value), node, a, b), dim)
        if op == "/":
            if b.is_vector:
                raise ProblemError("cannot divide by a vector", node.right.span, code="type")
            if isinstance(b.value, Const) and b.value.value == 0.0:
                raise ProblemError("division by zero", node.right.span, code="number")
            inv = _finite(power(b.value, -1.0), node, b)
            dim = dim_div(a.dim, b.dim)
            if a.is_vector:
                return Q(a.value.scale(inv), dim)
            return Q(_finite(mul(a.value, inv), node, a, b), dim)
        # power
        if a.is_vector or b.is_vector:
            raise ProblemError("cannot raise a vector to a power", node.span, code="type")
        if b.dim != NONE:
            raise ProblemError(f"an exponent must be a plain number; got {describe(b.dim)}",
                               node.right.span, code="units")
        if not isinstance(b.value, Const):
            raise ProblemError("an exponent must be a constant", node.right.span, code="type")
        p = b.value.value
        dim = dim_pow(a.dim, p)
        if dim is None:
            raise ProblemError(f"cannot raise {describe(a.dim)} to the power {p:g}", node.span,
                               code="units")
        if isinstance(a.value, Const) and a.value.value < 0 and p != int(p):
            raise ProblemError("a negative number to a fractional power", node.span,
                               code="number")
        if isinstance(a.value, Const) and a.value.value == 0 and p < 0:
            raise ProblemError("division by zero", node.span, code="number")
        return Q(_finite(power(a.value, p), node, a), dim)

    def _call(self, node: S.Call) -> Q:
        name = node.fn
        args = [self.ev(a) for a in node.args]
        want = {"atan2": 2, "dot": 2, "cross": 2, "min": 2, "max": 2}.get(name, 1)
        if name not in KNOWN_FUNCS:
            from .diagnostics import did_you_mean

            raise ProblemError(f"unknown function '{name}'" + did_you_mean(name, KNOWN_FUNCS),
                               node.fn_span, code="name")
        if len(args) != want:
            raise ProblemError(f"{name}() takes {want} argument{'s' if want > 1 else ''}; got "
                               f"{len(args)}", node.span, code="type")
        if name in ("dot", "cross"):
            a, b = args
            if not (a.is_vector and b.is_vector):
                raise ProblemError(f"{name}() takes two vectors", node.span, code="type")
            v = a.value.dot(b.value) if name == "dot" else a.value.cross(b.value)
            return Q(v, dim_mul(a.dim, b.dim))
        if name == "norm":
            (a,) = args
            if not a.is_vector:
                raise ProblemError("norm() takes a vector", node.span, code="type")
            v = a.value
            return Q(power(add(mul(v.x, v.x), mul(v.y, v.y)), 0.5), a.dim)
        for a, sub in zip(args, node.args):
            if a.is_vector:
                raise ProblemError(f"{name}() takes a scalar; got a vector", sub.span,
                                   code="type")
        if name == "atan2":
            y, x = args
            _common_dim(y, x, node, "compare")
            return Q(_atan2(y.value, x.value, node), NONE)
        if name in ("min", "max"):
            a, b = args
            dim = _common_dim(a, b, node, "compare")
            if isinstance(a.value, Const) and isinstance(b.value, Const):
                f = min if name == "min" else max
                return Q(Const(f(a.value.value, b.value.value)), dim)
            raise ProblemError(f"{name}() takes constants", node.span, code="type")
        (a,) = args
        if name == "sqrt":
            dim = dim_pow(a.dim, 0.5)
            if dim is None:
                raise ProblemError(f"cannot take the square root of {describe(a.dim)}",
                                   node.span, code="units")
            if isinstance(a.value, Const) and a.value.value < 0:
                raise ProblemError(f"square root of a negative number ({a.value.value:g})",
                                   node.span, code="number")
            return Q(power(a.value, 0.5), dim)
        if name == "abs":
            return Q(fn("abs", a.value), a.dim)
        if a.dim != NONE:
            raise ProblemError(f"{name}() takes a plain number or an angle; got "
                               f"{describe(a.dim)}", node.args[0].span, code="units")
        if name in ("asin", "acos") and isinstance(a.value, Const) and abs(a.value.value) > 1:
            raise ProblemError(f"{name}() of {a.value.value:g}: outside [-1, 1]", node.span,
                               code="number")
        if name in ("ln", "log") and isinstance(a.value, Const) and a.value.value <= 0:
            raise ProblemError(f"{name}() of a number that is not positive", node.span,
                               code="number")
        return Q(_finite(fn(name, a.value), node, a), NONE)


def _finite(r: E, node, *operands: Q) -> E:
    """`r`, unless it is a constant that overflowed: not finite, or left unevaluated by
    `power`/`fn` (they keep a constant expression symbolic when Python overflows)."""
    overflowed = operands and all(isinstance(q.value, Const) for q in operands) and \
        not isinstance(r, Const)
    if overflowed or (isinstance(r, Const) and not math.isfinite(r.value)):
        raise ProblemError("the result is too large or not a number", node.span, code="number")
    return r


def _atan2(y: E, x: E, node) -> E:
    if isinstance(y, Const) and isinstance(x, Const):
        return Const(math.atan2(y.value, x.value))
    # atan2(y, x) = 2 atan(y / (sqrt(x^2 + y^2) + x)), exact except on the negative x axis
    r = power(add(mul(x, x), mul(y, y)), 0.5)
    return mul(Const(2.0), fn("atan", mul(y, power(add(r, x), -1.0))))


def _common_dim(a: Q, b: Q, node, verb: str) -> Dim:
    if a.dim != b.dim:
        raise ProblemError(f"cannot {verb} {describe(a.dim)} and {describe(b.dim)}",
                           node.span, code="units")
    return a.dim


def constant(q: Q, node) -> float:
    """The float of a scalar quantity that must be a constant."""
    if q.is_vector:
        raise ProblemError("expected a scalar, got a vector", node.span, code="type")
    if not isinstance(q.value, Const):
        raise ProblemError("expected a constant; this depends on unknowns", node.span,
                           code="type")
    return q.value.value


def constant_vector(q: Q, node) -> tuple[float, float]:
    if not q.is_vector:
        raise ProblemError("expected a vector such as (1, 0)", node.span, code="type")
    v = q.value
    if not (isinstance(v.x, Const) and isinstance(v.y, Const)):
        raise ProblemError("expected a constant vector; this depends on unknowns", node.span,
                           code="type")
    return (v.x.value, v.y.value)
