"""Solve stage: a large block's rows read once per shape, for its solve and its bounds.

In: a large linear block's equations (a chain's 10^4-10^5 contact and momentum rows),
the solved values. Out: the rows grouped by shape (rowcode's keys: a chain has a
handful): each group's row indices, numbers and unknowns' names as columns; from them
the block's sparse rows and right-hand side as `solve._solve_block` makes them, the
affine walk of each (shape, which unknowns are the block's) run once on whole columns
(numpy: the same IEEE operations per element, NaN and inf included; no float operation
of the walk raises). `bounds_rows` reads the same groups for the block's bounds (the
last block read is kept until then). None where any row has no shape, a value is
missing or a row is not linear: `_solve_block` then reads its rows one by one (and
says what it says of them). tests/test_block_rows.py compares both, bit for bit.
"""
from __future__ import annotations

import sys

from . import rowcode
from .expr import NonLinear

ENABLED = True  # tests turn it off: every row by `rowcode.affine`
_AFF: dict = {}  # (shape key, inside flags) -> affine walk on columns, or None
_LAST: list = [None, None, None]  # the equations list last kept, its system's, its groups


class Groups:
    """A block's rows by shape: key -> (row indices as a list and an array, the numbers'
    columns as arrays, the names by position as tuples)."""

    __slots__ = ("by_key", "m")

    def __init__(self, by_key: dict, m: int):
        self.by_key, self.m = by_key, m


def groups(eqs, equations, keep: bool = False) -> Groups | None:
    """The rows of `equations` by shape; None where a row has no shape. `keep`: kept
    until `forget` (a block is read by its solve, then by its bounds)."""
    if _LAST[0] is equations and _LAST[1] is eqs:
        return _LAST[2]
    np = sys.modules.get("numpy")
    if np is None or not rowcode.ENABLED:
        return None
    by_key, free = rowcode.grouped([eqs[k].residual for k in equations])
    if free:
        return None
    out = {}
    for key, (idx, nums, names) in by_key.items():
        c = [np.array(cv, dtype=float) for cv in zip(*nums)] if nums[0] else []
        by_pos = list(zip(*names)) if names[0] else []
        out[key] = (idx, np.array(idx, dtype=np.intp), c, by_pos)
    got = Groups(out, len(equations))
    if keep:
        _LAST[0], _LAST[1], _LAST[2] = equations, eqs, got
    return got


def forget() -> None:
    """Drop the kept block (its bounds are done)."""
    _LAST[0] = _LAST[1] = _LAST[2] = None


def _affine_walk(key, inside):
    """f(c, n, values) -> (coef expressions in the walk's order, const) on columns, with
    the positions of each coefficient's unknown; None where the shape is not linear in
    the block's unknowns."""
    s = rowcode._Src()
    try:
        coef, const = rowcode.emit_affine(s, key, inside)
    except rowcode._Stop:
        return None
    items = ", ".join(v for _same, v, _i in coef)
    s.lines.append(f"    return ({items}{',' if coef else ''}), {const}")
    return s.function("caff(c, n, values)", {"NonLinear": NonLinear}), \
        tuple(i for _same, _v, i in coef)


def rows(eqs, equations, col: dict, values):
    """(rows, rhs) of the block as `_solve_block` makes them (each row a dict column ->
    coefficient in the walk's order, zeros left out; rhs the constants negated), or
    None."""
    if not ENABLED:
        return None
    np = sys.modules.get("numpy")
    g = groups(eqs, equations, keep=True)
    if g is None:
        return None
    m = g.m
    out_rows: list = [None] * m
    rhs = np.zeros(m)
    cget = col.get
    with np.errstate(all="ignore"):
        for key, (idx, ii, c, by_pos) in g.by_key.items():
            r = len(idx)
            js = [np.array([cget(nm, -1) for nm in nms], dtype=np.intp) for nms in by_pos]
            flags = np.zeros(r, dtype=np.int64)
            for p, j in enumerate(js):
                if p >= 62:
                    return None
                flags |= (j >= 0).astype(np.int64) << p
            for pattern in np.unique(flags).tolist():
                inside = tuple(bool(pattern >> p & 1) for p in range(len(js)))
                walk = _walk_for(key, inside)
                if walk is None:
                    return None
                f, positions = walk
                sel = np.flatnonzero(flags == pattern)
                every = len(sel) == r
                cs = c if every else [col_[sel] for col_ in c]
                try:
                    xs = [None if inside[p] else
                          np.array([values[nms[t]] for t in sel.tolist()], dtype=float)
                          for p, nms in enumerate(by_pos)]
                    coefs, const = f(cs, list(range(len(by_pos))), xs)
                except (KeyError, TypeError, ValueError, NonLinear):
                    return None
                n_sel = len(sel)
                rows_at = ii[sel]
                rhs[rows_at] = -np.broadcast_to(np.asarray(const, dtype=float), (n_sel,))
                jcols = [js[p][sel].tolist() for p in positions]
                vcols = [np.broadcast_to(np.asarray(v, dtype=float), (n_sel,)).tolist()
                         for v in coefs]
                for i, jr, vr in zip(rows_at.tolist(), zip(*jcols) if jcols else
                                     [()] * n_sel, zip(*vcols) if vcols else [()] * n_sel):
                    out_rows[i] = {j: v for j, v in zip(jr, vr) if v != 0.0}
    return out_rows, rhs.tolist()


