"""Report stage: a transition's system statements as the report shows them.

In: the `SystemLaw`s compile found for an impact (system momentum, moments about a pin),
the solved values, the reader's units. Out: plain dicts (principle, why, the
parallel-axis step, the equation symbolically and with the known numbers, and the
common velocity of bodies that move together), which every renderer lays out.
"""
from __future__ import annotations

import re
from collections import ChainMap

from ..expr import (
    Add,
    Const,
    Known,
    Mul,
    NonLinear,
    Var,
    add_all,
    affine,
    map_children,
    mul,
    to_text,
    variables,
)
from ..numbers import fmt_num
from ..units import INERTIA, LENGTH, MASS, VELOCITY
from .printer import lines
from .reader import Reader, lines_in, si_lines


class _Eq:
    """An equation-like pair for the printers (lhs, rhs, text)."""

    _texts = None  # as an Equation's: nothing printed yet

    def __init__(self, lhs, rhs):
        self.lhs, self.rhs = lhs, rhs

    def text(self, numeric: bool = False) -> str:
        return f"{to_text(self.lhs, numeric)} = {to_text(self.rhs, numeric)}"


def _variables(e) -> set:
    """`expr.variables(e)`, the same set built in the same order: a sum's products (a
    law's m*v terms) read in the sum's loop, not by a call each."""
    if type(e) is not Add:
        return variables(e)
    out: set = set()
    put = out.add
    for x in e.terms:
        tx = type(x)
        if tx is Var:
            put(x.name)
        elif tx is Mul:
            fs = x.factors
            for f in fs:  # a zero known factor: the product drops out
                if (type(f) is Const or type(f) is Known) and f.value == 0.0:
                    break
            else:
                for f in fs:
                    tf = type(f)
                    if tf is Var:
                        put(f.name)
                    elif tf is not Const and tf is not Known:
                        variables(f, out)
        elif tx is not Const and tx is not Known:
            variables(x, out)
    return out


def _moving_together(law, values, rhs_names=None) -> bool:
    """Every body has the same velocity component afterwards (to round-off);
    `rhs_names`: `variables(law.rhs)` if already taken."""
    if law.locked is None:
        return False
    comps = [values.get(n) for n in (variables(law.rhs) if rhs_names is None else rhs_names)]
    if any(v is None for v in comps) or len(comps) < 2:
        return False
    scale = max(abs(v) for v in comps) or 1.0
    return max(comps) - min(comps) <= 1e-9 * scale


def _arms(moments, t, values):
    """The moments about the pin as (arm)*(impulse) terms: the positions are those of
    the state before the impact, known here, so each impulse has one numeric arm."""
    impulses = {n for n in variables(moments) if n.endswith(f"@{t.key}")}
    try:
        coef, const = affine(moments, impulses, values)
    except (NonLinear, KeyError, ValueError, ZeroDivisionError, OverflowError):
        return moments
    scale = max((abs(c) for c in coef.values()), default=0.0)
    terms = [Mul((Const(c), Var(n))) if c != 1.0 else Var(n)
             for n, c in coef.items() if abs(c) > 1e-14 * scale]
    if const != 0.0:
        terms.append(Const(const))
    return add_all(terms) if terms else Const(0.0)


_VELOCITY = re.compile(r"\.(vx|vy)@")


def _named(e, given: dict):
    """`e` with the velocities it knows by name as unknowns, so that they keep their
    names through `affine`; their values go into `given`."""
    t = type(e)
    if t is Known and (_VELOCITY.search(e.name) or ".omega@" in e.name):
        given[e.name] = e.value
        return Var(e.name)
    return map_children(e, lambda x, _in_fn: _named(x, given))


def _moments(law, part, values, given: dict):
    """One side of a pinned system's angular momentum: I_O w of the pinned body, then
    for each other body m*(arm*v + ...) with its arms about O as numbers."""
    w, side = part
    p = law.parallel
    terms = [mul(Known(f"I_{p['point']}", p["I_O"]), _named(w, given))]
    for m, rxv, spin in side:
        rxv = _named(rxv, given)
        vs = {n for n in variables(rxv) if _VELOCITY.search(n)}
        known = {n: values[n] for n in variables(rxv) - vs if n in values}
        try:
            coef, const = affine(rxv, vs, ChainMap(known, given, values))
        except (NonLinear, KeyError, ValueError, ZeroDivisionError, OverflowError):
            return None
        scale = max((abs(c) for c in coef.values()), default=0.0)
        arm = add_all([Mul((Const(c), Var(n))) for n, c in sorted(coef.items())
                       if abs(c) > 1e-14 * scale] + ([Const(const)] if const else []))
        terms.append(Mul((m, arm)))
        if spin is not None:
            terms.append(_named(spin, given))
    return add_all(terms)


