"""Expectations: the `expect` lines of a problem file, built and checked (scene, then solve).

In: the parsed `Expect` statements (with the scene's constants) and, after solving, the
`Solution`. Out: `ExpectSpec`s (expected SI values, tolerances, the unit written) and
`ExpectCheck`s (met or not, the difference in the expectation's unit).
"""
from __future__ import annotations

import math
import re

from . import syntax as S
from .diagnostics import ProblemError, did_you_mean
from .quantity import constant, constant_vector, unit_readings
from .records import record
from .source import Span
from .units import NONE, Dim, describe, reading_for

# A value given by an expression (not a number as written): this relative tolerance.
EXPRESSION_RTOL = 1e-6
# Every diagnostic code a file can fail with (for `expect error CODE` and its "did you mean").
ERROR_CODES = ("syntax", "units", "name", "type", "number", "empty", "binary", "encoding",
               "too-large", "too-deep", "under-determined", "inconsistent", "no-solution",
               "singular", "ill-conditioned", "principle-does-not-hold", "ambiguous",
               "simulate", "integrated", "unreached")
_NUMBER = re.compile(r"(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?")


@record(frozen=True)
class ExpectSpec:
    """One `expect` line, in SI: a value per component (1 or 2) with its tolerance."""
    span: Span
    quantity: str  # as written: `rod.omega@3`
    name: str | None  # the answer's name (None: `expect error`)
    expected: tuple = ()  # SI value per component
    tolerance: tuple = ()  # SI half-width per component (absolute)
    how: str = ""  # "digits" | "abs" | "rel" | "expression": where the tolerance comes from
    unit: str = ""  # the unit the value is written in ("" if none)
    factor: float = 1.0  # SI per unit
    dim: Dim = NONE
    written: str = ""  # the value (and tolerance) as written
    error: str | None = None  # `expect error CODE`


@record(frozen=True)
class ExpectCheck:
    """The outcome of one expectation (per component)."""
    spec: ExpectSpec
    met: bool
    got: tuple = ()  # SI value per component (empty: not computed)
    message: str = ""  # `expected ... got ...` in the expectation's unit


def source_text(text: str, span: Span) -> str:
    """The text of a node on one line (for names of expected expressions)."""
    lines = text.split("\n")
    line = lines[span.line - 1] if span.line - 1 < len(lines) else ""
    if span.end_line == span.line and span.end_column:
        return line[span.column - 1: span.end_column - 1].strip()
    return line[span.column - 1:].strip()


def _first_unit(node):
    """The first unit written in the value: (unit, unit_span) or (None, None)."""
    if isinstance(node, S.Num):
        return (node.unit, node.unit_span) if node.unit else (None, None)
    for child in (getattr(node, "arg", None), getattr(node, "left", None),
                  getattr(node, "right", None), getattr(node, "x", None),
                  getattr(node, "y", None)):
        if child is not None:
            u = _first_unit(child)
            if u[0]:
                return u
    return None, None


def _components(node) -> list:
    if isinstance(node, S.VecLit):
        return [node.x, node.y]
    return [node]


def digits_tolerance(text: str, node) -> tuple[float, str | None] | None:
    """Half a unit in the last digit of a number as written (`-14.2` -> 0.05), in the
    number's own unit; None when the value is not a number as written."""
    if isinstance(node, S.Neg):
        node = node.arg
    if not isinstance(node, S.Num):
        return None
    line = text.split("\n")[node.span.line - 1]
    m = _NUMBER.match(line, node.span.column - 1)
    if not m:
        return None
    mant, exp = m.group(1), m.group(2)
    decimals = len(mant.split(".")[1]) if "." in mant else 0
    power = -decimals + (int(exp[1:]) if exp else 0)
    return 0.5 * 10.0 ** power, node.unit


