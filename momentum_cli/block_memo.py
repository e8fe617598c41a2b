"""Solve stage: a small linear block whose data were seen before is not solved again.

In: a block's sparse rows and right-hand side (float64 only). Out: what `linalg.solve`
(or `bounds._abs_inverse`) returned for the same data, bit for bit: the key holds every
coefficient's bits and the rows' column order, so -0.0 and 0.0 differ and a sum in
another order is another key. A sequence of N identical impacts solves its few kinds of
blocks once each instead of N times (a 1x1 block costs less to solve than to key).
Bounded: the table is emptied when full.
"""
from __future__ import annotations

from struct import pack

from .linalg import Quality, solve as linalg_solve

LIMIT = 4096  # entries per table; the blocks of a scene repeat in a few kinds
SMALL = 12  # larger blocks are rarely identical and cost more to key than to look up

_solves: dict = {}
_inverses: dict = {}


def block_key(rows, rhs=()) -> tuple | None:
    """The exact identity of a block's data, or None when it holds anything but floats
    (rationals of exact mode, traced numbers of a sweep: never shared)."""
    vals = [v for row in rows for v in row.values()]
    vals.extend(rhs)
    for v in vals:
        if type(v) is not float:
            return None
    return (tuple([tuple(row) for row in rows]), pack(f"{len(vals)}d", *vals))


def solve(rows, rhs, n: int, precision: str = "float"):
    """`linalg.solve`, remembered for float and refine solves of small blocks. Each
    caller gets its own lists (a Quality's components are never shared)."""
    key = block_key(rows, rhs) if 1 < n <= SMALL and precision != "exact" else None
    if key is None:
        return linalg_solve(rows, rhs, n, precision)
    key = (n, precision) + key
    hit = _solves.get(key)
    if hit is None:
        hit = linalg_solve(rows, rhs, n, precision)  # a singular block raises: not kept
        if len(_solves) >= LIMIT:
            _solves.clear()
        _solves[key] = hit
    x, q = hit
    return list(x), Quality(q.method, q.precision, q.cond, q.backward, q.bound, q.iterations,
                            list(q.components) if q.components is not None else None,
                            list(q.exact) if q.exact is not None else None)


def abs_inverse(A, compute):
    """`compute(A)` (|A^-1| or None), remembered by A's exact data; a fresh copy each."""
    key = block_key(A) if 1 < len(A) <= SMALL else None
    if key is None:
        return compute(A)
    if key in _inverses:
        hit = _inverses[key]
    else:
        hit = compute(A)
        if len(_inverses) >= LIMIT:
            _inverses.clear()
        _inverses[key] = hit
    return None if hit is None else [list(r) for r in hit]
