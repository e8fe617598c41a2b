"""Sizes and error bounds of solved quantities (part of `solve`).

In: the solved blocks in order, their equations and values. Out: for each solved
unknown its size (the magnitude of the terms that determine it, not amplified by
the conditioning: a velocity that is the difference of two 3 m/s terms has size 3)
and an absolute error bound (the rounding of each block's data and the bounds of the
unknowns it uses, carried through |A^-1|, plus the solver's own estimate). A check
judges a redundant equation against these; an answer carries its bound.
"""
from __future__ import annotations

import math
import sys
from struct import pack

from . import rowcode
from .block_memo import SMALL, kind_by_key, kind_of
from .expr import Add, Const, E, Fn, Known, Mul, Pow, Var, evaluate, keeps, variables

ROUNDOFF = 64 * 2.0**-53  # forming a term or a residual from exact values: a few ulps each
COLUMNS_FROM = 5000  # a sparse block's columns as arrays from here (linalg.BIG: numpy loaded)
DENSE = 40  # |A^-1| in plain Python up to here (a 40x80 Gauss-Jordan is ~1 ms); beyond, a cond-based bound


def derivatives(e: E, values) -> dict[str, float]:
    """d e / d v for each unknown v of `e`, at the solved values: one pass over the
    tree (a kinetic energy of 1000 bodies has 2000 unknowns: no symbolic diff each)."""
    out: dict[str, float] = {}
    try:
        _grad(e, 1.0, values, out)
    except (KeyError, ValueError, ZeroDivisionError, OverflowError):
        return {v: math.inf for v in variables(e)}
    return out


def _grad(e: E, w: float, values, out: dict[str, float]) -> None:
    """Accumulate w * d e / d v into out. Leaves are handled inline (the walk runs over
    every solved equation); the products and sums are the reference's, in its order
    (tests/test_fast_walks.py)."""
    t = type(e)
    if t is Var:
        out[e.name] = out.get(e.name, 0.0) + w
    elif t is Add:
        for x in e.terms:
            tx = type(x)
            if tx is Var:
                out[x.name] = out.get(x.name, 0.0) + w
            elif tx is not Const and tx is not Known:
                _grad(x, w, values, out)
    elif t is Mul:
        fs = e.factors
        for f in fs:  # a zero factor first: the others need no value then
            if (type(f) is Const or type(f) is Known) and f.value == 0.0 and \
                    not keeps(f.value):
                return
        vals = [f.value if type(f) is Const or type(f) is Known else
                values[f.name] if type(f) is Var else evaluate(f, values) for f in fs]
        for i, f in enumerate(fs):
            tf = type(f)
            if tf is Const or tf is Known:
                continue
            k = w
            for j, v in enumerate(vals):
                if j != i:
                    k *= v
            if tf is Var:
                out[f.name] = out.get(f.name, 0.0) + k
            else:
                _grad(f, k, values, out)
    elif t is Pow:
        if type(e.base) is not Const and type(e.base) is not Known:
            _grad(e.base, w * e.exp * evaluate(e.base, values) ** (e.exp - 1.0), values, out)
    elif t is Fn:
        if type(e.arg) is not Const and type(e.arg) is not Known:
            a = evaluate(e.arg, values)
            _grad(e.arg, w * _DERIVATIVE[e.name](a), values, out)


def derivatives_and_size(e: E, values) -> tuple[dict[str, float], float]:
    """(`derivatives(e)`, `_mag(e)`) in one walk of the tree, the same numbers in the same
    order (a block's bounds walk each residual once, not twice); where either walk would
    fail, each is taken on its own, as they handle it."""
    out: dict[str, float] = {}
    try:
        return out, _grad_size(e, 1.0, values, out)
    except (KeyError, ValueError, ZeroDivisionError, OverflowError):
        return derivatives(e, values), _mag(e, values)


def fast_derivatives_and_size(e: E, values) -> tuple[dict[str, float], float]:
    """`derivatives_and_size` by rowcode's compiled walk where the tree has one (none
    within a small solve: `rowcode.remembered`)."""
    if rowcode._PLAIN[0]:
        return derivatives_and_size(e, values)
    got = rowcode.derivatives_and_size(e, values)
    return got if got is not None else derivatives_and_size(e, values)


