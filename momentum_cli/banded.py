"""Solve stage: large sparse linear blocks by LAPACK's banded LU (a ball chain's 10^5 rows).

In: an equilibrated square block as sparse rows (column -> coefficient) and its
right-hand side. Out: the solution and the 1-norm condition estimate `linalg` makes
(the same four-pattern estimate, from the same factorisation), or None where the block
is not narrow once ordered (the caller then eliminates it in Python). Rows and columns
are ordered by a breadth-first walk of the row-column graph from a far end, so a chain
of contacts becomes a band a few entries wide; `dgbtrf` factors it with partial pivoting.
Only LAPACK's extension module is loaded (not `scipy.linalg`, ~0.3 s to import).
"""
from __future__ import annotations

import math

from .two_product import two_product as _two_product

MAX_WIDTH = 64  # kl + ku beyond this: the band costs more than the Python elimination
_LAPACK: list = []


def _flapack():
    """scipy's LAPACK wrappers (dgbtrf, dgbtrs), or None where scipy is missing."""
    if not _LAPACK:
        mod = None
        try:
            import importlib.util
            import os
            import sys

            mod = sys.modules.get("scipy.linalg._flapack")
            if mod is None:
                # scipy's folder found without running its __init__ (~10 ms: its
                # version checks and test helpers), which the extension never needs
                spec = importlib.util.find_spec("scipy")
                if spec is None or not spec.submodule_search_locations:
                    raise ImportError("scipy")
                here = os.path.join(list(spec.submodule_search_locations)[0], "linalg")
                name = next(f for f in os.listdir(here)
                            if f.startswith("_flapack.") and f.endswith((".so", ".pyd")))
                spec = importlib.util.spec_from_file_location("scipy.linalg._flapack",
                                                              os.path.join(here, name))
                mod = importlib.util.module_from_spec(spec)
                spec.loader.exec_module(mod)
        except Exception:  # noqa: BLE001 - any failure: the Python elimination
            try:
                from scipy.linalg import lapack as mod
            except Exception:  # noqa: BLE001
                mod = None
        _LAPACK.append(mod)
    return _LAPACK[0]


def _walk(A, col_rows, start: int, seen_r, seen_c, rows_out, cols_out) -> int:
    """Breadth-first over rows and columns from row `start`; appends the visit order,
    returns the last row reached (a far end of the component). `seen_r`, `seen_c`:
    lists of flags, set as rows and columns are reached."""
    queue = [start]
    seen_r[start] = True
    append_c, append_r = cols_out.append, queue.append
    for i in queue:  # the queue grows as it is walked: rows in the order they are reached
        for j in A[i]:
            if seen_c[j]:
                continue
            seen_c[j] = True
            append_c(j)
            for r in col_rows[j]:
                if not seen_r[r]:
                    seen_r[r] = True
                    append_r(r)
    rows_out.extend(queue)
    return queue[-1]


def order(A, n: int):
    """(row order, column order) of a narrow band, or None where a row or column is
    empty (structurally singular: the Python elimination names it)."""
    col_rows: list[list[int]] = [[] for _ in range(n)]
    for i, row in enumerate(A):
        if not row:
            return None
        for j in row:
            col_rows[j].append(i)
    if not all(col_rows):
        return None
    rows_out: list[int] = []
    cols_out: list[int] = []
    seen_r = [False] * n
    seen_c = [False] * n
    probe_r = [False] * n  # a probe's own flags, cleared after it (a component's walk
    probe_c = [False] * n  # from its far end must not see the probe's marks)
    for s in range(n):
        if seen_r[s]:
            continue
        # from the far end of this component (a chain walked from its middle is
        # twice as wide): walk once to find it, then again from there
        got_r: list[int] = []
        got_c: list[int] = []
        far = _walk(A, col_rows, s, probe_r, probe_c, got_r, got_c)
        for i in got_r:
            probe_r[i] = False
        for j in got_c:
            probe_c[j] = False
        _walk(A, col_rows, far, seen_r, seen_c, rows_out, cols_out)
    return rows_out, cols_out