def build_expects(items, ev, text: str, finds) -> tuple[list[ExpectSpec], list[S.FindItem]]:
    """The scene's expectations, and the `find` items they add (a quantity expected but
    not asked for is solved as if found, shown in the unit the expectation uses)."""
    specs, extra = [], []
    known = {f.name or (f.expr.text if isinstance(f.expr, S.Ref) else None) for f in finds}
    for e in items:
        if e.error is not None:
            specs.append(ExpectSpec(e.span, f"error {e.error}", None, error=e.error))
            continue
        unit, unit_span = _first_unit(e.value)
        hint = unit_readings(unit, unit_span)[0][1] if unit else None
        q = ev(e.value, hint)  # the hint lets a bare 0 take the unit's dimension
        if q.is_vector:
            expected = constant_vector(q, e.value)
        else:
            expected = (constant(q, e.value),)
        if not all(math.isfinite(v) for v in expected):
            raise ProblemError("the expected value is not a finite number", e.value.span,
                               code="number")
        factor = 1.0
        if unit:
            match = [f for f, d in unit_readings(unit, unit_span) if d == q.dim]
            factor = match[0] if match else unit_readings(unit, unit_span)[0][0]
        comps = _components(e.value)
        dim = q.dim
        if e.tolerance is not None:
            t = ev(e.tolerance)
            if t.is_vector:
                raise ProblemError("a tolerance is a scalar", e.tolerance.span, code="type")
            tol = abs(constant(t, e.tolerance))
            dim = q.dim
            if not unit and t.dim != NONE and not any(expected):  # `0 ± 1e-9 m/s`
                unit, unit_span = _first_unit(e.tolerance)
                dim = t.dim
                factor = reading_for(unit_readings(unit, unit_span), dim)[0] if unit else 1.0
            if t.dim == NONE and dim != NONE:
                tol *= factor  # `± 0.01` in the value's unit
            elif t.dim != dim:
                raise ProblemError(f"the tolerance needs {describe(q.dim)}; got "
                                   f"{describe(t.dim)}", e.tolerance.span, code="units")
            tols, how = tuple(tol for _ in expected), "abs"
        elif e.percent is not None:
            p = ev(e.percent, NONE)
            if p.dim != NONE or p.is_vector:
                raise ProblemError("`within P %` takes a plain number of percent",
                                   e.percent.span, code="units")
            rel = abs(constant(p, e.percent)) / 100.0
            tols, how = tuple(rel * abs(v) for v in expected), "rel"
        else:
            tols, how = [], "digits"
            for c, v in zip(comps if len(comps) == len(expected) else [None] * len(expected),
                            expected):
                d = digits_tolerance(text, c) if c is not None else None
                if d is None:
                    tols.append(EXPRESSION_RTOL * abs(v))
                    how = "expression"
                    continue
                half, own = d
                f = factor
                if own:
                    readings = unit_readings(own, None)
                    f = next((r for r, dd in readings if dd == q.dim), readings[0][0])
                tols.append(half * f)
            tols = tuple(tols)
        qty = source_text(text, e.quantity.span) if not isinstance(e.quantity, S.Ref) \
            else e.quantity.text
        written = source_text(text, Span(e.value.span.line, e.value.span.column,
                                         e.span.line, None))
        specs.append(ExpectSpec(e.span, qty, qty, tuple(expected), tols, how, unit or "",
                                factor, dim, written))
        if qty not in known:
            known.add(qty)
            name = None if isinstance(e.quantity, S.Ref) else qty
            extra.append(S.FindItem(e.quantity.span, name, e.quantity,
                                    unit if unit and not q.is_vector else None,
                                    unit_span if unit and not q.is_vector else None))
    return specs, extra


def component_names(name: str, answers: dict) -> list[str] | None:
    """The answers that hold an expected quantity: itself, or its two components."""
    if name in answers:
        return [name]
    for member, comps in ((".v@", (".vx@", ".vy@")), (".pos@", (".x@", ".y@"))):
        if member in name:
            names = [name.replace(member, c) for c in comps]
            if all(n in answers for n in names):
                return names
    names = [f"{name}.x", f"{name}.y"]
    return names if all(n in answers for n in names) else None


def fmt(x: float, sig: int = 6) -> str:
    from .numbers import fmt_num

    return fmt_num(x, sig)