def _grad_size(e: E, w: float, values, out: dict[str, float]) -> float:
    """`_grad(e, w)` into `out`, returning `term_size(e)`. Leaves inline (the walk runs
    over every row of the bounds and every answer): the same products and sums as
    tests/test_bounds_fused.py's two walks, in their order, with the same failures."""
    t = type(e)
    if t is Const or t is Known:
        return abs(e.value)
    if t is Var:
        nm = e.name
        out[nm] = out.get(nm, 0.0) + w
        return abs(values[nm])
    if t is Add:
        return _sum_walk(e, w, values, out)[0]
    if t is Mul:
        fs = e.factors
        for f in fs:  # `is_zero`: a zero number factor (not a traced one that keeps it)
            tf = type(f)
            if (tf is Const or tf is Known) and f.value == 0.0 and not keeps(f.value):
                return 0.0
        free = [f for f in fs if type(f) is not Const and type(f) is not Known]
        if len(free) == 1 and type(free[0]) is Add:
            return _one_free(fs, free[0], w, values, out)
        vals = [f.value if type(f) is Const or type(f) is Known else
                values[f.name] if type(f) is Var else evaluate(f, values) for f in fs]
        two = len(fs) == 2
        r = 1.0
        for i, f in enumerate(fs):
            tf = type(f)
            if tf is Const or tf is Known:
                r *= abs(f.value)
                continue
            k = w
            if two:  # the loop below for two factors: the one other value
                k *= vals[1 - i]
            else:
                for j, v in enumerate(vals):
                    if j != i:
                        k *= v
            if tf is Var:
                nm = f.name
                out[nm] = out.get(nm, 0.0) + k
                r *= abs(values[nm])
            else:
                r *= _grad_size(f, k, values, out)
        return r
    if t is Pow:
        if type(e.base) is not Const and type(e.base) is not Known:
            base = _grad_size(e.base, w * e.exp * evaluate(e.base, values) ** (e.exp - 1.0),
                              values, out)
        else:
            base = abs(e.base.value)
        return base ** e.exp if e.exp > 0 else abs(evaluate(e, values))
    # a function: its own walks (rare; their failures are handled as they handle them)
    _grad(e, w, values, out)
    return term_size(e, values)


def _one_free(fs, g, w: float, values, out: dict[str, float]) -> float:
    """`_grad_size` of a product of numbers and one sum `g` (a mass times a change of
    velocity): the same steps, without the general step's `evaluate(g)`, whose value no
    other factor's weight reads, where that evaluation cannot fail: g's terms are leaves
    and products of two leaves (`_sum_walk`) and its size is a float below 1e300 (such a
    sum's evaluation fails only where the walk does, an unknown missing, or in its
    fsum: an intermediate overflow or an inf minus an inf, which need terms of that
    size; a leaf's or a product of two leaves' size is its value's magnitude). Anywhere
    else g is evaluated, and first where the walk fails (its failure came first)."""
    r = 1.0
    for f in fs:
        if f is not g:
            r *= abs(f.value)
            continue
        k = w
        for h in fs:
            if h is not g:
                k *= h.value
        try:
            z, flat = _sum_walk(g, k, values, out)
        except Exception:
            evaluate(g, values)
            raise
        if not flat or type(z) is not float or not z < 1e300:
            evaluate(g, values)
        r *= z
    return r


def _sum_walk(g, w: float, values, out: dict[str, float]):
    """(`_grad_size(g, w)` of a sum, whether its terms are all leaves and products of two
    leaves): `_grad_size`'s steps for a sum, in its order."""
    sizes = []
    flat = True
    for x in g.terms:
        tx = type(x)
        if tx is Const or tx is Known:
            sizes.append(abs(x.value))
        elif tx is Var:
            nm = x.name
            out[nm] = out.get(nm, 0.0) + w
            sizes.append(abs(values[nm]))
        elif tx is Mul and len(x.factors) == 2 and type(x.factors[0]) in _LEAVES and \
                type(x.factors[1]) in _LEAVES:
            sizes.append(_leaf_pair(x, w, values, out))
        else:
            flat = False
            sizes.append(_grad_size(x, w, values, out))
    return sum(sizes), flat


