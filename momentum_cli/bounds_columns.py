"""Solve stage: the sizes and error bounds of a large sparse block's unknowns, as arrays.

In: what `bounds.propagate` has gathered for a block past DENSE (each row's largest
entry, scale and data error; each column's (row, |entry|) pairs; the unknowns' values,
the solver's componentwise bounds and the condition number). Out: each unknown's size
and error bound, as `propagate`'s loops over the columns make them, or None where
they might differ. The loops take a minimum or a maximum over each column's few
entries and a quotient or a product per entry; numpy's elementwise quotients and
products are the same IEEE operations, and over finite, non-negative numbers (no NaN,
no -0.0: every input is an absolute value or a sum of them) a minimum or maximum is
the same number whichever order takes it. So any non-finite input returns None and
the loops run. Only for blocks the banded LU solved (BIG unknowns or more: numpy is
loaded already). tests/test_bounds_columns.py compares both on chains and random
blocks, non-finite ones included.
"""
from __future__ import annotations

from itertools import chain

ENABLED = True  # tests turn it off: every column by `propagate`'s loops


def sizes_and_errors(cols, rmax, scale, delta, xs, comps, cond: float, solved: bool):
    """(sizes, errors) as lists of floats in the columns' order, or None."""
    import numpy as np

    n = len(cols)
    if len(xs) != n or len(comps) != n:
        return None
    lens = np.fromiter((len(cj) for cj in cols), dtype=np.intp, count=n) >> 1
    flat = np.array(list(chain.from_iterable(cols)), dtype=float)
    return _from_entries(np, n, lens, flat[0::2].astype(np.intp), flat[1::2], rmax, scale,
                         delta, xs, comps, cond, solved)


def from_rows(rows, cols, ents, rmax, scale, delta, xs, comps, cond: float, solved: bool):
    """`sizes_and_errors` of a block's entries given as arrays (row, column, |entry|) in
    row order (`bounds_rows.read`): each column's entries in row order, as the columns'
    lists hold them."""
    import numpy as np

    n = len(xs)
    if len(comps) != n:
        return None
    by_col = np.lexsort((rows, cols))  # by column, then row
    return _from_entries(np, n, np.bincount(cols, minlength=n), rows[by_col],
                         ents[by_col], rmax, scale, delta, xs, comps, cond, solved)


def _from_entries(np, n, lens, rows, ent, rmax, scale, delta, xs, comps, cond, solved):
    """`sizes_and_errors` from the entries in column order (`lens` per column)."""
    rmax = np.array(rmax, dtype=float)
    scale = np.array(scale, dtype=float)
    delta = np.array(delta, dtype=float)
    x = np.array(xs, dtype=float)
    comp = np.array(comps, dtype=float)
    for a in (ent, rmax, scale, delta, x, comp):
        if not np.isfinite(a).all():
            return None
    if not np.isfinite(cond):
        return None
    with np.errstate(all="ignore"):  # overflow to inf, as the loops' floats do
        full = lens > 0
        starts = (np.cumsum(lens) - lens)[full]  # each non-empty column's first entry
        # each column's largest entry scaled by its row's largest (rows with one above 0)
        rm = rmax[rows]
        ratio = np.where(rm > 0, ent / np.where(rm > 0, rm, 1.0), -np.inf)
        unit = np.zeros(n)
        if len(starts):
            u = np.maximum.reduceat(ratio, starts)
            unit[full] = np.where(u == -np.inf, 0.0, u)
        big = float(np.max(x * unit)) if n else 0.0
        least = x.copy()  # min(cands) if cands else x
        if len(starts):
            least[full] = np.minimum.reduceat(scale[rows] / ent, starts)
        pos = unit > 0
        third = np.where(pos, big / np.where(pos, unit, 1.0), 0.0)
        sizes = np.maximum(np.maximum(x, least), third)
        worst = np.zeros(n)  # max([...], default=0.0)
        if len(starts):
            worst[full] = np.maximum.reduceat(delta[rows] / ent, starts)
        e = cond * worst
        solver = comp * x if solved else np.zeros(n)
        errs = np.where(np.isfinite(e), e + solver, np.inf)
        return sizes.tolist(), errs.tolist()
