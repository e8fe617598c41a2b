"""`solve_batch`: one problem file solved for many variants, compiled once.

In: a problem file and each parameter's SI values (numpy columns). Out: `BatchResult`,
every `find` answer as an array (SI), and each variant's status: "ok" (solved by the
batch in the regimes the scalar solve would choose), or why it was solved on its
own by the ordinary scalar solve (a decision of the structure that goes another way,
a block near-singular, another set of roots), or "error: ..." if it does not solve.

The file is built and compiled once with traced numbers (trace.py) at a base variant;
the structure is analysed once; each block's rows become numpy kernels (kernel.py,
blocks.py). Friction regimes follow the scalar solve's rounds variant by variant:
every variant starts with every contact sticking, switches where the scalar rule
says, and is solved again with the structure of its new regimes.
"""
from __future__ import annotations

import math

import numpy as np

from ..records import record
from . import trace
from .blocks import _mark, block_for
from .kernel import function
from .params import ParamError, bind, build_variant

CHUNK = 32_768  # variants per chunk: arrays that stay in cache, memory bounded
ROUNDOFF = 64 * 2.0**-53  # as bounds.ROUNDOFF: a few ulps per term
MAX_ROUNDS = 8


class SweepError(ValueError):
    """The sweep cannot start (unreadable file, unknown parameter): one line."""


@record
class BatchResult:
    answers: dict  # name -> float64 array (SI)
    units: dict  # name -> SI unit label of the answer
    status: np.ndarray  # object array: "ok" or why the variant was solved on its own
    params: dict  # name -> float64 array (SI)
    display: dict  # name -> (unit of the `find`, factor: SI / factor = display value)
    param_units: dict  # name -> SI unit label of the parameter
    regimes: np.ndarray | None = None  # object array: the friction regimes that held
    batched: bool = True  # False: the structure could not be batched; all scalar
    note: str = ""  # why not batched
    ok: np.ndarray | None = None  # bool: status == "ok" (kept, not recomputed)
    failed: np.ndarray | None = None  # bool: the variant did not solve


def solve_batch(problem_path: str, columns: dict, dims: dict | None = None,
                progress=None, chunk: int = CHUNK, base: dict | None = None) -> BatchResult:
    """Every variant of the file (columns: parameter -> SI values).

    `dims` (parameter -> dimension) checks the values against the file's `let`s;
    `progress(done)` is called after each chunk. The structure is traced at one
    variant (chosen so that most variants share it); `base` (parameter -> SI value,
    see `choose_base`) fixes that point, so that a design split into parts (Dask)
    gives the same bits as the whole: a variant's answer depends only on the base."""
    from ..run import SourceTextError, read_source
    from ..diagnostics import ProblemError
    from ..syntax import parse

    try:
        source = read_source(problem_path)
    except (OSError, SourceTextError) as exc:
        raise SweepError(f"{problem_path}: cannot read: "
                         f"{getattr(exc, 'strerror', None) or exc}") from None
    names = list(columns)
    cols = {n: np.ascontiguousarray(columns[n], dtype=float) for n in names}
    sizes = {len(c) for c in cols.values()}
    if len(sizes) > 1:
        raise SweepError("the parameter columns have different lengths")
    n = sizes.pop() if sizes else 0
    try:
        doc = bind(parse(source), names, problem_path)
    except ParamError as exc:
        raise SweepError(str(exc)) from None
    except ProblemError as exc:
        d = exc.diagnostics[0]
        where = f":{d.span.line}:{d.span.column}" if d.span else ""
        raise SweepError(f"{problem_path}{where}: error: {d.message}") from None
    fixed = None
    if base is not None:
        missing = [p for p in names if p not in base]
        if missing:
            raise SweepError(f"base: no value for {', '.join(missing)}")
        cols = {p: np.append(cols[p], float(base[p])) for p in names}
        fixed = n
    sweep = _Sweep(doc, names, dims or {}, cols, n)
    sweep.fixed = fixed
    sweep.prepare()
    for lo in range(0, n, chunk):
        sweep.run_chunk(lo, min(n, lo + chunk))
        if progress is not None:
            progress(min(n, lo + chunk))
    return sweep.result()