_LEAVES = frozenset((Const, Known, Var))


def _leaf_pair(x, w: float, values, out: dict[str, float]) -> float:
    """`_grad_size(x, w)` of a product of two leaves (numbers or unknowns: the most
    common term of a row, a mass times a velocity), the general product's steps written
    out: the same operations in the same order."""
    a, b = x.factors
    ta, tb = type(a), type(b)
    na = ta is Const or ta is Known
    nb = tb is Const or tb is Known
    if na and a.value == 0.0 and not keeps(a.value) or \
            nb and b.value == 0.0 and not keeps(b.value):
        return 0.0
    va = a.value if na else values[a.name]
    vb = b.value if nb else values[b.name]
    r = 1.0
    if na:
        r *= abs(va)
    else:
        k = w
        k *= vb
        nm = a.name
        out[nm] = out.get(nm, 0.0) + k
        r *= abs(values[nm])
    if nb:
        r *= abs(vb)
    else:
        k = w
        k *= va
        nm = b.name
        out[nm] = out.get(nm, 0.0) + k
        r *= abs(values[nm])
    return r


def slopes_and_size(e: E, values, size: dict[str, float]) -> tuple[dict[str, float], float]:
    """(`slopes(e)`, `size_of(e, values, size)`) with the tree walked once, not twice."""
    got = None if rowcode._PLAIN[0] else rowcode.derivatives_and_size(e, values)
    if got is None and not rowcode._PLAIN[0]:
        got = rowcode.grad_size_big(e, values, _grad_size)
    dv, mag = got if got is not None else derivatives_and_size(e, values)
    return slopes_of(dv, mag, size)


def slopes_of(dv: dict, mag: float, size: dict[str, float]) -> tuple[dict[str, float], float]:
    """`slopes_and_size` from the derivatives and the size of the terms."""
    slope = {v: abs(d) for v, d in dv.items()}
    return slope, mag + sum(s * size.get(v, 0.0) for v, s in slope.items() if s)


def slopes(e: E, values) -> dict[str, float]:
    """|d e / d v| for each unknown v of `e`, at the solved values."""
    return {v: abs(d) for v, d in derivatives(e, values).items()}


def _mag(e: E, values) -> float:
    try:
        return term_size(e, values)
    except (KeyError, ValueError, ZeroDivisionError, OverflowError):
        return math.inf


def term_size(e: E, values) -> float:
    """The sum of the sizes of the terms of `e`, products taken factor by factor. A
    function counts with its sensitivity: cos(-90 deg) is 6e-17 in float64 but carries
    the rounding of its argument, |sin(a)| |a| eps, so its size is ~1.57, not 6e-17.
    (Leaves inline; the same sums and products as the plain walk.)"""
    t = type(e)
    if t is Const or t is Known:
        return abs(e.value)
    if t is Var:
        return abs(values[e.name])
    if t is Add:
        return sum([abs(x.value) if type(x) is Const or type(x) is Known else
                    abs(values[x.name]) if type(x) is Var else term_size(x, values)
                    for x in e.terms])
    if t is Mul:
        fs = e.factors
        for f in fs:
            if (type(f) is Const or type(f) is Known) and f.value == 0.0 and \
                    not keeps(f.value):
                return 0.0
        r = 1.0
        for f in fs:
            tf = type(f)
            r *= abs(f.value) if tf is Const or tf is Known else \
                abs(values[f.name]) if tf is Var else term_size(f, values)
        return r
    if t is Pow:
        if e.exp > 0:
            return term_size(e.base, values) ** e.exp
        return abs(evaluate(e, values))
    v = abs(evaluate(e, values))
    try:
        slope = _fn_slope(e, values)
    except (ValueError, ZeroDivisionError, OverflowError):
        return v
    return max(v, slope * term_size(e.arg, values))


def _fn_slope(e, values) -> float:
    """|f'(a)| of a function node at its argument."""
    a = evaluate(e.arg, values)
    return abs(_SLOPE[e.name](a))


