"""Solve stage: a small linear block whose data were seen before is not solved again.

In: a block's sparse rows and right-hand side (float64 only). Out: what `linalg.solve`
(or `bounds._abs_inverse`) returned for the same data, bit for bit: the key holds every
coefficient's bits and the rows' column order, so -0.0 and 0.0 differ and a sum in
another order is another key. A sequence of N identical impacts solves its few kinds of
blocks once each instead of N times (a 1x1 block costs less to solve than to key);
blocks of one kind (the same matrix, another right-hand side) share its factorization.
Bounded: the tables are emptied when full.
"""
from __future__ import annotations

from math import copysign
from struct import pack

from .linalg import Quality, SingularError, factor_small, solve_factored
from .linalg import solve as linalg_solve
from .linalg import solve_one as linalg_solve_one

LIMIT = 4096  # entries per table; the blocks of a scene repeat in a few kinds
SMALL = 12  # larger blocks are rarely identical and cost more to key than to look up

_solves: dict = {}
_inverses: dict = {}
KINDS = True  # tests turn it off: every block eliminated and inverted afresh
_factors: dict = {}  # a float block's matrix (its key without the rhs) -> Factored or cond


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
        if KINDS and precision == "float" and len(rows) == n and len(rhs) == n:
            hit = _by_kind(rows, rhs, n, key[2:4])
        else:
            hit = linalg_solve(rows, rhs, n, precision)  # a singular block raises: not kept
        if len(_solves) >= LIMIT:
            _solves.clear()
        _solves[key] = hit
    x, q = hit
    return list(x), Quality(q.method, q.precision, q.cond, q.backward, q.bound, q.iterations,
                            list(q.components) if q.components is not None else None,
                            list(q.exact) if q.exact is not None else None)


def _by_kind(rows, rhs, n: int, akey):
    """`linalg.solve` of a float block by its matrix's factorization, made once per
    matrix (`akey`: the rows' columns and the bits of their coefficients) and replayed
    for each right-hand side: a sequence of impacts of one kind (the same masses and
    restitution, other velocities) eliminates its matrix once, not once per impact."""
    akey = (n, akey[0], akey[1][:8 * sum(len(row) for row in rows)])
    F = _factors.get(akey)
    if F is None:
        try:
            F = factor_small(rows, n)
        except SingularError as exc:
            F = exc.cond  # singular: raised again, the same way, for every rhs
        if len(_factors) >= LIMIT:
            _factors.clear()
        _factors[akey] = F
    if type(F) is float:
        raise SingularError(F)
    return solve_factored(F, rhs)


_ones: dict = {}
_one_skip = [0, 0]  # solve_one: calls left with the table off, misses in a row
MISSES, OFF = 256, 4096


def solve_one(a: float, b: float):
    """`linalg.solve_one(a, b)` of a 1x1 float block, remembered by its two numbers: a
    sequence of impacts of one kind repeats its one-unknown rows' data (a still body's
    y row: m v2 = m v1), and keying two floats costs a tenth of the solve. A zero right
    side is keyed with its sign (0.0 and -0.0 are equal keys, their x are not); a
    singular block is not kept (it raises again). Shared: the caller only reads x and
    the Quality (a BlockReport keeps it, nothing changes it). Where the rows do not
    repeat (a chain of other masses), MISSES in a row turn the table off for a while:
    a miss costs a quarter of a solve more."""
    skip = _one_skip
    if skip[0]:
        skip[0] -= 1
        return linalg_solve_one(a, b)
    if type(a) is not float or type(b) is not float:
        return linalg_solve_one(a, b)
    key = (a, b) if b else (a, b, copysign(1.0, b))
    hit = _ones.get(key)
    if hit is None:
        hit = linalg_solve_one(a, b)
        if len(_ones) >= LIMIT:
            _ones.clear()
        _ones[key] = hit
        skip[1] += 1
        if skip[1] >= MISSES:
            skip[0], skip[1] = OFF, 0
    else:
        skip[1] = 0
    return hit


_kinds: dict = {}


def kind_of(A, make):
    """`make(A)` (what depends on a matrix alone), remembered by A's exact data for
    blocks of 2..SMALL rows and shared: the caller only reads it."""
    key = block_key(A) if KINDS and 1 < len(A) <= SMALL else None
    if key is None:
        return make(A)
    return _remembered(_kinds, key, make, A)


_squares: dict = {}


def kind_by_key(key, make):
    """`make(None)` (what depends on a matrix alone), remembered by the `block_key` the
    caller made itself (`bounds._square`, which keeps its rows as lists; its own table:
    it keeps more than `kind_of`'s) and shared: the caller only reads it."""
    if not KINDS:
        return make(None)
    return _remembered(_squares, key, make, None)


def _remembered(table: dict, key, make, arg):
    """table[key], made by make(arg) on a miss; the table is emptied when it holds LIMIT
    entries (a bound on memory, not an eviction policy: kinds recur in runs)."""
    hit = table.get(key, table)
    if hit is table:
        hit = make(arg)
        if len(table) >= LIMIT:
            table.clear()
        table[key] = hit
    return hit


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
