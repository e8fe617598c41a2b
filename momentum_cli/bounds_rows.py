"""Solve stage: a large sparse block's rows for its error bounds, read as arrays per shape.

In: a block `bounds.propagate` bounds with its column arrays (the banded LU's blocks:
10^4-10^5 rows), the solved values and the sizes and bounds of earlier unknowns. Out:
each row's largest |entry|, scale and data error, and the block's entries (row, column,
|entry|), as numpy arrays; or None, and `_row_max` reads the rows one by one as before.
A chain's rows come in a handful of shapes (rowcode's keys, already taken by the
solve): the rows of one shape are one table (a column per number, per unknown) and the
shape's walk (`rowcode.emit_gs`, the code the per-row walk runs) runs once on whole
columns. Elementwise numpy operations are the same IEEE operations on each element, so
where every number is finite the results are the per-row ones bit for bit; anything
not finite (and any unknown without a value) returns None. tests/test_bounds_rows.py
compares both on chains and examples.
"""
from __future__ import annotations

import sys

from . import rowcode

ENABLED = True  # tests turn it off: every row by `bounds._row_max`
_WALKS: dict = {}  # shape key -> its walk on columns, or None where it has none


def _column_walk(key):
    """f(c, x) -> (size, slopes) for the shape `key` on columns: c the numbers' columns,
    x the unknowns' value columns; slopes: (first position, column) of each distinct
    unknown in the order the per-row walk's dict holds them. None for a shape whose walk
    sums more than two values (`fsum` of three: not one IEEE addition)."""
    firsts: list[int] = []

    def add(i, same, w, c, n):
        if same not in firsts:
            firsts.append(same)
            return f"    d{same} = 0.0 + {w}"
        return f"    d{same} = d{same} + {w}"

    s = rowcode._Src()
    root, size, _val = rowcode.emit_gs(s, key, add=add)
    if any("fsum([" in line and line.count(",") > 1 for line in s.lines):
        return None
    s.lines.append(f"    return {size}, ({''.join(f'd{p}, ' for p in firsts)})")
    f = s.function("cgs(c, n, values, w)", {"fsum": _fsum2, "abs": abs})
    return f, tuple(firsts)


class _NotFinite(Exception):
    pass


def _fsum2(parts):
    """`math.fsum` of one or two columns: one rounding, the sum itself (+ 0.0: fsum's
    zero is +0.0); where one is not finite, fsum would raise: the rows decline."""
    got = (parts[0] if len(parts) == 1 else parts[0] + parts[1]) + 0.0
    if not _np().isfinite(got).all():
        raise _NotFinite
    return got


def _np():
    return sys.modules["numpy"]


def _walk_of(key):
    return rowcode.kept(_WALKS, key, _column_walk)


def read(eqs, equations, col: dict, values, size: dict, err: dict, roundoff: float):
    """(rmax, scale, delta, rows, cols, ents) as `bounds._row_max` makes them for each of
    `equations` (delta with the rounding term added, as `propagate` adds it to a float
    solve's linear rows), entries with a nonzero slope in row order; or None."""
    np = sys.modules.get("numpy")
    if not ENABLED or np is None or not rowcode.ENABLED:
        return None
    from .block_rows import groups

    g = groups(eqs, equations)
    if g is None:
        return None
    m = len(equations)
    rmax = np.zeros(m)
    scale = np.zeros(m)
    delta = np.zeros(m)
    e_rows, e_cols, e_ents = [], [], []
    sget, eget, cget = size.get, err.get, col.get
    for key, (idx, ii, c, by_pos) in g.by_key.items():
        walk = _walk_of(key)
        if walk is None:
            return None
        f, firsts = walk
        r = len(idx)
        try:
            x = [np.array([values[nm] for nm in nms], dtype=float) for nms in by_pos]
        except (KeyError, TypeError, ValueError):
            return None
        with np.errstate(all="ignore"):
            try:
                got_size, slopes = f(c, list(range(len(x))), x, 1.0)
            except _NotFinite:
                return None
            mag = np.broadcast_to(np.asarray(got_size, dtype=float), (r,))
            sc = np.zeros(r)
            d = np.zeros(r)
            m_row = np.zeros(r)
            for p, s in zip(firsts, slopes):
                s = np.broadcast_to(np.asarray(s, dtype=float), (r,))
                if not np.isfinite(s).all():
                    return None
                nms = by_pos[p]
                j = np.array([cget(nm, -1) for nm in nms], dtype=np.intp)
                a = np.abs(s)
                inside = j >= 0
                out = ~inside & (a != 0.0)
                if out.any():
                    sz = np.array([sget(nm, 0.0) for nm in nms], dtype=float)
                    er = np.array([eget(nm, 0.0) for nm in nms], dtype=float)
                    sc = sc + np.where(out, a * sz, 0.0)
                    d = d + np.where(out, a * er, 0.0)
                hit = inside & (s != 0.0)
                if hit.any():
                    m_row = np.maximum(m_row, np.where(hit, a, 0.0))
                    e_rows.append(ii[hit])
                    e_cols.append(j[hit])
                    e_ents.append(a[hit])
            sc = mag + sc
            d = d + roundoff * sc
        for v in (mag, sc, d):
            if not np.isfinite(v).all():
                return None
        rmax[ii] = m_row
        scale[ii] = sc
        delta[ii] = d
    if not e_rows:
        return None
    return (rmax, scale, delta, np.concatenate(e_rows), np.concatenate(e_cols),
            np.concatenate(e_ents))