# each function's derivative at a (`_grad`) and its size |f'(a)| up to sign (`_fn_slope`),
# made once, not as a table of closures per node walked
_DERIVATIVE = {"sin": lambda a: math.cos(a), "cos": lambda a: -math.sin(a),
               "tan": lambda a: 1 / math.cos(a) ** 2, "exp": lambda a: math.exp(a),
               "asin": lambda a: 1 / math.sqrt(1 - a * a),
               "acos": lambda a: -1 / math.sqrt(1 - a * a), "atan": lambda a: 1 / (1 + a * a),
               "ln": lambda a: 1 / a, "log": lambda a: 1 / a,
               "abs": lambda a: math.copysign(1.0, a)}
_SLOPE = {"sin": lambda a: math.cos(a), "cos": lambda a: math.sin(a),
          "tan": lambda a: 1 / math.cos(a) ** 2, "exp": lambda a: math.exp(a),
          "asin": lambda a: 1 / math.sqrt(1 - a * a), "acos": lambda a: 1 / math.sqrt(1 - a * a),
          "atan": lambda a: 1 / (1 + a * a), "ln": lambda a: 1 / a, "log": lambda a: 1 / a,
          "abs": lambda a: 1.0}


def size_of(e: E, values, size: dict[str, float], slope: dict[str, float] | None = None) -> float:
    """The size of the quantities in `e`: its terms, and each solved unknown's own size."""
    slope = slopes(e, values) if slope is None else slope
    return _mag(e, values) + sum(s * size.get(v, 0.0) for v, s in slope.items() if s)


def error_of(slope: dict[str, float], err: dict[str, float]) -> float:
    """First-order bound on the error of an expression from its unknowns' bounds."""
    return sum(s * err.get(v, 0.0) for v, s in slope.items() if s)