def statements(t, values: dict, system, reader: Reader, sig: int = 6,
               numbers: tuple | None = None) -> list[dict]:
    """One dict per system law of transition `t`: kind, principle, why, steps (lines
    before the equation: the parallel-axis step), symbolic, numeric, result (lines after:
    the common velocity). `numbers`: the numbers printed so far to 6 and to `sig`
    figures (value -> text), kept by the caller across transitions (`printer.lines`)."""
    out = []
    shown: set = set()  # a pin's parallel-axis step is shown once per transition
    si = reader.system != "us" and not reader.degrees  # the printers per shape (printer.py)
    if numbers is None:
        six: dict = {}
        numbers = (six, six if sig == 6 else {})
    six, shown_numbers = numbers[0], numbers[1]
    # build_report's: whether its scene is big enough for the printers, the angles' test
    # (else the printers for SI in radians, as `lines` decides)
    printers, angle = (numbers[2], numbers[3]) if len(numbers) > 2 else (si, None)
    for law in getattr(t, "laws", ()) or ():
        steps, result = [], []
        rhs = law.rhs
        rhs_names = _variables(law.rhs)
        lhs_names = _variables(law.lhs)
        names = lhs_names | rhs_names
        if law.kind == "linear" and all(values.get(n, 1.0) == 0 for n in names):
            continue  # nothing moves along it: 0 = 0 says nothing
        vals = values
        if law.kind == "linear" and _moving_together(law, values, rhs_names):
            rhs = law.locked
            vals = ChainMap({k: values[v] for k, v in law.alias.items() if v in values}, values)
            for k, v in law.alias.items():
                if v in values:
                    v_shown = values[v] / reader.factor(VELOCITY)
                    result.append(f"{k} = {fmt_num(v_shown, sig)} {reader.label(VELOCITY)}: "
                                  "the bodies move together")
        lhs = law.lhs
        if law.kind == "pin":
            rhs = _arms(rhs, t, values)
        elif law.kind == "pin-system":
            given: dict = {}
            lhs, rhs = (_moments(law, part, values, given) for part in law.parts)
            if lhs is None or rhs is None:
                lhs, rhs = law.lhs, law.rhs
            else:
                vals = ChainMap(given, values)
        eq = _Eq(lhs, rhs)
        both = names if lhs is law.lhs and rhs is law.rhs else \
            (lhs_names if lhs is law.lhs else variables(lhs)) | variables(rhs)  # known ones
        after, key = f"@{t.after}", f"@{t.key}"  # a state quantity after it, its impulses
        keep = {n for n in both if "'" in n or n.endswith(after) or n.endswith(key)}
        p = law.parallel
        if p is not None and (p["body"], p["point"]) not in shown:
            shown.add((p["body"], p["point"]))
            I_G, m, d, I_O = (p["I_G"] / reader.factor(INERTIA), p["m"] / reader.factor(MASS),
                              p["d"] / reader.factor(LENGTH), p["I_O"] / reader.factor(INERTIA))
            f = lambda x: fmt_num(x, sig)  # noqa: E731
            steps.append(f"I_{p['point']} = I_G + m*d^2 = {f(I_G)} + {f(m)}*{f(d)}^2 = {f(I_O)} "
                          f"{reader.label(INERTIA)} (parallel axes: {p['body']}'s G is "
                          f"{f(d)} {reader.label(LENGTH)} from {p['point']})")
        got = lines(eq, vals, keep, sig, six, shown_numbers) if si and printers else None
        if got is None and reader.system != "us":
            got = si_lines(eq, vals, keep, sig, six, shown_numbers,
                           angle if reader.degrees else None) \
                if angle is not None or not reader.degrees else None
        if got is None:
            got = lines_in(eq, vals, keep, system, reader, sig)
        out.append(dict(kind=law.kind, principle=law.principle, why=law.why, steps=steps,
                        symbolic=got[0], numeric=got[1], result=result))
    return out


def unknown_names(text: str) -> set[str]:
    """The quantity names in a printed line (`rod.vx@2`, `J_n[A]@1->2`, `vx'@2`)."""
    return set(re.findall(r"[A-Za-z_][\w.\[\]\-']*@[\w>\-]+", text))