def _coo(A, pr, pc):
    """The block's entries as (band row, band column, value) arrays, in row order."""
    from itertools import chain

    import numpy as np

    # read straight from the rows' dicts into typed arrays (no list of boxed numbers:
    # a 10^5-row block's were the solve's peak memory; no Python loop per entry)
    lens = np.fromiter(map(len, A), dtype=np.intp, count=len(A))
    total = int(lens.sum())
    cols = np.fromiter(chain.from_iterable(A), dtype=np.intp, count=total)
    vv = np.fromiter(chain.from_iterable(row.values() for row in A), dtype=float,
                     count=total)
    first = np.cumsum(lens) - lens  # each row's first entry
    ii = np.repeat(np.array(pr, dtype=np.intp)[:len(A)], lens)
    jj = np.array(pc, dtype=np.intp)[cols]
    kk = np.arange(total, dtype=np.intp) - np.repeat(first, lens)  # place in its row
    return ii, jj, vv, kk


def _positions(got, n: int):
    rows_out, cols_out = got
    pr = [0] * n  # position of each row and column in the band
    for p, i in enumerate(rows_out):
        pr[i] = p
    pc = [0] * n
    for p, j in enumerate(cols_out):
        pc[j] = p
    return pr, pc


def _factor_solve(lapack, I, J, V, n: int, rhs):
    """Solve the band (entries I, J, V in band positions) for the columns of `rhs`
    (band rows); None if too wide, [] if a pivot is exactly zero."""
    import numpy as np

    d = I - J
    kl = int(max(d.max(), 0))
    ku = int(max(-d.min(), 0))
    if kl + ku > MAX_WIDTH:
        return None
    ab = np.zeros((2 * kl + ku + 1, n), order="F")
    ab[kl + ku + I - J, J] = V
    lu, piv, info = lapack.dgbtrf(ab, kl, ku, overwrite_ab=1)
    if info != 0:  # an exactly zero pivot: singular (the caller's error path names it)
        return []
    x, info = lapack.dgbtrs(lu, kl, ku, rhs, piv, overwrite_b=1)
    return x if info == 0 else None


def _with_patterns(lapack, I, J, V, n, b_band, perm, cols_out, patterns):
    """(y, |A^-1|_1 estimate) in the block's own column order, or None / ([], inf)."""
    import numpy as np

    rhs = np.empty((n, 1 + len(patterns)), order="F")
    rhs[:, 0] = b_band
    k = perm.astype(float)  # each band row's equation index: the patterns' k
    for q, pat in enumerate(patterns, 1):
        rhs[:, q] = pat(k, n)
    sizes = np.abs(rhs[:, 1:]).sum(axis=0)  # |b|_1 of each pattern
    x = _factor_solve(lapack, I, J, V, n, rhs)
    if x is None or len(x) == 0:
        return None if x is None else (np.empty(0), math.inf)
    out = np.empty_like(x)
    out[np.array(cols_out, dtype=np.intp)] = x  # band column p is unknown cols_out[p]
    if not np.isfinite(out).all():
        return out[:, 0], math.inf
    est = max(float(np.abs(out[:, q]).sum() / sizes[q - 1])
              for q in range(1, 1 + len(patterns)))
    return out[:, 0], est


def solve(A, b: list[float], n: int, patterns):
    """(y, |A^-1|_1 estimate) of an equilibrated block by a banded LU, or None (not
    square, not narrow, or no LAPACK); y is [] where a pivot is exactly zero."""
    if len(A) != n:
        return None
    got = order(A, n)
    lapack = _flapack() if got is not None else None
    if lapack is None:
        return None
    import numpy as np

    pr, pc = _positions(got, n)
    I, J, V, _ = _coo(A, pr, pc)
    perm = np.array(got[0], dtype=np.intp)  # band row p is equation perm[p]
    res = _with_patterns(lapack, I, J, V, n, np.array(b, dtype=float)[perm], perm, got[1],
                         patterns)
    if res is None:
        return None
    return res[0].tolist(), res[1]


def _pow2(x):
    """linalg._pow2 on arrays: the power of two at or below |x|; 1 for 0 and non-finite."""
    import numpy as np

    m, e = np.frexp(x)
    out = np.ldexp(1.0, e - 1)
    out[(x == 0.0) | ~np.isfinite(x)] = 1.0
    return out