def propagate(system, reports, values, exact: bool = False, fused: dict | None = None):
    """(size, err): dictionaries over the solved unknowns, block by block in order.

    In exact mode a linear block's rows are formed and solved without rounding: its
    own data add no error, only the bounds of float (Newton) unknowns it uses do.
    `fused`: id of a report -> (kind, shapes) of the blocks `block_kinds` solved, whose
    steps their kind's code takes (`Kind.fill`: the same operations as `_one` and
    `_square`; where it declines, they run).
    """
    size: dict[str, float] = {}
    err: dict[str, float] = {}
    if not fused or exact or not FAST or not SQUARE:
        fused = None
    # runs of 1x1 blocks (each ball's y velocity) as arrays: `_ones_as_arrays`
    try_ones = 0 if FAST and not exact and len(reports) >= ONES_RUN and \
        "numpy" in sys.modules else len(reports)
    done = 0  # reports before this were bounded as a run
    for at, rep in enumerate(reports):
        if at < done:
            continue
        names = rep.unknowns
        if at >= try_ones and len(names) == 1 and len(rep.equations) == 1 and \
                at + ONES_RUN <= len(reports) and \
                len(reports[at + ONES_RUN - 1].unknowns) == 1:  # else a short run
            end, ok = _ones_as_arrays(system, reports, at, values, size, err, fused)
            if ok:
                done = end
                continue
            try_ones = end
        if fused is not None:
            got = fused.get(id(rep))
            if got is not None and got[0].fill(got[1], names, rep.quality, values, size, err):
                continue
        if rep.method == "integrated":  # its rows are placeholders: the integrator's rtol
            for name in names:
                x = abs(values.get(name, 0.0))
                size[name], err[name] = x, 10 * rep.residual * x
            continue
        if FAST and len(names) == 1 and len(rep.equations) == 1:
            _one(system, rep, values, exact, size, err)
            continue
        if FAST and SQUARE and 1 < len(names) <= SMALL and len(rep.equations) == len(names) \
                and rep.method == "linear":
            _square(system, rep, values, exact, size, err)
            continue
        col = {n: j for j, n in enumerate(names)}
        n = len(names)
        # a block past DENSE needs only each row's largest entry, not the rows themselves
        # (a 10^5-row block's row dicts were most of the solve's peak memory)
        sparse = FAST and not (n <= DENSE and len(rep.equations) == n)
        A: list = [] if sparse else [{} for _ in rep.equations]
        cols: list[list[tuple[int, float]]] = [[] for _ in names]
        scale, delta = [], []
        newton = rep.method == "newton"
        eqs, sget, eget = system.equations, size.get, err.get
        pairs = _flat_pairs if sparse else _same
        if sparse and n >= COLUMNS_FROM and not exact and rep.method == "linear" and \
                "numpy" in sys.modules and _rows_as_arrays(rep, eqs, col, values, size, err):
            continue
        for i, k in enumerate(rep.equations):
            f = eqs[k].residual
            if not FAST:
                d = _row_plain(f, values, col, A, cols, i, size, err, scale)
            elif sparse:
                d = _row_max(f, values, col, A, cols, i, sget, eget, scale)
            else:
                d = _row(f, values, col, A[i], cols, i, sget, eget, scale)
            if not exact or newton:
                d += ROUNDOFF * scale[-1]
            if newton:
                try:
                    d += abs(evaluate(f, values))
                except (KeyError, ValueError, ZeroDivisionError, OverflowError):
                    d = math.inf
            delta.append(d)
        # the block's largest quantity in each unknown's units (columns scaled as the
        # solver equilibrates them): a value far below it is round-off, not a result
        # (lists, not generators, for max/min/sum: the same values in the same order)
        # (the parts that depend on the matrix alone, once per kind of block: a sequence
        # of impacts repeats one matrix; shared, only read)
        if sparse and n >= COLUMNS_FROM and "numpy" in sys.modules:  # by the banded LU
            from . import bounds_columns

            q = rep.quality
            got = bounds_columns.sizes_and_errors(
                cols, A, scale, delta, [abs(values.get(nm, 0.0)) for nm in names],
                q.components if q is not None and q.components else [0.0] * n,
                rep.cond if rep.cond and math.isfinite(rep.cond) else 1.0,
                not exact or newton) if bounds_columns.ENABLED else None
            if got is not None:
                size.update(zip(names, got[0]))
                err.update(zip(names, got[1]))
                continue
        if sparse:
            rmax, unit, inv = A, _units(A, cols, _flat_pairs), None
        elif n <= DENSE and len(A) == n:
            rmax, unit, inv = kind_of(A, lambda A: _matrix_parts(A, cols, True))
        else:
            rmax, unit, inv = _matrix_parts(A, cols, False)
        xs = [abs(values.get(nm, 0.0)) for nm in names]
        big = max([x * u for x, u in zip(xs, unit)]) if names else 0.0
        for j, name in enumerate(names):
            x = xs[j]
            cands = [scale[i] / a for i, a in pairs(cols[j])]
            uj = unit[j]
            size[name] = max(x, min(cands) if cands else x, big / uj if uj > 0 else 0.0)
        q = rep.quality
        comps = q.components if q is not None and q.components else [0.0] * n
        cond = rep.cond if rep.cond and math.isfinite(rep.cond) else 1.0
        solved = not exact or newton
        for j, name in enumerate(names):
            if inv is not None:
                e = sum([a * b for a, b in zip(inv[j], delta)])
            else:
                e = cond * max([delta[i] / a for i, a in pairs(cols[j])], default=0.0)
            solver = comps[j] * abs(values.get(name, 0.0)) if solved else 0.0
            err[name] = e + solver if math.isfinite(e) else math.inf
    return size, err


def _same(x):
    return x


def _rows_as_arrays(rep, eqs, col, values, size: dict, err: dict) -> bool:
    """`propagate`'s step for a large linear block with its rows read per shape as
    arrays (`bounds_rows`) and its columns' sizes and bounds as arrays (`bounds_columns`):
    True where both took it (sizes and bounds set), False where either declined."""
    from . import bounds_columns, bounds_rows

    if not bounds_columns.ENABLED:
        return False
    got = bounds_rows.read(eqs, rep.equations, col, values, size, err, ROUNDOFF)
    if got is None:
        return False
    rmax, scale, delta, rows, cols, ents = got
    names = rep.unknowns
    n = len(names)
    q = rep.quality
    out = bounds_columns.from_rows(
        rows, cols, ents, rmax, scale, delta, [abs(values.get(nm, 0.0)) for nm in names],
        q.components if q is not None and q.components else [0.0] * n,
        rep.cond if rep.cond and math.isfinite(rep.cond) else 1.0, True)
    if out is None:
        return False
    size.update(zip(names, out[0]))
    err.update(zip(names, out[1]))
    return True


