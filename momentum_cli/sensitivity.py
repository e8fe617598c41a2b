"""Sensitivities: d answer / d given number, through the solved system.

Stage: after solve. In: the parsed document and its `Solution`. Out: `Sensitivities`,
for every `find` answer and every given number of the file (`given_numbers.py`), the
derivative and its relative form d ln(answer) / d ln(given).

The implicit function theorem, block by block in the order solve used: each block
F_b(x_b; x_prev, p) = 0 gives dx_b/dp = -J_b^-1 (dF_b/dp + dF_b/dx_prev . dx_prev/dp),
with J_b and dF_b/dx_prev from the symbolic derivatives of the equation trees at the
solution. A given number enters the trees through the scene (a mass, an inertia
m L^2/12, a moment arm from an angle), so dF/dp, the explicit dependence at the fixed
solution, is exact: one build and compile with every number a traced leaf
(traced_partials.py), then expr.diff. A number the trace does not see (folded by code
outside it) is found by a probe compile and only it gets a residual difference (the
file recompiled with it moved, a central difference, error ~1e-10), said in the note.
Friction regimes and root choices are those of the solution, held fixed; derived
answers (`find NAME = expr`, speeds, T_lost) are differentiated through their trees.
A number that a redundant equation ties to others has no derivative of its own (said
why); where the numbers leave an impulse's split free, only the determined unknowns
get derivatives.
"""
from __future__ import annotations

import math

from .bounds import size_of
from .compile import compile_scene
from .diagnostics import ProblemError
from .expr import diff, evaluate, magnitude, variables
from .given_numbers import GivenNumber, given_numbers, replaced
from .gradient import gradient
from .records import field, record
from .traced_partials import traced_partials

STEP = 1e-5  # the central difference's step, relative to the number (absolute for a zero
# with a unit): the residuals are evaluated, not solved, so the error is ~(h^2 + eps/h) ~ 1e-10
TIED = 1e-7  # a redundant equation moved more than this (relative to its terms) is broken
EDGE_STEP = 1e-6  # a one-sided step, where one side leaves the problem's domain (e = 1)
NOTE = ("friction regimes and root choices held fixed; per the unit each number is "
        "written in")


@record
class AnswerSensitivity:
    name: str
    value: float  # in the answer's display unit
    unit: str
    derivatives: dict[str, float]  # parameter id -> d answer / d parameter
    size: float = 0.0  # the size of the terms that make the answer (display unit)


@record
class Sensitivities:
    parameters: list[GivenNumber]
    answers: list[AnswerSensitivity] = field(default_factory=list)
    unavailable: str | None = None  # why none could be computed
    skipped: dict = field(default_factory=dict)  # parameter id -> why it has no derivative
    note: str = NOTE
    by_difference: dict = field(default_factory=dict)  # parameter id -> why its dF/dp is a
    # residual difference (a number the trace does not see), not exact

    def relative(self, a: AnswerSensitivity, pid: str) -> float | None:
        """d ln(answer) / d ln(given); None for a zero answer."""
        p = next(q for q in self.parameters if q.id == pid)
        d = a.derivatives[pid]
        if a.value == 0 or not math.isfinite(d):
            return None
        return d * p.value / a.value

    def ranked(self, a: AnswerSensitivity) -> list[str]:
        """Parameter ids by how much a 1 % change moves the answer, largest first."""
        return sorted(a.derivatives, key=lambda pid: (-self.effect(a, pid), int(pid[1:])))

    def effect(self, a: AnswerSensitivity, pid: str) -> float:
        """|d answer / d ln given|: what a relative change moves (per unit for a zero)."""
        p = next(q for q in self.parameters if q.id == pid)
        return abs(a.derivatives[pid] * (p.value or 1.0))


def sensitivities(doc, sol, build=None) -> Sensitivities:
    """The sensitivities of `sol` (solved from `doc`) to every given number of `doc`; a
    number that fails on the way (an overflow in a derivative) makes the section say so
    and never costs the file its answers."""
    import numpy as np

    params = given_numbers(doc)
    out = Sensitivities(params)
    try:
        return _sensitivities(doc, sol, build, out)
    except (KeyError, ValueError, ZeroDivisionError, OverflowError,
            np.linalg.LinAlgError) as exc:
        out.answers = []
        out.unavailable = f"the derivatives could not be computed ({type(exc).__name__})"
        return out