def choose_base(problem_path: str, columns: dict, dims: dict | None = None) -> dict:
    """The parameter values `solve_batch` would trace the whole design at: pass them as
    `base` when solving its parts separately (byte-identical results)."""
    from ..run import read_source
    from ..syntax import parse

    names = list(columns)
    cols = {n: np.ascontiguousarray(columns[n], dtype=float) for n in names}
    n = len(next(iter(cols.values()))) if cols else 0
    try:
        doc = bind(parse(read_source(problem_path)), names, problem_path)
    except Exception as exc:  # the sweep itself reports it, with its line
        raise SweepError(str(exc)) from None
    sweep = _Sweep(doc, names, dims or {}, cols, n)
    sweep.fixed = None
    sweep.prepare()
    i = getattr(sweep, "base_trace", None)
    if i is None:
        i = n // 2 if n else 0
    return {p: float(cols[p][i]) for p in names} if n else {}


class _Plan:
    """One regime assignment's traced structure and its kernels."""

    def __init__(self, sweep, regimes: dict):
        from ..analyse import analyse
        from ..compile import compile_scene
        from ..solve import _needed

        self.regimes = regimes
        trace.start()
        try:
            scene = build_variant(sweep.doc, sweep.traced, sweep.dims)
            system = compile_scene(scene, dict(regimes))
            structure = analyse(system)
        finally:
            self.guards = trace.stop()
        self.system, self.structure = system, structure
        self.reason = _unbatchable(system, structure)
        if self.reason:
            return
        with trace.paused():
            needed = _needed(system, structure, False)
            order = structure.needed_blocks(needed)
            self.unknowns = [u for b in order for u in structure.blocks[b].unknowns]
            self.blocks = []
            for b in order:
                blk = block_for(system, structure, structure.blocks[b], sweep.names,
                                self.unknowns)
                if blk is None:
                    self.reason = "a block the batch does not solve (more equations than " \
                        "unknowns, or a hint that depends on the parameters)"
                    return
                self.blocks.append(blk)
            self.finds = system.finds
            fexprs = [f.expr for f in system.finds]
            self.find_fn = function(fexprs, sweep.names, self.unknowns, "finds")
            # each answer's terms: a value within round-off of them is zero, as in solve
            self.find_terms = []
            tl = []
            for e in fexprs:
                ts = _terms(e)
                self.find_terms.append((len(tl), len(ts)))
                tl.extend(ts)
            self.find_mag = function(tl, sweep.names, self.unknowns, "magnitudes")
            # guards, friction sites, redundant rows and durations: checked per variant
            g = self.guards
            self.guard_fn = function([x.lhs for x in g] + [x.rhs for x in g], sweep.names,
                                     self.unknowns, "guards") if g else None
            self.sites = [s for s in system.friction if s.jn in self.unknowns]
            site_exprs = []
            for s in self.sites:
                site_exprs.append(_lift(s.mu))
                site_exprs.append(s.slip_expr if s.slip_expr is not None else _lift(0.0))
            self.site_fn = function(site_exprs, sweep.names, self.unknowns, "sites") \
                if self.sites else None
            known = set(self.unknowns)
            checks = [k for k in structure.redundant
                      if structure.incidence[k] <= known] + \
                [k for k in structure.constant_eqs if not structure.incidence[k]]
            self.check_eqs = [system.equations[k] for k in checks]
            terms = []
            self.check_terms = []
            for e in self.check_eqs:
                r = e.residual
                ts = _terms(r)
                self.check_terms.append((len(terms), len(ts)))
                terms.extend(ts)
            self.check_fn = function(terms, sweep.names, self.unknowns, "checks") \
                if terms else None
            self.durations = [self.unknowns.index(u) for u, k in
                              ((u, system.unknowns[u].kind) for u in self.unknowns)
                              if k == "duration"]

    def solve(self, p, m):
        """(values per unknown, ok mask, reasons) for m variants."""
        ok = np.ones(m, bool)
        why = np.empty(m, dtype=object)
        v: list = [None] * len(self.unknowns)
        with np.errstate(all="ignore"):
            if self.guard_fn is not None:
                vals = self.guard_fn(p, v)
                h = len(self.guards)
                for g, a, b in zip(self.guards, vals[:h], vals[h:]):
                    got = _compare(g.op, a, b)
                    bad = np.broadcast_to(got != g.outcome, (m,))
                    if bad.any():
                        _mark(ok, why, bad, _guard_text(g))
            for blk in self.blocks:
                blk.run(p, v, m, ok, why)
            for j, x in enumerate(v):
                if x is None or np.ndim(x) == 0:
                    v[j] = np.broadcast_to(np.asarray(x, float), (m,))
            for j in self.durations:
                _mark(ok, why, ~(v[j] > 0), "a duration is not positive")
            if self.check_fn is not None:
                terms = self.check_fn(p, v)
                for e, (start, cnt) in zip(self.check_eqs, self.check_terms):
                    ts = [np.broadcast_to(np.asarray(t, float), (m,)) for t in
                          terms[start:start + cnt]]
                    res = np.abs(np.sum(ts, axis=0))
                    mag = np.sum(np.abs(ts), axis=0)
                    _mark(ok, why, ~((res <= ROUNDOFF * mag) | ((mag == 0) & (res == 0))),
                          f"a redundant equation does not hold ({e.principle})")
        return v, ok, why

    def next_regimes(self, p, v, m):
        """Each variant's regimes after the scalar solve's update rule; (keys, changed)."""
        keys = np.empty(m, dtype=object)
        changed = np.zeros(m, bool)
        if not self.sites:
            return keys, changed
        vals = self.site_fn(p, v)
        new = [np.empty(m, dtype=object) for s in self.sites]
        for a, s in zip(new, self.sites):
            a.fill(s.regime)
        idx = {u: j for j, u in enumerate(self.unknowns)}
        with np.errstate(all="ignore"):
            for i, s in enumerate(self.sites):
                mu = np.broadcast_to(np.asarray(vals[2 * i], float), (m,))
                jn = v[idx[s.jn]]
                jt = v[idx[s.jt]] if s.jt and s.jt in idx else np.zeros(m)
                if s.regime == "stick":
                    slide = np.abs(jt) > mu * jn * (1 + 1e-12) + 1e-300
                    new[i][slide & (jt < 0)] = "slide+"
                    new[i][slide & ~(jt < 0)] = "slide-"
                    changed |= slide
                elif s.slip_expr is not None and not s.decided:
                    slip = np.broadcast_to(np.asarray(vals[2 * i + 1], float), (m,))
                    want = np.where(slip > 0, "slide+", "slide-")
                    flip = (slip != 0) & (want != s.regime)
                    new[i][flip] = want[flip]
                    changed |= flip
        base = dict(self.regimes)
        for j in range(m):
            if changed[j]:
                r = dict(base)
                for i, s in enumerate(self.sites):
                    if new[i][j] != s.regime:
                        r[s.key] = new[i][j]
                keys[j] = tuple(sorted(r.items()))
        return keys, changed


