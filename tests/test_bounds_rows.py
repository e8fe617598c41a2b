"""A large block's rows read per shape as arrays (bounds_rows) against `bounds._row_max`
row by row: the same floats, bit for bit; and the whole bounds with and without it."""
from __future__ import annotations

import math
import random
from pathlib import Path

import pytest

import momentum_cli.linalg as L
from momentum_cli import bounds, bounds_rows, rowcode
from momentum_cli.bench import chain_text
from momentum_cli.expr import Add, Const, Mul, Var

from helpers import example_both_ways, solve_keeping_system

np = pytest.importorskip("numpy")
pytest.importorskip("scipy")

EXAMPLES = sorted((Path(__file__).resolve().parent.parent / "examples").glob("*.mom"))


def _bits(d: dict) -> list:
    return [(k, repr(v)) for k, v in d.items()]


def _chain(monkeypatch, n: int, **kw):
    monkeypatch.setattr(L, "BIG", 1000)
    monkeypatch.setattr(bounds, "COLUMNS_FROM", 1000)
    return solve_keeping_system(monkeypatch, chain_text(n, **kw), "chain.mom")


def _by_rows(eqs, equations, col, values, size, err):
    """`propagate`'s loop with `_row_max` (the reference), as arrays of the same kind."""
    rmax, cols, scale, delta = [], [[] for _ in col], [], []
    for i, k in enumerate(equations):
        d = bounds._row_max(eqs[k].residual, values, col, rmax, cols, i, size.get,
                            err.get, scale)
        delta.append(d + bounds.ROUNDOFF * scale[-1])
    entries = sorted((cj[t], j, cj[t + 1]) for j, cj in enumerate(cols)
                     for t in range(0, len(cj), 2))
    return rmax, scale, delta, entries


def _compare(eqs, equations, col, values, size, err):
    got = bounds_rows.read(eqs, equations, col, values, size, err, bounds.ROUNDOFF)
    if got is None:
        return None
    rmax, scale, delta, rows, cols, ents = got
    want = _by_rows(eqs, equations, col, values, size, err)
    assert [repr(v) for v in rmax.tolist()] == [repr(v) for v in want[0]]
    assert [repr(v) for v in scale.tolist()] == [repr(v) for v in want[1]]
    assert [repr(v) for v in delta.tolist()] == [repr(v) for v in want[2]]
    mine = sorted(zip(rows.tolist(), cols.tolist(), ents.tolist()))
    assert [(i, j, repr(a)) for i, j, a in mine] == [(i, j, repr(a)) for i, j, a in want[3]]
    return True


def _big_block(sol):
    return max(sol.blocks, key=lambda r: len(r.unknowns))


@pytest.mark.parametrize("n, kw", [(600, {}), (700, {"decades": 9.0}), (550, {"e": 0.37})])
def test_chains_bound_the_same_with_and_without_rows_as_arrays(monkeypatch, n, kw):
    sol, system = _chain(monkeypatch, n, **kw)
    values = dict(sol.values)
    out = []
    for on in (True, False):
        monkeypatch.setattr(bounds_rows, "ENABLED", on)
        with rowcode.remembered():
            size, err = bounds.propagate(system, sol.blocks, values, False)
        out.append((_bits(size), _bits(err)))
    assert out[0] == out[1]
    monkeypatch.setattr(bounds_rows, "ENABLED", True)
    rep = _big_block(sol)
    col = {nm: j for j, nm in enumerate(rep.unknowns)}
    with rowcode.remembered():
        assert _compare(system.equations, rep.equations, col, values, sol.size,
                        sol.errors)


def test_random_values_read_as_the_rows_do(monkeypatch):
    """The chain's rows at random values, sizes and bounds over many decades and signs,
    some earlier unknowns without a size: every row's numbers as `_row_max` makes them."""
    sol, system = _chain(monkeypatch, 300)
    rep = _big_block(sol)
    col = {nm: j for j, nm in enumerate(rep.unknowns)}
    rng = random.Random(5)
    for _ in range(5):
        values = {k: rng.choice([-1, 1]) * 10 ** rng.uniform(-100, 100) * rng.choice([1, 1, 0])
                  for k in sol.values}
        size = {k: 10 ** rng.uniform(-50, 50) for k in sol.values if rng.random() < 0.8}
        err = {k: rng.choice([0.0, 10 ** rng.uniform(-50, 50)]) for k in size}
        with rowcode.remembered():
            assert _compare(system.equations, rep.equations, col, values, size, err)