def check_solution(specs: list[ExpectSpec], sol) -> list[ExpectCheck]:
    """Compare each expectation with the solved answers (SI), in the expectation's unit."""
    answers: dict[str, tuple[float, Dim]] = {}
    dims = {f.name: f.dim for f in sol.system.finds}
    for name, _, _, si in sol.answers:
        answers.setdefault(name, (si, dims.get(name, NONE)))
    out = []
    for s in specs:
        if s.error is not None:
            out.append(ExpectCheck(s, False, (), f"expected error {s.error}, got solved"))
            continue
        names = component_names(s.name, answers)
        if names is None or len(names) != len(s.expected):
            shape = "a vector" if names and len(names) == 2 else "a scalar"
            raise ProblemError(f"{s.quantity} is {shape}; the expected value is not",
                               s.span, code="type")
        dim = answers[names[0]][1]
        if dim != s.dim and any(v != 0 for v in s.expected):
            raise ProblemError(f"{s.quantity} is {describe(dim)}; the expected value is "
                               f"{describe(s.dim)}", s.span, code="units")
        got = tuple(answers[n][0] for n in names)
        ok = all(g is not None and math.isfinite(g) and
                 abs(g - v) <= t * (1 + 1e-9) + 1e-12 * abs(v)
                 for g, v, t in zip(got, s.expected, s.tolerance))
        out.append(ExpectCheck(s, ok, got, describe_check(s, got, ok)))
    return out


def describe_check(s: ExpectSpec, got, ok: bool) -> str:
    """`expected -14.2 +- 0.05 rad/s, got -14.1637 rad/s (difference 0.0363 rad/s)`."""
    unit = f" {s.unit}" if s.unit else ""
    f = s.factor or 1.0

    def vec(vals, sig=6):
        vs = [fmt(v / f, sig) if v is not None else "-" for v in vals]
        return vs[0] if len(vs) == 1 else f"({', '.join(vs)})"

    tol = vec(s.tolerance, 3) if len(set(s.tolerance)) > 1 else \
        fmt(s.tolerance[0] / f, 3) if s.tolerance else "0"
    diff = [g - v if g is not None else math.nan for g, v in zip(got, s.expected)]
    worst = max(diff, key=lambda d: abs(d) if math.isfinite(d) else math.inf)
    return (f"{'met' if ok else 'not met'}: expected {s.quantity} = {vec(s.expected)} "
            f"+- {tol}{unit}, got {vec(got)}{unit} (difference "
            f"{fmt(worst / f, 3) if math.isfinite(worst) else '-'}{unit})")


def check_error(specs: list[ExpectSpec], diagnostics) -> list[ExpectCheck]:
    """A file that did not solve: each `expect error CODE` is met if an error has that
    code; every value expectation is not met."""
    codes = [d.code for d in diagnostics if d.severity == "error"]
    got = ", ".join(dict.fromkeys(codes)) or "no error"
    out = []
    for s in specs:
        if s.error is not None:
            ok = s.error in codes
            hint = "" if ok or s.error in ERROR_CODES else did_you_mean(s.error, ERROR_CODES)
            out.append(ExpectCheck(s, ok, (), f"{'met' if ok else 'not met'}: expected error "
                                   f"{s.error}, got error {got}{hint}"))
        else:
            out.append(ExpectCheck(s, False, (), f"not met: expected {s.quantity} = "
                                   f"{s.written}, got error {got}"))
    return out


_EXPECT = re.compile(r"^[ \t]*expect[ \t]+(error[ \t]+([A-Za-z_][A-Za-z_0-9-]*)|"
                     r"([^=#\n]+?)[ \t]*=[ \t]*([^#\n]*?))[ \t]*(#.*)?$", re.M)


def scan_expects(text: str) -> list[ExpectSpec]:
    """The `expect` lines of a file that did not build, read line by line (no parse):
    enough to check `expect error CODE` and to name the values that were not reached."""
    out = []
    for m in _EXPECT.finditer(text):
        line = text.count("\n", 0, m.start()) + 1
        if m.group(2):
            out.append(ExpectSpec(Span(line, 1), f"error {m.group(2)}", None, error=m.group(2)))
        else:
            q = m.group(3).strip()
            out.append(ExpectSpec(Span(line, 1), q, q, written=m.group(4).strip()))
    return out
