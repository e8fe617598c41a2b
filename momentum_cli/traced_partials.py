"""How the given numbers enter the compiled equations: dF/dp, exact, by tracing.

Stage: after solve (for sensitivity.py). In: the parsed document, the solution's system,
regimes and values, its given numbers. Out: `Partials`, d residual / d number and
d answer / d number at the solution for every number, from ONE build and compile in
which every literal is a `sweep.trace.Traced` leaf (the compiled trees then hold each
number's part as a tree over the leaves: its derivative, gradient.py, is exact). One probe compile
with every number moved checks that nothing was folded outside the trace (math.cos of
a float); the numbers it finds (by halving) are `untraced`, left to a residual difference.
"""
from __future__ import annotations

from .diagnostics import ProblemError
from .expr import Add, Const, Fn, Known, Mul, Pow, Var, evaluate, magnitude, variables
from .given_numbers import replaced
from .gradient import gradient
from .records import record
from .sweep import trace

MOVE = 1e-3  # the probe's relative move of each number: far above round-off (1e-16),
# so a number folded outside the trace shows as a mismatch of ~1e-3 of its term
MATCH = 1e-9  # traced and ordinary residuals agree to this, relative to their terms


@record
class Partials:
    rows: list  # per parameter id: d residual / d number (a list over rows)
    finds: list  # per parameter id: d answer / d number (over the finds)
    untraced: dict  # parameter id -> why its derivative is not from the trace


def traced_partials(doc, params, system, regimes, rows, values, build) -> Partials | str:
    """d F / d p at `values` for every given number (str: why the trace cannot be used,
    e.g. the traced compile has another structure)."""
    pv = {_name(p.id): float(p.value) for p in params}
    tdoc = replaced(doc, {id(n): trace.leaf(p.id, float(p.value)) for p in params
                         for n in p.nodes})
    try:
        with trace.keeping():
            ts = _compile(tdoc, regimes, build)
            for e in ts.equations:  # built lazily: here, where traced terms are kept
                e.residual  # noqa: B018
    except ProblemError as exc:
        return f"the traced compile fails ({exc.message})"
    if not _same_shape(ts, system):
        return "the traced compile has other equations"
    memo: dict = {}
    trees = [_lift(ts.equations[k].residual, memo) for k in rows] + \
        [_lift(f.expr, memo) for f in ts.finds]
    plain = [system.equations[k].residual for k in rows] + [f.expr for f in system.finds]
    vals = dict(values)
    vals.update(pv)
    try:
        for t, e in zip(trees, plain):  # at the numbers as given: the same residuals
            if not _close(evaluate(t, vals), evaluate(e, values),
                          magnitude(e, values) + magnitude(t, vals)):
                return "the traced equations differ from the solved ones"
    except (KeyError, ValueError, ZeroDivisionError, OverflowError) as exc:
        return f"the traced equations cannot be evaluated ({type(exc).__name__})"
    n_rows = len(rows)
    cols_r = {p.id: [0.0] * n_rows for p in params}
    cols_f = {p.id: [0.0] * len(system.finds) for p in params}
    for i, t in enumerate(trees):
        names = variables(t) & pv.keys()
        g = gradient(t, vals) if names else {}
        for name in sorted(names):
            d = g.get(name, 0.0)  # = evaluate(diff(t, name), vals), all in one sweep
            pid = name[len(trace.PREFIX):]
            if i < n_rows:
                cols_r[pid][i] = d
            else:
                cols_f[pid][i - n_rows] = d
    untraced = _untraced(doc, params, system, regimes, rows, trees, values, pv, build)
    return Partials(cols_r, cols_f, untraced)


def _name(pid: str) -> str:
    return trace.PREFIX + pid


def _compile(doc, regimes, build):
    from .compile import compile_scene

    return compile_scene(build(doc), dict(regimes))


def _same_shape(s2, system) -> bool:
    return len(s2.equations) == len(system.equations) and \
        len(s2.finds) == len(system.finds) and \
        all(a.principle == b.principle for a, b in zip(s2.equations, system.equations))


def _close(a: float, b: float, size: float) -> bool:
    return abs(a - b) <= MATCH * (size + abs(a) + abs(b)) + 1e-300


def _untraced(doc, params, system, regimes, rows, trees, values, pv, build) -> dict:
    """The numbers whose effect the trace misses, by probe compiles with numbers moved:
    all at once first (one compile when the trace is whole), then halves of a set that
    disagrees, down to the single numbers."""
    moved = {p.id: _moved(p, j) for j, p in enumerate(params)}
    out: dict = {}

    def probe(group) -> str:
        new = {id(n): moved[p.id] for p in group for n in p.nodes}
        try:
            s2 = _compile(replaced(doc, new), regimes, build)
        except ProblemError:
            return "moving it changes the problem"
        if not _same_shape(s2, system):
            return "moving it changes the equations"
        vals = dict(values)
        vals.update(pv)
        vals.update((_name(p.id), moved[p.id]) for p in group)
        got = [s2.equations[k].residual for k in rows] + \
            [f.expr for f in s2.finds]
        try:
            for t, e in zip(trees, got):
                if not _close(evaluate(t, vals), evaluate(e, values),
                              magnitude(e, values) + magnitude(t, vals)):
                    return "a number computed outside the trace"
        except (KeyError, ValueError, ZeroDivisionError, OverflowError):
            return "moving it leaves the domain of an equation"
        return ""

    def search(group) -> None:
        why = probe(group)
        if not why:
            return
        if len(group) == 1:
            out[group[0].id] = why
            return
        half = len(group) // 2
        search(group[:half])
        search(group[half:])

    if params:
        search(list(params))
    return out


def _moved(p, j: int) -> float:
    """A move of number j, different for each (no two cancel), down (e = 1 is an edge)."""
    step = MOVE * (1.0 + 0.618 * ((j * 0.618034) % 1.0))
    v = float(p.value)
    return v * (1.0 - step) if v else step  # a zero (`0 m/s` exhaust) up: speeds are >= 0


def _lift(e, memo: dict):
    """`e` with each traced number replaced by its tree over the numbers (as `Var`s
    named by trace.PREFIX + id, so that `diff` and `evaluate` see them); shared subtrees
    stay shared."""
    key = id(e)
    hit = memo.get(key)
    if hit is not None:
        return hit
    t = type(e)
    if t is Const or t is Known:
        v = e.value
        out = _lift(v.expr, memo) if isinstance(v, trace.Traced) else e
        if t is Known and isinstance(out, Known) and out.name.startswith(trace.PREFIX):
            out = Var(out.name)
    elif t is Var:
        out = e
    elif t is Add:
        out = Add(tuple(_lift(x, memo) for x in e.terms))
    elif t is Mul:
        out = Mul(tuple(_lift(x, memo) for x in e.factors))
    elif t is Pow:
        out = Pow(_lift(e.base, memo), e.exp)
    elif t is Fn:
        out = Fn(e.name, _lift(e.arg, memo))
    else:
        raise TypeError(f"cannot lift {e!r}")
    memo[key] = out
    return out