def _sensitivities(doc, sol, build, out: Sensitivities) -> Sensitivities:
    import numpy as np

    if build is None:
        from .scene import build
    params = out.parameters
    system = sol.system
    why = _unsupported(sol)
    if why:
        out.unavailable = why
        return out
    values = sol.values
    eqs = system.equations
    solved = [k for rep in sol.blocks for k in rep.equations]
    free = sorted({v for k in solved for v in variables(eqs[k].residual)} - values.keys())
    if free:  # a rank-revealed block: the numbers leave these free, the rows share them
        values = _with_free(eqs, solved, values, free)
        if values is None:
            out.unavailable = f"a block leaves {', '.join(free[:3])} free and its rows are " \
                              "not linear in them"
            return out
    checks = _checks(system, set(solved), values)
    rows = solved + checks
    finds = system.finds
    base = _residuals(system, rows, values)
    # dF/dx and the answers' dF/dx at the solution, from the trees' derivatives
    jac = {k: _gradient(eqs[k].residual, values) for k in rows}
    fgrad = [_gradient(f.expr, values) for f in finds]
    # dF/dp and d answer/dp at fixed x, for each given number
    n = len(params)
    Fp = np.zeros((len(rows), n))
    Ap = np.zeros((len(finds), n))
    ok = np.ones(n, dtype=bool)
    exact = traced_partials(doc, params, system, sol.regimes, rows, values, build)
    if isinstance(exact, str):  # the whole trace is unusable: every number by difference
        out.note += f"; dF/dp by residual differences: {exact}"
        by_difference = {p.id: exact for p in params}
    else:
        by_difference = exact.untraced
        whys: dict = {}  # why -> the numbers, in the file's order
        for pid, why in sorted(by_difference.items(), key=lambda kv: int(kv[0][1:])):
            whys.setdefault(why, []).append(f"d/d{pid}")
        for why, ds in whys.items():
            out.note += f"; {', '.join(ds)} by a residual difference: {why}"
    out.by_difference = dict(by_difference)
    for j, prm in enumerate(params):
        if prm.id not in by_difference:
            Fp[:, j], Ap[:, j] = exact.rows[prm.id], exact.finds[prm.id]
            continue
        col = _explicit(doc, prm, system, sol.regimes, rows, values, base, build)
        if isinstance(col, str):
            out.skipped[prm.id] = col
            ok[j] = False
            continue
        Fp[:, j], Ap[:, j] = col
    # forward through the blocks: dx_b/dp = -J_b^-1 (dF_b/dp + dF_b/dx_prev dx_prev/dp)
    dx: dict = {}
    pos = {k: i for i, k in enumerate(rows)}
    for rep in sol.blocks:
        # a free unknown (one split of an impulse among many), or one a rank-revealed
        # block's rows share with a later block, is a column here too (minimum norm):
        # only the block's own unknowns, the determined ones, are unique and kept
        names = list(rep.unknowns) + sorted({v for k in rep.equations for v in jac[k]
                                             if v not in dx and v not in rep.unknowns})
        idx = {v: i for i, v in enumerate(names)}
        J = np.zeros((len(rep.equations), len(names)))
        rhs = np.zeros((len(rep.equations), n))
        for r, k in enumerate(rep.equations):
            rhs[r] = -Fp[pos[k]]
            for v, d in jac[k].items():
                if v in idx:
                    J[r, idx[v]] = d
                else:
                    rhs[r] -= d * dx[v]
        if J.shape[0] == J.shape[1]:
            try:
                sol_b = np.linalg.solve(J, rhs)
            except np.linalg.LinAlgError:
                sol_b = np.linalg.lstsq(J, rhs, rcond=None)[0]
        else:
            sol_b = np.linalg.lstsq(J, rhs, rcond=None)[0]
        for v in rep.unknowns:
            dx[v] = sol_b[idx[v]]
    # a redundant equation that the number alone breaks: the file ties the number to
    # others (equal masses that make one `e` fit two contacts), so it has no derivative
    for k in checks:
        if not jac[k].keys() <= dx.keys():
            continue  # it holds a split that the numbers leave free
        dr = Fp[pos[k]] + sum(d * dx[v] for v, d in jac[k].items())
        size = _size(eqs[k], values)
        for j, prm in enumerate(params):
            if ok[j] and abs(dr[j] * prm.value) > TIED * size:
                ok[j] = False
                line = f"line {eqs[k].span.line}" if eqs[k].span else "the scene"
                out.skipped[prm.id] = f"moving it alone breaks equation ({k + 1}), " \
                    f"{eqs[k].principle} ({line})"
    for i, f in enumerate(finds):
        name, shown, unit, si = sol.answers[i]
        d = Ap[i].copy()
        for v, g in fgrad[i].items():
            if v not in dx:
                out.unavailable = f"{f.name} needs {v}, which no solved block gives"
                return out
            d += g * dx[v]
        d /= f.factor
        try:
            size = size_of(f.expr, values, sol.size or {}) / abs(f.factor)
        except (KeyError, ValueError, ZeroDivisionError, OverflowError):
            size = abs(shown)
        out.answers.append(AnswerSensitivity(
            name, shown, unit,
            {p.id: float(d[j]) for j, p in enumerate(params) if ok[j]},
            size if math.isfinite(size) else abs(shown)))
    return out


