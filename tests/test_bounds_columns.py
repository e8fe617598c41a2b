"""A large sparse block's sizes and error bounds as arrays (bounds_columns) against
`bounds.propagate`'s loops over the columns: the same floats, bit for bit, in the same
order; and banded._coo's arrays against the loop it replaced."""
from __future__ import annotations

import math
import random
from array import array

import pytest

import momentum_cli.linalg as L
from momentum_cli import banded, bounds, bounds_columns, rowcode
from momentum_cli.bench import chain_text

from helpers import solve_keeping_system

np = pytest.importorskip("numpy")
pytest.importorskip("scipy")


def _bits(d: dict) -> list:
    """A dict of floats as its keys in order and each value's bits (-0.0, NaN apart)."""
    return [(k, math.copysign(1.0, v) if v == 0.0 else v, repr(v)) for k, v in d.items()]


def _chain_solution(monkeypatch, n: int, **kw):
    """A chain's solution and its system, kept from the solve (the banded path from
    1,000 unknowns, so a few hundred balls take it)."""
    monkeypatch.setattr(L, "BIG", 1000)
    monkeypatch.setattr(bounds, "COLUMNS_FROM", 1000)
    return solve_keeping_system(monkeypatch, chain_text(n, **kw), "chain.mom")


def _both(monkeypatch, system, reports, values, exact=False):
    out = []
    for on in (True, False):
        monkeypatch.setattr(bounds_columns, "ENABLED", on)
        with rowcode.remembered():
            size, err = bounds.propagate(system, reports, values, exact)
        out.append((_bits(size), _bits(err)))
    return out


@pytest.mark.parametrize("n, kw", [(600, {}), (700, {"decades": 9.0}),
                                   (550, {"e": 0.37}), (800, {"decades": 3.0, "e": 0.9})])
def test_chains_bound_the_same_with_and_without_arrays(monkeypatch, n, kw):
    sol, system = _chain_solution(monkeypatch, n, **kw)
    values = dict(sol.values)
    assert max(len(r.unknowns) for r in sol.blocks) >= 1000  # the arrays' path is taken
    with_arrays, loops = _both(monkeypatch, system, sol.blocks, values)
    assert with_arrays == loops
    # exact mode's step (its rows add no rounding of their own: other sums, ints)
    with_arrays, loops = _both(monkeypatch, system, sol.blocks, values, exact=True)
    assert with_arrays == loops


def test_the_whole_solve_is_the_same_with_and_without_arrays(monkeypatch):
    got = []
    for on in (True, False):
        monkeypatch.setattr(bounds_columns, "ENABLED", on)
        sol, _ = _chain_solution(monkeypatch, 600)
        got.append((sol.answers, _bits(sol.size), _bits(sol.errors), sol.answer_errors))
    assert got[0] == got[1]


def _loops(cols, rmax, scale, delta, xs, comps, cond, solved):
    """`propagate`'s loops over the columns of a sparse block (the reference)."""
    pairs = bounds._flat_pairs
    unit = bounds._units(rmax, cols, pairs)
    big = max([x * u for x, u in zip(xs, unit)]) if xs else 0.0
    sizes, errs = [], []
    for j in range(len(cols)):
        x = xs[j]
        cands = [scale[i] / a for i, a in pairs(cols[j])]
        uj = unit[j]
        sizes.append(max(x, min(cands) if cands else x, big / uj if uj > 0 else 0.0))
    for j in range(len(cols)):
        e = cond * max([delta[i] / a for i, a in pairs(cols[j])], default=0.0)
        solver = comps[j] * xs[j] if solved else 0.0
        errs.append(e + solver if math.isfinite(e) else math.inf)
    return sizes, errs