def _matrix_parts(A, cols, square: bool):
    """(each row's largest entry, each column's largest scaled entry, |A^-1| or None):
    `propagate`'s parts of a block that depend on its matrix alone."""
    rmax = [max([abs(v) for v in row.values()]) if row else 0.0 for row in A]
    return rmax, _units(rmax, cols), _abs_inverse(A) if square else None


def _units(rmax, cols, pairs=None):
    """Each column's largest entry scaled by its row's largest (`_matrix_parts`)."""
    unit = []
    for cj in cols:
        us = [a / rmax[i] for i, a in (cj if pairs is None else pairs(cj)) if rmax[i] > 0]
        unit.append(max(us) if us else 0.0)
    return unit


def _one(system, rep, values, exact: bool, size: dict, err: dict) -> None:
    """`propagate`'s general step for a block of one unknown and one equation (most
    blocks of a large scene), the same operations on scalars, in the same order
    (tests/test_rowcode.py compares the two on every example)."""
    name = rep.unknowns[0]
    newton = rep.method == "newton"
    f = system.equations[rep.equations[0]].residual
    dv, mag = fast_derivatives_and_size(f, values)
    a = None  # A[0][0]: the derivative by the block's unknown, where nonzero
    sc = d = 0  # the sizes and bounds of the unknowns used, summed from int 0 as sum() does
    sget, eget = size.get, err.get
    for v, s in dv.items():
        if v == name:
            if s != 0:
                a = s
        else:
            s = abs(s)
            if s:
                sc += s * sget(v, 0.0)
                d += s * eget(v, 0.0)
    scale = mag + sc
    if not exact or newton:
        d += ROUNDOFF * scale
    if newton:
        try:
            d += abs(evaluate(f, values))
        except (KeyError, ValueError, ZeroDivisionError, OverflowError):
            d = math.inf
    x = abs(values.get(name, 0.0))
    # the general step's one-element maxima and minima are their elements, and its
    # |A^-1| of [[a]] is |1/float(a)| (None where a is 0 or not finite)
    if a is None:
        size[name] = max(x, x, 0.0)
        inv = None
    else:
        aa = abs(a)
        rmax = abs(a)
        unit = aa / rmax if rmax > 0 else 0.0
        big = x * unit
        size[name] = max(x, scale / aa, big / unit if unit > 0 else 0.0)
        af = float(a)
        inv = None if af == 0.0 or not math.isfinite(af) else abs(1.0 / af)
    q = rep.quality
    comp = q.components[0] if q is not None and q.components else 0.0
    if inv is not None:
        e = 0 + inv * d
    else:
        cond = rep.cond if rep.cond and math.isfinite(rep.cond) else 1.0
        e = cond * (d / aa) if a is not None else cond * 0.0
    solver = 0.0 if exact and not newton else comp * abs(values.get(name, 0.0))
    err[name] = e + solver if math.isfinite(e) else math.inf


ONES_RUN = 64  # a run of this many 1x1 blocks is bounded as arrays (`_ones_as_arrays`)