def test_sums_and_products_of_many_shapes():
    """Random rows (sums of products of numbers, unknowns and sums, repeated unknowns,
    zero numbers), enough of each shape to be compiled: read as `_row_max` reads them."""
    rng = random.Random(11)
    names = [f"u{j}" for j in range(40)] + [f"k{j}" for j in range(40)]
    col = {nm: j for j, nm in enumerate(names[:40])}

    def leaf(nm):
        return Var(nm) if rng.random() < 0.6 else Const(rng.choice([0.0, 2.5, -1e-3, 7.0]))

    def tree(pick):
        kinds = rng.random()
        if kinds < 0.4:
            return Add(tuple(Mul((Const(rng.uniform(-9, 9)), leaf(pick()))) for _ in range(3)))
        if kinds < 0.7:
            return Add((Var(pick()), Mul((Const(0.5), Add((Var(pick()), Var(pick()))))),
                        Const(1.25)))
        return Add((Mul((Var(pick()), Const(-2.0))), Var(pick()), Var(pick())))

    rows = []
    for _ in range(600):
        rows.append(tree(lambda: rng.choice(names)))

    class Eq:
        def __init__(self, r):
            self.residual = r

    eqs = [Eq(r) for r in rows]
    values = {nm: rng.uniform(-3, 3) for nm in names}
    size = {nm: rng.uniform(0, 5) for nm in names[40:]}
    err = {nm: rng.uniform(0, 1e-12) for nm in names[40:]}
    with rowcode.remembered():
        for _ in range(2):  # once to meet the shapes often enough, once compiled
            for e in eqs:
                rowcode.derivatives_and_size(e.residual, values)
        assert _compare(eqs, list(range(len(eqs))), col, values, size, err)


@pytest.mark.parametrize("bad", [math.inf, math.nan])
def test_anything_not_finite_declines(monkeypatch, bad):
    sol, system = _chain(monkeypatch, 300)
    rep = _big_block(sol)
    col = {nm: j for j, nm in enumerate(rep.unknowns)}
    values = dict(sol.values)
    values[rep.unknowns[3]] = bad
    with rowcode.remembered():
        assert bounds_rows.read(system.equations, rep.equations, col, values, sol.size,
                                sol.errors, bounds.ROUNDOFF) is None
        del values[rep.unknowns[3]]
        assert bounds_rows.read(system.equations, rep.equations, col, values, sol.size,
                                sol.errors, bounds.ROUNDOFF) is None


@pytest.mark.parametrize("path", EXAMPLES, ids=lambda p: p.stem)
def test_examples_bound_the_same_with_and_without_rows_as_arrays(monkeypatch, path):
    """Every block past DENSE (or not square) of every example through the arrays, with
    and without."""
    monkeypatch.setattr(bounds, "COLUMNS_FROM", 1)
    monkeypatch.setattr(rowcode, "PLAIN_SMALL", False)
    monkeypatch.setattr(rowcode, "COMPILE_AFTER", 0)
    got = example_both_ways(monkeypatch, bounds_rows, path, lambda sol: (
        sol.answers, _bits(sol.size or {}), _bits(sol.errors or {})))
    assert got[0] == got[1]


@pytest.mark.parametrize("n, kw", [(300, {}), (450, {"decades": 6.0, "e": 0.6})])
def test_runs_of_one_unknown_bound_as_each_alone(monkeypatch, n, kw):
    """A chain's run of 1x1 blocks (each ball's y velocity) bounded as arrays against
    `_one` block by block; also with values that make some rows decline."""
    sol, system = _chain(monkeypatch, n, **kw)
    taken = []
    ones = bounds._ones_as_arrays

    def spy(*a, **k):
        got = ones(*a, **k)
        taken.append(got[1])
        return got

    monkeypatch.setattr(bounds, "_ones_as_arrays", spy)
    for values in (dict(sol.values), {k: (v if i % 97 else math.inf)
                                      for i, (k, v) in enumerate(sol.values.items())}):
        out = _bounds_with_and_without_runs(monkeypatch, system, sol.blocks, values)
        assert out[0] == out[1]
    assert True in taken


def _bounds_with_and_without_runs(monkeypatch, system, blocks, values) -> list:
    """The bounds' bits with runs of 1x1 blocks taken as arrays, then never."""
    out = []
    for run in (64, 10**9):
        monkeypatch.setattr(bounds, "ONES_RUN", run)
        with rowcode.remembered():
            size, err = bounds.propagate(system, blocks, values, False)
        out.append((_bits(size), _bits(err)))
    return out


def test_cradle_bounds_the_same_with_and_without_runs_of_ones(monkeypatch):
    from test_hard import cradle_text

    sol, system = solve_keeping_system(monkeypatch, cradle_text(300, "sequence"),
                                       "cradle.mom")
    out = _bounds_with_and_without_runs(monkeypatch, system, sol.blocks, dict(sol.values))
    assert out[0] == out[1]