def _random_block(rng, n, rows):
    """Flat columns (row, |entry|, ...) with empty columns, empty rows (largest entry
    0.0), int zeros among the data errors, entries over many decades."""
    cols = [[] for _ in range(n)]
    rmax = [0.0] * rows
    for i in range(rows):
        if rng.random() < 0.1:
            continue  # a row without entries in the block
        for j in rng.sample(range(n), rng.randint(1, min(3, n))):
            a = abs(rng.uniform(-1, 1)) * 10 ** rng.uniform(-150, 150)
            cols[j] += [i, a]
            rmax[i] = max(rmax[i], a)
    for j in rng.sample(range(n), n // 10):
        cols[j] = []  # an unknown in no row of the block
    scale = [10 ** rng.uniform(-20, 20) * rng.choice([0.0, 1.0, 1.0]) for _ in range(rows)]
    delta = [rng.choice([0, 0.0, 10 ** rng.uniform(-300, 10)]) for _ in range(rows)]
    xs = [abs(rng.gauss(0, 1)) * rng.choice([0.0, 1.0, 1e200]) for _ in range(n)]
    comps = [rng.choice([0.0, 2.0**-52, 1e-10]) for _ in range(n)]
    return cols, rmax, scale, delta, xs, comps


@pytest.mark.parametrize("seed", range(20))
def test_random_columns_are_the_loops(seed):
    rng = random.Random(seed)
    n = rng.randint(1, 60)
    data = _random_block(rng, n, rng.randint(1, 80))
    for cond in (1.0, 3.7e12, 1e300):
        for solved in (True, False):
            got = bounds_columns.sizes_and_errors(*data, cond, solved)
            want = _loops(*data, cond, solved)
            assert got is not None
            assert [repr(v) for v in got[0]] == [repr(v) for v in want[0]]
            assert [repr(v) for v in got[1]] == [repr(v) for v in want[1]]


@pytest.mark.parametrize("bad", [math.inf, -math.inf, math.nan])
def test_anything_not_finite_goes_to_the_loops(bad):
    rng = random.Random(7)
    cols, rmax, scale, delta, xs, comps = _random_block(rng, 20, 30)
    for which in (rmax, scale, delta, xs, comps):
        was = which[0]
        which[0] = bad
        assert bounds_columns.sizes_and_errors(cols, rmax, scale, delta, xs, comps,
                                               1.0, True) is None
        which[0] = was
    j = next(j for j, cj in enumerate(cols) if cj)
    cols[j][1] = bad
    assert bounds_columns.sizes_and_errors(cols, rmax, scale, delta, xs, comps,
                                           1.0, True) is None
    cols[j][1] = 1.0
    assert bounds_columns.sizes_and_errors(cols, rmax, scale, delta, xs, comps,
                                           bad, True) is None


def _coo_loop(A, pr, pc):
    """banded._coo as a loop over the entries (the code it replaced)."""
    ii, jj, vv, kk = array("q"), array("q"), array("d"), array("q")
    for i, row in enumerate(A):
        p = pr[i]
        for k, (j, v) in enumerate(row.items()):
            ii.append(p)
            jj.append(pc[j])
            vv.append(v)
            kk.append(k)
    return (np.array(ii, dtype=np.intp), np.array(jj, dtype=np.intp),
            np.array(vv, dtype=float), np.array(kk, dtype=np.intp))


@pytest.mark.parametrize("seed", range(10))
def test_coo_arrays_are_the_loops(seed):
    rng = random.Random(seed)
    n = rng.randint(1, 200)
    A = []
    for _ in range(n):
        cols = rng.sample(range(n), rng.randint(1, min(5, n)))
        A.append({j: rng.choice([rng.gauss(0, 1), -0.0, 1e-310, 7]) for j in cols})
    pr = rng.sample(range(n), n)
    pc = rng.sample(range(n), n)
    got, want = banded._coo(A, pr, pc), _coo_loop(A, pr, pc)
    for g, w in zip(got, want):
        assert g.dtype == w.dtype and g.shape == w.shape
        assert g.tobytes() == w.tobytes()