def _terms(e, depth: int = 0) -> list:
    """The terms of `e` multiplied out one level at a time (as `expr.magnitude` sees
    them): the size a round-off residual is measured against."""
    from ..expr import Add, Mul, mul

    if depth > 6:
        return [e]
    if type(e) is Add:
        return [t for x in e.terms for t in _terms(x, depth + 1)]
    if type(e) is Mul:
        sums = [f for f in e.factors if type(f) is Add]
        if len(sums) == 1:
            rest = [f for f in e.factors if f is not sums[0]]
            out = []
            for t in _terms(sums[0], depth + 1):
                x = t
                for f in rest:
                    x = mul(f, x)
                out.append(x)
            return out
    return [e]


def _guard_text(g) -> str:
    """Why a variant leaves the batch's structure: `1 - e[A] == 0` is true there."""
    from ..expr import to_text

    with trace.paused():
        lhs, rhs = (to_text(x).replace(trace.PREFIX, "") for x in (g.lhs, g.rhs))
    return f"the structure changes where {lhs} {g.op} {rhs} is {not g.outcome}"


def _lift(x):
    from ..expr import Const

    return Const(x) if isinstance(x, float) else Const(float(x))


def _compare(op, a, b):
    return {"==": np.equal, "!=": np.not_equal, "<": np.less, "<=": np.less_equal,
            ">": np.greater, ">=": np.greater_equal}[op](a, b)


def _unbatchable(system, structure) -> str:
    """Why this structure is left to the scalar solve ('' if it is not)."""
    if system.integrations:
        return "a phase integrated numerically"
    if system.path_laws:
        return "an impact law that follows the impulse path (Poisson, Stronge)"
    from ..solve import _under_rows

    if structure.under and _under_rows(structure):
        return "an under-determined part"
    return ""