def _ones_as_arrays(system, reports, start: int, values, size: dict, err: dict, fused):
    """(end, done): `_one` for each of the run of 1x1 linear blocks from reports[start]
    (not fused) as arrays, their rows read per shape (`bounds_rows`); done False where the
    run is short or declined (then each takes `_one`, as before). Only where no row of the
    run uses another unknown of it (no bound of the run feeds the run), so the order of
    the steps changes nothing: each element takes `_one`'s float operations."""
    from . import bounds_rows

    end = start
    while end < len(reports):
        rep = reports[end]
        if len(rep.unknowns) != 1 or len(rep.equations) != 1 or rep.method != "linear" or \
                (fused is not None and id(rep) in fused):
            break
        end += 1
    run = reports[start:end]
    if len(run) < ONES_RUN or not bounds_rows.ENABLED:
        return end, False
    names = [rep.unknowns[0] for rep in run]
    col = {nm: j for j, nm in enumerate(names)}
    if len(col) != len(names):
        return end, False
    got = bounds_rows.read(system.equations, [rep.equations[0] for rep in run], col, values,
                           size, err, ROUNDOFF)
    if got is None:
        return end, False
    np = sys.modules["numpy"]
    _rmax, scale, delta, rows, cols, ents = got
    m = len(run)
    # each row's one entry is its own unknown's (a row without it, or with another of
    # the run's unknowns, is left to `_one`)
    if len(rows) != m or not (cols == rows).all() or \
            not (np.bincount(rows, minlength=m) == 1).all():
        return end, False
    a = np.empty(m)
    a[rows] = ents  # entries come shape by shape: in row order here
    try:
        x = np.array([abs(values[nm]) for nm in names], dtype=float)
    except KeyError:
        return end, False
    comp = np.array([q.components[0] if q is not None and q.components else 0.0
                     for q in (rep.quality for rep in run)], dtype=float)
    with np.errstate(all="ignore"):
        sizes = np.maximum(x, scale / a)  # max(x, scale / |a|, x * 1.0 / 1.0)
        e = (1.0 / a) * delta  # |1 / a| * d
        errs = np.where(np.isfinite(e), e + comp * x, np.inf)
    if not (np.isfinite(x).all() and np.isfinite(sizes).all()):
        return end, False
    size.update(zip(names, sizes.tolist()))
    err.update(zip(names, errs.tolist()))
    return end, True


FAST = True  # tests turn it off to compare the scalar steps with the general ones
SQUARE = True  # tests turn it off: small square blocks take the general step


def _square(system, rep, values, exact: bool, size: dict, err: dict) -> None:
    """`propagate`'s general step for a small square linear block (each impact of a
    sequence: 2..SMALL unknowns), in one loop: the rows' entries kept as column and
    value lists (no dict per row; the kind's key made from them as `block_key` makes
    it from dicts), and the columns' (row, |entry|) lists remembered with the kind's
    other parts (they depend on the matrix alone); the same float operations in the
    same order (tests/test_bounds_square.py compares the two)."""
    names = rep.unknowns
    col = {nm: j for j, nm in enumerate(names)}
    eqs, sget, eget = system.equations, size.get, err.get
    scale, delta, keys, vals = [], [], [], []
    floats = True
    for k in rep.equations:
        dv, mag = fast_derivatives_and_size(eqs[k].residual, values)
        sc = d = 0
        js = []
        for v, s in dv.items():
            j = col.get(v)
            if j is None:
                a = abs(s)
                if a:
                    sc += a * sget(v, 0.0)
                    d += a * eget(v, 0.0)
            elif s != 0:
                js.append(j)
                vals.append(s)
                if type(s) is not float:
                    floats = False
        keys.append(tuple(js))
        sc = mag + sc
        scale.append(sc)
        if not exact:
            d += ROUNDOFF * sc
        delta.append(d)

    def make(_):
        """(rmax, unit, |A^-1|, cols) as `propagate` makes them from its row dicts."""
        A = [{} for _ in keys]
        cols: list[list[tuple[int, float]]] = [[] for _ in names]
        it = iter(vals)
        for i, js in enumerate(keys):
            Ai = A[i]
            for j in js:
                s = next(it)
                Ai[j] = s
                cols[j].append((i, abs(s)))
        return _matrix_parts(A, cols, True) + (cols,)

    if floats:
        rmax, unit, inv, cols = kind_by_key((tuple(keys), pack(f"{len(vals)}d", *vals)), make)
    else:
        rmax, unit, inv, cols = make(None)
    xs = [abs(values.get(nm, 0.0)) for nm in names]
    big = max([x * u for x, u in zip(xs, unit)])
    for j, name in enumerate(names):
        x = xs[j]
        cands = [scale[i] / a for i, a in cols[j]]
        uj = unit[j]
        size[name] = max(x, min(cands) if cands else x, big / uj if uj > 0 else 0.0)
    q = rep.quality
    comps = q.components if q is not None and q.components else [0.0] * len(names)
    cond = rep.cond if rep.cond and math.isfinite(rep.cond) else 1.0
    isfinite = math.isfinite
    for j, name in enumerate(names):
        if inv is not None:
            e = sum([a * b for a, b in zip(inv[j], delta)])
        else:
            e = cond * max([delta[i] / a for i, a in cols[j]], default=0.0)
        solver = comps[j] * xs[j] if not exact else 0.0
        err[name] = e + solver if isfinite(e) else math.inf