def _two_sum_into(s, comp, rows, t) -> None:
    """s[rows] += t exactly as a two-sum: the rounded sum into s, its error into comp
    (rows are distinct)."""
    a = s[rows]
    x = a + t
    bv = x - a
    comp[rows] += (a - (x - bv)) + (t - bv)
    s[rows] = x


def solve_float(rows, b: list[float], n: int, patterns, eps: float):
    """`linalg.solve_rows` in float for a large square block, on arrays: the same
    equilibration (bit for bit), a banded LU, the same round-off snap and componentwise
    bounds; the residual of the backward error summed in doubled precision (error-free
    products, compensated sums) rather than by fsum row by row. (x, cond, backward,
    components) as lists and floats, or None where the block is not narrow (the caller
    takes the general path); cond is inf where the LU meets an exactly zero pivot."""
    if len(rows) != n:
        return None
    got = order(rows, n)
    lapack = _flapack() if got is not None else None
    if lapack is None:
        return None
    import numpy as np

    pr, pc = _positions(got, n)
    I, J, V, R = _coo(rows, pr, pc)  # band positions, entries in row order
    bb = np.empty(n)
    bb[np.array(pr, dtype=np.intp)] = np.array(b, dtype=float)
    # equilibrate: rows, then columns, by powers of two (exact)
    rmax = np.zeros(n)
    np.maximum.at(rmax, I, np.abs(V))
    r = _pow2(rmax)
    cmax = np.zeros(n)
    np.maximum.at(cmax, J, np.abs(V) / r[I])
    c = _pow2(cmax)
    A = V / r[I] / c[J]
    bs = bb / r
    norm1 = np.zeros(n)
    np.add.at(norm1, J, np.abs(A))  # column sums, entries in row order as _norm1 adds
    norm1 = float(norm1.max())
    perm = np.array(got[0], dtype=np.intp)
    res = _with_patterns(lapack, I, J, A, n, bs, perm, got[1], patterns)
    if res is None:
        return None
    y_cols, inv = res
    cond = norm1 * inv
    if len(y_cols) == 0 or not math.isfinite(cond):
        return [], cond, 0.0, []
    y = np.empty(n)  # in band column order from here
    y[np.array(pc, dtype=np.intp)] = y_cols
    # snap_roundoff: a column whose every term is round-off against its row's size is 0
    t = np.abs(A * y[J])
    size = np.zeros(n)
    np.add.at(size, I, t)
    size = np.abs(bs) + size
    keep = np.zeros(n, dtype=bool)
    keep[J[t > 1e-15 * size[I]]] = True
    y = np.where(keep, y, 0.0)
    # backward error: |b - A y| / (|A| |y| + |b|), the residual in doubled precision
    p, e = _two_product(A, y[J])
    s = bs.copy()
    comp = np.zeros(n)
    for term in (p, e):  # the row's terms by two-sums, k-th entries of all rows at once
        for k in range(int(R.max(initial=-1)) + 1):
            at = R == k
            rows_k = I[at]
            _two_sum_into(s, comp, rows_k, -term[at])
    r_ = np.abs(s + comp)  # the residual: sum and its compensation
    rows_abs = np.zeros(n)
    np.add.at(rows_abs, I, np.abs(A))
    denom = float(rows_abs.max()) * float(np.abs(y).max(initial=0.0)) + \
        float(np.abs(bs).max(initial=0.0))
    num = float(r_.max(initial=0.0))
    back = num / denom if denom > 0 else num
    normwise = cond * max(back, eps)
    big = float(np.abs(y).max(initial=0.0))
    ay = np.abs(y)
    with np.errstate(divide="ignore", invalid="ignore"):
        comps = np.where(y != 0.0, normwise * big / ay, normwise)
    x = y / c
    back_cols = np.array(got[1], dtype=np.intp)  # band column p is unknown got[1][p]
    xo = np.empty(n)
    xo[back_cols] = x
    co = np.empty(n)
    co[back_cols] = comps
    return xo.tolist(), cond, back, co.tolist()