def _unsupported(sol) -> str | None:
    """Why the solution's derivatives cannot be taken this way (None: they can)."""
    system = sol.system
    if system.integrations or any(b.method == "integrated" for b in sol.blocks):
        return "a phase is integrated numerically (its derivatives are not taken)"
    if system.path_laws:
        return "an impulse-path contact law (Poisson, Stronge) decides its impulses by " \
               "integration"
    if len(sol.answers) != len(system.finds):
        return "the answers could not all be computed"
    return None


def _checks(system, solved: set[int], values) -> list[int]:
    """The equations not solved for anything whose unknowns all have values and that
    hold: the redundant ones solve checked, and pure checks of the given numbers."""
    out = []
    for k, e in enumerate(system.equations):
        if k in solved or not variables(e.residual) <= values.keys():
            continue
        try:
            r, size = evaluate(e.residual, values), _size(e, values)
        except (ValueError, ZeroDivisionError, OverflowError):
            continue
        if size > 0 and abs(r) <= 1e-9 * size:
            out.append(k)
    return out


def _with_free(eqs, rows, values, free):
    """`values` with one choice (minimum norm) of the unknowns the numbers leave free, so
    that the rows can be evaluated and differentiated; None if they are not linear in
    them."""
    import numpy as np

    vals = dict(values)
    vals.update((v, 0.0) for v in free)
    use = [k for k in rows if variables(eqs[k].residual) & set(free)]
    A = np.array([[evaluate(diff(eqs[k].residual, v), vals) for v in free] for k in use])
    b = -np.array([evaluate(eqs[k].residual, vals) for k in use])
    x = np.linalg.lstsq(A, b, rcond=None)[0]
    vals.update(zip(free, map(float, x)))
    for k in use:
        if abs(evaluate(eqs[k].residual, vals)) > 1e-9 * max(_size(eqs[k], vals), 1e-300):
            return None
    return vals


def _size(e, values) -> float:
    """The scale of an equation's terms (both sides: `20 = 20` folds to a zero residual)."""
    return magnitude(e.lhs, values) + magnitude(e.rhs, values)


def _gradient(e, values) -> dict[str, float]:
    """d e / d x for each unknown of `e` that has a value (one reverse sweep when all
    have one, else `diff` per unknown)."""
    names = sorted(variables(e))
    if all(v in values for v in names):
        g = gradient(e, values)
        return {v: g.get(v, 0.0) for v in names}
    return {v: evaluate(diff(e, v), values) for v in names if v in values}


def _residuals(system, rows, values):
    """The residuals of `rows` and the `find` expressions at `values`, one vector."""
    import numpy as np

    r = [evaluate(system.equations[k].residual, values) for k in rows]
    r += [evaluate(f.expr, values) for f in system.finds]
    return np.array(r, dtype=float)


def _explicit(doc, prm: GivenNumber, system, regimes, rows, values, base, build):
    """(dF/dp, d answer/dp) at the fixed solution, or why the number has none."""
    p = prm.value
    h = STEP * abs(p) if p != 0 else STEP

    def at(delta):
        try:
            sc = build(replaced(doc, {id(n): p + delta for n in prm.nodes}))
            s2 = compile_scene(sc, dict(regimes))
        except ProblemError:
            return None
        if len(s2.equations) != len(system.equations) or len(s2.finds) != len(system.finds) \
                or any(s2.equations[k].principle != system.equations[k].principle
                       for k in rows):
            return None  # the number changes the structure: no derivative
        try:
            return _residuals(s2, rows, values)
        except (KeyError, ValueError, ZeroDivisionError, OverflowError):
            return None

    r1, m1 = at(h), at(-h)
    if r1 is not None and m1 is not None:
        d = (r1 - m1) / (2 * h)
    else:  # at the edge of the domain (e = 1, mu = 0): one side, a smaller step
        h = EDGE_STEP * abs(p) if p != 0 else EDGE_STEP
        side = 1.0 if r1 is not None else -1.0
        a, b = at(side * h), at(side * 2 * h)
        if a is None or b is None:
            return "moving it changes the problem's structure or leaves its domain"
        d = side * (-3 * base + 4 * a - b) / (2 * h)
    if not all(math.isfinite(x) for x in d):
        return "not differentiable here"
    return d[:len(rows)], d[len(rows):]