def ones(eqs, equations, names, values):
    """(a, b, stop) of a run of one-unknown rows (`solve_ones.run`: row i in names[i]
    alone) as `rowcode.affine(row, {name: 0}, values)` gives them, a the coefficient of
    the row's own unknown (0.0 where it has none), b the constant negated: the rows
    before `stop`, the first row the run takes no further (a value missing, not linear,
    a zero or a number not finite); None where a row has no shape."""
    if not ENABLED:
        return None
    np = sys.modules.get("numpy")
    g = groups(eqs, equations)
    if g is None:
        return None
    m = g.m
    A = np.zeros(m)
    B = np.zeros(m)
    bad = np.zeros(m, dtype=bool)
    missing = _MISSING
    with np.errstate(all="ignore"):
        for key, (idx, ii, c, by_pos) in g.by_key.items():
            own = [names[i] for i in idx]
            r = len(idx)
            flags = np.zeros(r, dtype=np.int64)
            for p, nms in enumerate(by_pos):
                if p >= 62:
                    return None
                mine = np.fromiter(map(str.__eq__, nms, own), dtype=bool, count=r)
                flags |= mine.astype(np.int64) << p
            for pattern in np.unique(flags).tolist():
                inside = tuple(bool(pattern >> p & 1) for p in range(len(by_pos)))
                sel = np.flatnonzero(flags == pattern)
                rows_at = ii[sel]
                walk = _walk_for(key, inside)
                if walk is None:  # not linear in the row's own unknown
                    bad[rows_at] = True
                    continue
                f, positions = walk
                cs = c if len(sel) == r else [col_[sel] for col_ in c]
                gone = np.zeros(len(sel), dtype=bool)
                xs = []
                for p, nms in enumerate(by_pos):
                    if inside[p]:
                        xs.append(None)
                        continue
                    got = [values.get(nms[t], missing) for t in sel.tolist()]
                    lost = np.fromiter((v is missing for v in got), dtype=bool, count=len(got))
                    if lost.any():
                        gone |= lost
                        got = [0.0 if v is missing else v for v in got]
                    try:
                        xs.append(np.array(got, dtype=float))
                    except (TypeError, ValueError):
                        return None
                try:
                    coefs, const = f(cs, list(range(len(by_pos))), xs)
                except (TypeError, ValueError, NonLinear):
                    return None
                n_sel = len(sel)
                a = np.broadcast_to(np.asarray(coefs[0], dtype=float), (n_sel,)) if coefs \
                    else np.zeros(n_sel)
                A[rows_at] = a
                B[rows_at] = -np.broadcast_to(np.asarray(const, dtype=float), (n_sel,))
                bad[rows_at] |= gone
        bad |= (A == 0.0) | ~np.isfinite(A) | ~np.isfinite(B)
    stop = int(np.argmax(bad)) if bad.any() else m
    return A[:stop].tolist(), B[:stop].tolist(), stop


_MISSING = object()


def _walk_for(key, inside):
    k = (key, inside)
    if k not in _AFF:
        if len(_AFF) >= rowcode.LIMIT:
            _AFF.clear()
        _AFF[k] = _affine_walk(key, inside)
    return _AFF[k]