def _row(f, values, col, Ai, cols, i, sget, eget, scale):
    """One row of `propagate`: its entries in the block (into Ai, cols), its scale (into
    scale), its data's error bound (returned). The unknowns from earlier blocks: sizes
    and bounds summed in the derivatives' order from int 0, as `_row_plain` sums them."""
    dv, mag = fast_derivatives_and_size(f, values)
    sc = d = 0
    for v, s in dv.items():
        j = col.get(v)
        if j is None:
            a = abs(s)
            if a:
                sc += a * sget(v, 0.0)
                d += a * eget(v, 0.0)
        elif s != 0:
            Ai[j] = s
            cols[j].append((i, abs(s)))
    scale.append(mag + sc)
    return d


def _flat_pairs(cj):
    """A column of `_row_max` as `_row`'s (row, |entry|) pairs, in order (one iterator
    zipped with itself: no slices made)."""
    it = iter(cj)
    return zip(it, it)


def _row_max(f, values, col, rmax, cols, i, sget, eget, scale):
    """`_row` without the row: its largest |entry| appended to rmax, found as
    `_matrix_parts` finds it (max keeps the first of equals and NaN where it comes first:
    the same comparisons in the same order)."""
    dv, mag = fast_derivatives_and_size(f, values)
    sc = d = 0
    m = None
    for v, s in dv.items():
        j = col.get(v)
        if j is None:
            a = abs(s)
            if a:
                sc += a * sget(v, 0.0)
                d += a * eget(v, 0.0)
        elif s != 0:
            a = abs(s)
            cj = cols[j]  # flat: row, |entry|, row, |entry| ... (`_flat_pairs`)
            cj.append(i)
            cj.append(a)
            if m is None or a > m:
                m = a
    rmax.append(0.0 if m is None else m)
    scale.append(mag + sc)
    return d


def _row_plain(f, values, col, A, cols, i, size, err, scale):
    """`_row` as it was first written (the reference the tests compare with)."""
    dv, mag = derivatives_and_size(f, values)
    up = {v: abs(s) for v, s in dv.items() if v not in col}
    for v, s in dv.items():
        if v in col and s != 0:
            A[i][col[v]] = s
            cols[col[v]].append((i, abs(s)))
    scale.append(mag + sum(s * size.get(v, 0.0) for v, s in up.items() if s))
    return error_of(up, err)


def _abs_inverse(A: list[dict[int, float]]) -> list[list[float]] | None:
    """|A^-1| of a small square matrix (Gauss-Jordan, partial pivoting); None if singular."""
    n = len(A)
    if n == 1:  # the elimination below, on one entry: |1/a|
        a = float(A[0].get(0, 0.0))
        return None if a == 0.0 or not math.isfinite(a) else [[abs(1.0 / a)]]
    M = [[float(row.get(j, 0.0)) for j in range(n)] + [1.0 if i == j else 0.0 for j in range(n)]
         for i, row in enumerate(A)]
    for c in range(n):
        p, big = c, abs(M[c][c])  # the first row of the largest |entry| (as max picks it)
        for r in range(c + 1, n):
            a = abs(M[r][c])
            if a > big:
                p, big = r, a
        if M[p][c] == 0.0 or not math.isfinite(M[p][c]):
            return None
        M[c], M[p] = M[p], M[c]
        piv = M[c][c]
        M[c] = [v / piv for v in M[c]]
        for r in range(n):
            if r != c and M[r][c] != 0.0:
                f = M[r][c]
                M[r] = [a - f * b for a, b in zip(M[r], M[c])]
    return [[abs(v) for v in M[i][n:]] for i in range(n)]
