"""Solve stage: a large sum's terms of one shape walked as arrays (an energy's 10^5 terms).

In: the terms of a sum (`rowcode._vgs`'s walk of an answer: a kinetic energy, an energy
lost), the solved values. Out: each term's value and size, as the shape's compiled
walk makes them, and each slope the walk adds to the derivatives, in the walk's order.
The terms of one shape are one table (a column per number, per unknown) and the shape's
walk (`rowcode.emit_gs`, with its value) runs once on whole columns: elementwise numpy
operations are the same IEEE operations on each element, so where every number is
finite the values are the per-term ones bit for bit; the derivatives are then added to
the walk's dict term by term in order, as the walk adds them. Anything not finite, a
missing value, a sum inside a term of more than two parts: None (the walk runs).
tests/test_terms_columns.py compares both on chains and random sums.
"""
from __future__ import annotations

import sys
from bisect import bisect_left
from itertools import chain

from . import rowcode

ENABLED = True  # tests turn it off: every term by its compiled walk
MIN_TERMS = 256  # shorter sums term by term (arrays cost more than they save)
_WALKS: dict = {}  # shape key -> (f, positions of its slopes) or None


class _NotFinite(Exception):
    pass


def _fsum2(parts):
    """`math.fsum` of one or two columns: one rounding (+ 0.0: fsum's zero is +0.0);
    where one is not finite fsum would raise or differ: decline."""
    got = (parts[0] if len(parts) == 1 else parts[0] + parts[1]) + 0.0
    if not sys.modules["numpy"].isfinite(got).all():
        raise _NotFinite
    return got


def _column_walk(key):
    """f(c, n, values, w) -> (value, size, slopes): `rowcode`'s vgs walk of the shape on
    columns, slopes one per statement adding to the walk's dict, in its order, with the
    position of each one's unknown; None where a sum has more than two parts."""
    positions: list[int] = []

    def add(i, same, w, c, n):
        positions.append(i)
        return f"    s{len(positions)} = {w}"

    s = rowcode._Src()
    root, size, val = rowcode.emit_gs(s, key, add=add)
    value = val(root)
    if any("fsum([" in line and line.count(",") > 1 for line in s.lines):
        return None
    slopes = "".join(f"s{k + 1}, " for k in range(len(positions)))
    s.lines.append(f"    return {value}, {size}, ({slopes})")
    return s.function("cvgs(c, n, values, w)", {"fsum": _fsum2, "abs": abs}), \
        tuple(positions)


def _walk_of(key):
    return rowcode.kept(_WALKS, key, _column_walk)


def walk_sum(terms, w, values, out, walk_term):
    """(values, sizes) of the terms as lists in order, their slopes times w added to
    `out` in the walk's order (`walk_term(x)`: the walk of a term without a shape, in
    its place); None where the arrays decline (before `out` is touched)."""
    np = sys.modules.get("numpy")
    if not ENABLED or np is None or len(terms) < MIN_TERMS:
        return None
    groups, free = rowcode.grouped(terms)  # free: the terms without a shape, in order
    if len(groups) * 8 > len(terms):
        return None  # too few terms of each shape
    n = len(terms)
    V = np.zeros(n)
    Z = np.zeros(n)
    sloped = []  # (term indices, names by slope, slopes by slope) of shapes with slopes
    with np.errstate(all="ignore"):
        for key, (idx, nums, names) in groups.items():
            walk = _walk_of(key)
            if walk is None:
                return None
            f, positions = walk
            r = len(idx)
            c = [np.array(cv, dtype=float) for cv in zip(*nums)] if nums[0] else []
            by_pos = list(zip(*names)) if names[0] else []
            try:
                x = [np.array([values[nm] for nm in nms], dtype=float) for nms in by_pos]
                v, z, slopes = f(c, list(range(len(x))), x, w)
            except (KeyError, TypeError, ValueError, _NotFinite):
                return None
            v = np.broadcast_to(np.asarray(v, dtype=float), (r,))
            z = np.broadcast_to(np.asarray(z, dtype=float), (r,))
            cols = [np.broadcast_to(np.asarray(s, dtype=float), (r,)) for s in slopes]
            for a in (v, z, *cols):
                if not np.isfinite(a).all():
                    return None
            ii = np.array(idx, dtype=np.intp)
            V[ii] = v
            Z[ii] = z
            if cols:
                sloped.append((idx, [by_pos[p] for p in positions], [s.tolist() for s in cols]))
    # the slopes into `out` in the walk's order: term by term, each term's in its order,
    # a term without a shape walked in its place
    vs = V.tolist()
    zs = Z.tolist()
    get = out.get
    ends = free + [n]
    at = 0
    for stop in ends:
        parts = []  # each shape's terms with slopes in [at, stop): rows lo..hi
        for idx, nms, sl in sloped:
            lo, hi = bisect_left(idx, at), bisect_left(idx, stop)
            if lo < hi:
                parts.append((idx, nms, sl, lo, hi))
        if len(parts) == 1:  # one shape: its rows in order, each row's slopes in order
            _idx, nms, sl, lo, hi = parts[0]
            pairs_n = list(chain.from_iterable(zip(*[col[lo:hi] for col in nms])))
            pairs_s = list(chain.from_iterable(zip(*[col[lo:hi] for col in sl])))
        elif parts:  # terms of several shapes: their slopes sorted into term order
            most = max(len(nms) for _idx, nms, _sl, _lo, _hi in parts)
            keys, pairs_n, flat_s = [], [], []
            for idx, nms, sl, lo, hi in parts:
                at_terms = np.array(idx[lo:hi], dtype=np.int64) * most
                for a, (col_n, col_s) in enumerate(zip(nms, sl)):
                    keys.append(at_terms + a)
                    pairs_n.extend(col_n[lo:hi])
                    flat_s.extend(col_s[lo:hi])
            by_term = np.argsort(np.concatenate(keys), kind="stable").tolist()
            pairs_n = [pairs_n[k] for k in by_term]
            pairs_s = [flat_s[k] for k in by_term]
        else:
            pairs_n = pairs_s = []
        if pairs_n and len(set(pairs_n)) == len(pairs_n) and out.keys().isdisjoint(pairs_n):
            out.update(zip(pairs_n, [0.0 + w_ for w_ in pairs_s]))  # each new: 0.0 + w
        else:
            for nm, w_ in zip(pairs_n, pairs_s):
                out[nm] = get(nm, 0.0) + w_
        if stop < n:
            vs[stop], zs[stop] = walk_term(terms[stop])
        at = stop + 1
    return vs, zs

