"""Solve stage: a run of one-unknown blocks solved together, their scalar solves as arrays.

In: the solve's order of blocks, from a block of one unknown in one equation, and the
values known so far. Out: how far the run went and each block's report, its value set
as `solve._solve_one` sets it, in the same order. A big scene has thousands of such
blocks one after another (each ball's y velocity in a chain: all of one shape, none
needing another), and their 1x1 solves (equilibration, condition, round-off snap,
backward error) cost as much as reading their rows: here the rows are read one by one
(rowcode's compiled walks, as before) and the solves run as numpy arrays, the same IEEE
operations on each element (`linalg.solve_one`'s steps; the residual's `fsum` still one
by one). A run stops before a block that needs a value the run has not set yet, or that
`_solve_one` would hand on (not linear, not finite, a zero coefficient, singular): the
caller takes that block as it always did. Only where numpy is loaded already (by a large
block's banded LU) and the run is long. tests/test_solve_ones.py compares the solve with
and without it, bit for bit.
"""
from __future__ import annotations

import math
import sys

from . import rowcode
from .expr import NonLinear
from .linalg import EPS, SINGULAR_COND, Quality

ENABLED = True  # tests turn it off: every block by `_solve_one`
MIN_RUN = 64  # shorter runs one by one (arrays cost more than they save)


def run(system, blocks, order, start: int, values, make_report) -> tuple[int, list, int]:
    """(index in `order` after the run, [(block, report)] of the blocks solved, index
    before which no run is tried again) from order[start]; no blocks where no run is
    taken (each block's row is then read at most once more, one by one).
    `make_report(block, a, b, x, quality)`: the BlockReport `_solve_one` makes."""
    np = sys.modules.get("numpy")
    if not ENABLED or np is None or len(order) - start < MIN_RUN:
        return start, [], len(order)  # no run from here on
    end = start  # first, by their sizes alone: is the run long enough?
    stop = min(len(order), start + MIN_RUN)
    while end < stop:
        block = blocks[order[end]]
        if len(block.unknowns) != 1 or len(block.equations) != 1:
            break
        end += 1
    if end - start < MIN_RUN:
        return start, [], end + 1
    eqs = system.equations
    got = _read_as_arrays(eqs, blocks, order, start, values)
    if got is not None:
        taken, As, Bs, k = got
    else:
        taken, As, Bs, k = _read_one_by_one(eqs, blocks, order, start, values)
    if len(taken) < MIN_RUN:
        return start, [], k + 1
    out = []
    for block, a, b, got in zip(taken, As, Bs, solve_ones(np, As, Bs)):
        if got is None:  # singular: `_solve_one` would hand it on; so does the caller
            break
        x, quality = got
        values[block.unknowns[0]] = x[0]
        out.append((block, make_report(block, a, b, x, quality)))
    return start + len(out), out, start + len(out) + 1


def _read_as_arrays(eqs, blocks, order, start: int, values):
    """`_read_one_by_one` with the rows read per shape as arrays (`block_rows.ones`: the
    same coefficients, the run ending at the same block), or None (one by one then)."""
    from . import block_rows

    taken, names = [], []
    for block, name in _candidates(blocks, order, start, values):
        taken.append(block)
        names.append(name)
    if len(taken) < MIN_RUN:
        return None
    got = block_rows.ones(eqs, [b.equations[0] for b in taken], names, values)
    if got is None:
        return None
    As, Bs, stop = got
    return taken[:stop], As, Bs, start + stop


def _read_one_by_one(eqs, blocks, order, start: int, values):
    """(blocks, a, b, where the run stopped): each block's row read by rowcode.affine
    until one the run cannot take."""
    affine = rowcode.affine
    isfinite = math.isfinite
    taken, As, Bs = [], [], []
    for block, name in _candidates(blocks, order, start, values):
        try:
            coef, const = affine(eqs[block.equations[0]].residual, {name: 0}, values)
        except (NonLinear, KeyError, ValueError, ZeroDivisionError, OverflowError):
            break  # also a value the run has not set yet: after the run, one by one
        a = coef.get(name, 0.0)
        b = -const
        if type(a) is not float or type(b) is not float or a == 0.0 or \
                not (isfinite(a) and isfinite(b)):
            break
        taken.append(block)
        As.append(a)
        Bs.append(b)
    return taken, As, Bs, start + len(taken)


def _candidates(blocks, order, start: int, values):
    """(block, its unknown) from order[start] while the run may take them: one unknown
    in one equation, not solved yet, none twice."""
    pending: set = set()
    for k in range(start, len(order)):
        block = blocks[order[k]]
        if len(block.unknowns) != 1 or len(block.equations) != 1:
            return
        name = block.unknowns[0]
        if name in values or name in pending:
            return
        pending.add(name)
        yield block, name


def _pow2(np, x):
    """`linalg._pow2` elementwise."""
    out = np.ldexp(1.0, np.frexp(x)[1] - 1)
    return np.where((x == 0.0) | ~np.isfinite(x), 1.0, out)


def solve_ones(np, As, Bs) -> list:
    """`linalg.solve_one(a, b)` for each pair: [(x, Quality), or None where it raises
    SingularError], the same floats (its steps on arrays; `fsum` per element)."""
    from .two_product import two_product

    a = np.array(As, dtype=float)
    b = np.array(Bs, dtype=float)
    with np.errstate(all="ignore"):
        r = _pow2(np, np.abs(a))
        c = _pow2(np, np.abs(a) / r)
        A = a / r / c
        bs = b / r
        norm1 = np.abs(A)
        y = bs / A
        cond = norm1 * np.abs(1.0 / A)
        ok = (A != 0.0) & np.isfinite(cond) & ~(cond > SINGULAR_COND)
        t = np.abs(A * y)
        y = np.where(t > 1e-15 * (np.abs(bs) + t), y, 0.0)
        p, e = two_product(A, y)
        fsum = math.fsum
        num = np.array([abs(fsum([u, -v, -w])) for u, v, w in
                        zip(bs.tolist(), p.tolist(), e.tolist())], dtype=float)
        denom = np.abs(A) * np.abs(y) + np.abs(bs)
        back = np.where(denom > 0, num / np.where(denom > 0, denom, 1.0), num)
        normwise = cond * np.maximum(back, EPS)
        ay = np.abs(y)
        comp = np.where(y != 0.0, normwise * ay / np.where(y != 0.0, ay, 1.0), normwise)
        x = y / c
    return [([xv], Quality("python", "float", cv, bv, kv, 0, [kv])) if good else None
            for good, xv, cv, bv, kv in zip(ok.tolist(), x.tolist(), cond.tolist(),
                                            back.tolist(), comp.tolist())]