class _Sweep:
    def __init__(self, doc, names, dims, cols, n):
        self.doc, self.names, self.dims, self.cols, self.n = doc, names, dims, cols, n
        self.plans: dict = {}
        self.answers: dict = {}
        self.units: dict = {}
        self.display: dict = {}
        self.status = np.empty(n, dtype=object)
        self.status.fill("ok")
        self.ok = np.ones(n, bool)
        self.failed = np.zeros(n, bool)
        self.regimes = np.empty(n, dtype=object)
        self.regimes.fill("")
        self.batched = True
        self.note = ""
        self.order: list = []
        self.let_dims: dict = {}
        self.fixed = None  # the index of a given base (an extra last row), if any

    # ---- the base variant: the scalar solve decides the answers' names and units
    def prepare(self) -> None:
        from ..diagnostics import ProblemError

        n = self.n
        tries = [self._generic()] + ([n // 2, 0, n - 1] if n else [])
        if self.fixed is not None:
            tries = [self.fixed]
        base = None
        self.base_error = None
        for i in dict.fromkeys(tries):
            try:
                sol = self._scalar(i)
            except ProblemError as exc:
                self.base_error = exc
                continue
            except ParamError as exc:
                raise SweepError(str(exc)) from None
            base = (i, sol)
            break
        if base is None:
            self.batched = False
            self.note = "no variant tried first solves"
            if self.base_error is not None and n:
                d = self.base_error.diagnostics[0]
                if d.code in ("syntax", "name", "units", "type"):
                    where = f":{d.span.line}:{d.span.column}" if d.span else ""
                    raise SweepError(f"{self.doc.source.name}{where}: error: {d.message}")
            return
        i, sol = base
        self.base = i
        for name, _v, unit, _si in sol.answers:
            self.order.append(name)
        self._find_units(sol)
        self.answers = {a: np.full(n, np.nan) for a in self.order}
        plan = self._trace_at(i)
        if plan.reason:
            self.batched, self.note = False, plan.reason
            return
        # traced at a special value (e = 1 folds a term away), most variants would leave
        # the structure: trace at one of them instead, if that keeps more
        best = (self._leaving(plan), i)
        for j in self._others(i) if self.fixed is None else ():
            if best[0] <= 0.1:
                break
            other = self._trace_at(j)
            if not other.reason:
                best = min(best, (self._leaving(other), j))
        if best[1] != self.base_trace:
            plan = self._trace_at(best[1])
        leak = self._leaks(plan, sol)
        if leak:
            self.batched, self.note = False, leak

    def _trace_at(self, i: int) -> "_Plan":
        """The all-stick plan traced at variant i (earlier plans are dropped)."""
        self.base_trace = i
        self.plans = {}
        self.traced = {p: trace.leaf(p, float(self.cols[p][i])) for p in self.names}
        return self._plan(())

    def _leaving(self, plan) -> float:
        """The share of (up to 256 spread) variants whose structure differs from the plan's."""
        if plan.guard_fn is None:
            return 0.0
        idx = np.unique(np.linspace(0, self.n - 1, min(self.n, 256)).astype(int))
        p = [self.cols[name][idx] for name in self.names]
        m = len(idx)
        bad = np.zeros(m, bool)
        with np.errstate(all="ignore"):
            vals = plan.guard_fn(p, [None] * len(plan.unknowns))
        h = len(plan.guards)
        for g, a, b in zip(plan.guards, vals[:h], vals[h:]):
            bad |= np.broadcast_to(_compare(g.op, a, b) != g.outcome, (m,))
        return float(bad.mean())

    def _others(self, i: int) -> list:
        n = self.n
        return [j for j in dict.fromkeys([n // 3, (2 * n) // 3, n // 4, (3 * n) // 4])
                if j != i and 0 <= j < n][:3]

    def _generic(self) -> int:
        """A variant to trace at whose values are not special (0 and +-1 fold terms
        away, so the other variants' structure would differ): the middle one if it will
        do, else the first such one of a few spread over the design."""
        n = self.n
        if not n:
            return 0
        for i in dict.fromkeys([n // 2, n // 3, (2 * n) // 3, 1 % n, n - 2 if n > 1 else 0,
                                n // 4, (3 * n) // 4]):
            if all(float(self.cols[p][i]) not in (0.0, 1.0, -1.0) for p in self.names):
                return i
        return n // 2

    def _find_units(self, sol) -> None:
        from ..units import si_label

        for f in sol.system.finds:
            self.display[f.name] = (f.unit, f.factor)
            self.units[f.name] = f.unit if f.factor == 1.0 else si_label(f.dim)
        for name, _v, unit, si in sol.answers:
            if name not in self.display:  # a vector's components
                self.display[name] = (unit, (si / _v) if _v not in (0.0,) and si else 1.0)
                self.units[name] = unit

    def _plan(self, key) -> _Plan:
        plan = self.plans.get(key)
        if plan is None:
            plan = self.plans[key] = _Plan(self, dict(key))
        return plan

    def _leaks(self, plan: _Plan, base_sol) -> str:
        """Build and compile a second variant as the scalar solve would; every number of
        its equations must be what the traced ones give there (a number computed outside
        the trace, e.g. by math.hypot, would be the base's for every variant)."""
        from ..compile import compile_scene
        from ..expr import evaluate
        from ..diagnostics import ProblemError

        n = self.n
        probes = [j for j in (0, n - 1, n // 3) if j != self.base]
        for j in probes[:2]:
            vals = {p: float(self.cols[p][j]) for p in self.names}
            try:
                scene = build_variant(self.doc, vals, self.dims)
                system = compile_scene(scene, dict(plan.regimes))
            except ProblemError:
                continue
            if len(system.equations) != len(plan.system.equations):
                return "the number of equations depends on the parameters"
            pv = [np.array([vals[p]]) for p in self.names]
            exprs = [e.residual for e in plan.system.equations]
            # compare the residuals at a common random point of the unknowns
            rng = np.random.default_rng(12345)
            point = {u: float(rng.uniform(0.5, 1.5)) for u in system.unknowns}
            if set(system.unknowns) != set(plan.system.unknowns):
                return "the unknowns depend on the parameters"
            names = list(point)
            fn = function(exprs, self.names, names, "probe")
            with trace.paused():
                got = fn(pv, [np.array([point[u]]) for u in names])
                for e, g in zip(system.equations, got):
                    try:
                        want = evaluate(e.residual, point)
                    except (ValueError, ZeroDivisionError, OverflowError, KeyError):
                        continue
                    g = float(np.asarray(g).ravel()[0])
                    if not math.isclose(g, want, rel_tol=1e-9, abs_tol=1e-12 * (1 + abs(want))):
                        return (f"a number of {e.principle} is computed outside the batch "
                                "(not traced)")
        return ""

    def _scalar(self, i):
        from ..solve import solve_scene
        from .params import ParamBuilder

        vals = {p: float(self.cols[p][i]) for p in self.names}
        builder = ParamBuilder(self.doc, vals, self.dims)
        scene = builder.run()
        self.let_dims = self.let_dims or dict(builder.let_dims)
        return solve_scene(scene)

    # ---- a chunk of variants
    def run_chunk(self, lo: int, hi: int) -> None:
        m = hi - lo
        if not self.batched:
            for i in range(lo, hi):
                self._fallback(i, "")
            return
        idx = np.arange(lo, hi)
        groups = [((), idx, ())]
        final_reason = np.empty(m, dtype=object)
        for _ in range(MAX_ROUNDS):
            nxt = []
            for key, ids, path in groups:
                plan = self._plan(key)
                if plan.reason:
                    for i in ids:
                        self._fallback(int(i), f"regimes {_show(key)}: {plan.reason}")
                    continue
                p = [self.cols[name][ids] for name in self.names]
                v, ok, why = plan.solve(p, len(ids))
                keys, changed = plan.next_regimes(p, v, len(ids))
                done = ok & ~changed
                self._store(plan, p, v, ids[done], done, key)
                for j in np.nonzero(~ok)[0]:
                    final_reason[ids[j] - lo] = why[j]
                moving = ok & changed
                by_key: dict = {}
                for j in np.nonzero(moving)[0]:
                    by_key.setdefault(keys[j], []).append(j)
                for k2, js in by_key.items():
                    js = np.array(js)
                    if k2 in path or k2 == key:
                        for j in js:
                            final_reason[ids[j] - lo] = "the friction regimes do not settle"
                        continue
                    nxt.append((k2, ids[js], path + (key,)))
            groups = nxt
            if not groups:
                break
        for key, ids, _ in groups:
            for i in ids:
                final_reason[i - lo] = "the friction regimes do not settle"
        for j in np.nonzero(final_reason != None)[0]:  # noqa: E711 - object array
            self._fallback(lo + int(j), final_reason[j])

    def _store(self, plan, p, v, ids, mask, key) -> None:
        if not len(ids):
            return
        m = mask.shape[0]
        with np.errstate(all="ignore"):
            vals = plan.find_fn(p, v)
            terms = plan.find_mag(p, v)
            for f, val, (start, cnt) in zip(plan.finds, vals, plan.find_terms):
                val = np.array(np.broadcast_to(np.asarray(val, float), (m,)))
                mag = np.sum([np.abs(np.broadcast_to(np.asarray(t, float), (m,)))
                              for t in terms[start:start + cnt]], axis=0)
                val[np.abs(val) <= ROUNDOFF * mag] = 0.0
                if f.name in self.answers:
                    self.answers[f.name][ids] = val[mask]
        self.regimes[ids] = _regimes_text(plan.system)
        fin = np.ones(len(ids), bool)
        for a in self.order:
            fin &= np.isfinite(self.answers[a][ids])
        bad = ~fin
        for i in ids[bad]:
            self._fallback(int(i), "an answer is not finite")

    def _fallback(self, i: int, reason: str) -> None:
        """The ordinary scalar solve of variant i."""
        from ..diagnostics import ProblemError

        try:
            sol = self._scalar(i)
        except ProblemError as exc:
            d = exc.diagnostics[0]
            self.status[i] = f"error: {d.message}"
            self.ok[i], self.failed[i] = False, True
            for a in self.answers.values():
                a[i] = np.nan
            return
        if not self.answers:
            for name, _v, _u, _si in sol.answers:
                self.order.append(name)
            self._find_units(sol)
            self.answers = {a: np.full(self.n, np.nan) for a in self.order}
        for name, _v, _u, si in sol.answers:
            if name in self.answers:
                self.answers[name][i] = si
        self.status[i] = reason or "ok"
        if not self.batched:
            self.status[i] = "ok"
        self.ok[i] = self.status[i] == "ok"
        self.regimes[i] = _regimes_text(sol.system)

    def result(self) -> BatchResult:
        from ..units import si_label

        dims = {**self.let_dims, **self.dims}
        units = {p: si_label(dims[p]) if p in dims else "" for p in self.names}
        return BatchResult({a: self.answers[a] for a in self.order},
                           {a: self.units.get(a, "") for a in self.order}, self.status,
                           {p: c[:self.n] for p, c in self.cols.items()},
                           {a: self.display.get(a, ("", 1.0))
                                             for a in self.order},
                           units, self.regimes, self.batched, self.note, self.ok,
                           self.failed)


def _regimes_text(system) -> str:
    """The friction regimes a solution holds: `ball (1->2): stick`."""
    return ", ".join(f"{s.label} ({s.transition}): {s.regime}" for s in system.friction)


def _show(key) -> str:
    return ", ".join(f"{k}: {v}" for k, v in key)


def concat(parts: list) -> BatchResult:
    """The results of consecutive parts of one design, as one (for a design solved in
    parts: Dask, chunks; pass the same `base` to each part for identical bits)."""
    full = next((p for p in parts if p.answers), parts[0])
    sizes = [len(p.status) for p in parts]

    def join(get, fill=np.nan):
        out = {}
        for k in get(full):
            out[k] = np.concatenate([get(p)[k] if k in get(p) else np.full(s, fill)
                                     for p, s in zip(parts, sizes)])
        return out

    def objects(get):
        arr = np.empty(sum(sizes), dtype=object)
        lo = 0
        for p, s in zip(parts, sizes):
            part = get(p)
            arr[lo:lo + s] = part if part is not None else ""
            lo += s
        return arr

    def flags(get, default):
        return np.concatenate([get(p) if get(p) is not None else np.full(s, default)
                               for p, s in zip(parts, sizes)])

    return BatchResult(join(lambda p: p.answers), dict(full.units),
                       objects(lambda p: p.status), join(lambda p: p.params),
                       dict(full.display), dict(full.param_units),
                       objects(lambda p: p.regimes), all(p.batched for p in parts),
                       "; ".join(sorted({p.note for p in parts if p.note})),
                       flags(lambda p: p.ok, True), flags(lambda p: p.failed, False))
