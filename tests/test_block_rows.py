"""A large block's rows read per shape as arrays (block_rows) against `rowcode.affine`
row by row, as `solve._solve_block` reads them: the same dicts (keys in the same order,
the same floats bit for bit, NaN and inf included) and right-hand sides; the whole solve
with and without."""
from __future__ import annotations

import math
import random
from pathlib import Path

import pytest

import momentum_cli.linalg as L
from momentum_cli import block_rows, bounds, rowcode
from momentum_cli.bench import chain_text
from momentum_cli.expr import Add, Const, Mul, NonLinear, Var

from helpers import example_both_ways, solve_keeping_system

np = pytest.importorskip("numpy")

EXAMPLES = sorted((Path(__file__).resolve().parent.parent / "examples").glob("*.mom"))


def _bits(x) -> str:
    return repr(x) if not (isinstance(x, float) and x == 0.0) else repr(math.copysign(1, x))


def _one_by_one(eqs, equations, names, values):
    """`_solve_block`'s loop (the reference)."""
    bset = set(names)
    col = {n: j for j, n in enumerate(names)}
    rows, rhs = [], []
    for k in equations:
        coef, const = rowcode.affine(eqs[k].residual, bset, values)
        rows.append({col[n]: v for n, v in coef.items() if v != 0.0})
        rhs.append(-const)
    return rows, rhs


def _same(got, want):
    rows, rhs = got
    assert [[(j, _bits(v)) for j, v in r.items()] for r in rows] == \
        [[(j, _bits(v)) for j, v in r.items()] for r in want[0]]
    assert [_bits(v) for v in rhs] == [_bits(v) for v in want[1]]


def _compare(eqs, equations, names, values):
    col = {n: j for j, n in enumerate(names)}
    block_rows.forget()
    got = block_rows.rows(eqs, equations, col, values)
    block_rows.forget()
    if got is None:
        return None
    _same(got, _one_by_one(eqs, equations, names, values))
    return True


def _chain(monkeypatch, n: int, **kw):
    monkeypatch.setattr(L, "BIG", 1000)
    monkeypatch.setattr(bounds, "COLUMNS_FROM", 1000)
    return solve_keeping_system(monkeypatch, chain_text(n, **kw), "chain.mom")


@pytest.mark.parametrize("n, kw", [(600, {}), (700, {"decades": 9.0, "e": 0.37})])
def test_chain_rows_read_as_one_by_one(monkeypatch, n, kw):
    sol, system = _chain(monkeypatch, n, **kw)
    rep = max(sol.blocks, key=lambda r: len(r.unknowns))
    values = {k: v for k, v in sol.values.items() if k not in set(rep.unknowns)}
    with rowcode.remembered():
        assert _compare(system.equations, rep.equations, rep.unknowns, values)


class _Eq:
    def __init__(self, r):
        self.residual = r


def test_random_rows_of_many_shapes():
    """Sums of products with numbers, the block's unknowns and others, repeated unknowns,
    zero numbers, some rows of a shape whose unknowns are all the block's, some of one
    with none: read as the rows are read one by one."""
    rng = random.Random(4)
    inside = [f"u{j}" for j in range(300)]
    outside = [f"k{j}" for j in range(300)]

    def leaf():
        return Var(rng.choice(inside + outside)) if rng.random() < 0.7 else \
            Const(rng.choice([0.0, 2.5, -1e-3, 7.0]))

    def row():
        k = rng.random()
        if k < 0.4:
            return Add(tuple(Mul((Const(rng.uniform(-9, 9)), leaf())) for _ in range(3)))
        if k < 0.7:
            a = rng.choice(inside)
            return Add((Var(a), Mul((Const(0.5), Add((Var(rng.choice(outside)), Var(a))))),
                        Const(1.25)))
        return Add((Mul((Var(rng.choice(inside)), Const(-2.0))), Var(rng.choice(outside))))

    eqs = [_Eq(row()) for _ in range(900)]
    values = {nm: rng.uniform(-3, 3) for nm in outside}
    with rowcode.remembered():
        for _ in range(2):  # met often enough to be compiled, as in a large solve
            for e in eqs:
                try:
                    rowcode.affine(e.residual, set(inside), values)
                except NonLinear:
                    pass
        linear = [k for k, e in enumerate(eqs) if _linear(e, set(inside), values)]
        assert _compare(eqs, linear, inside, values)
        for bad in (math.inf, -math.inf, math.nan):  # not finite: the same NaN and inf
            spoilt = dict(values)
            for k in rng.sample(outside, 20):
                spoilt[k] = bad
            assert _compare(eqs, linear, inside, spoilt)
        missing = dict(values)
        for k in rng.sample(outside, 3):
            del missing[k]
        assert _compare(eqs, linear, inside, missing) is None
        # a row not linear in the block's unknowns: declined
        eqs.append(_Eq(Mul((Var(inside[0]), Var(inside[1])))))
        assert _compare(eqs, linear + [len(eqs) - 1], inside, values) is None


def _linear(e, bset, values) -> bool:
    try:
        rowcode.affine(e.residual, bset, values)
    except NonLinear:
        return False
    return True


def test_whole_chain_solve_the_same_with_and_without(monkeypatch):
    got = []
    for on in (True, False):
        monkeypatch.setattr(block_rows, "ENABLED", on)
        sol, _ = _chain(monkeypatch, 800)
        got.append((repr(sol.answers), repr(sol.values), repr(sol.errors),
                    [(r.cond, r.quality) for r in sol.blocks]))
    assert got[0] == got[1]


@pytest.mark.parametrize("path", EXAMPLES, ids=lambda p: p.stem)
def test_examples_solve_the_same_with_and_without(monkeypatch, path):
    """Every square block of every example read as arrays (BIG 1), with and without."""
    monkeypatch.setattr(L, "BIG", 1)
    monkeypatch.setattr(rowcode, "PLAIN_SMALL", False)
    monkeypatch.setattr(rowcode, "COMPILE_AFTER", 0)
    got = example_both_ways(monkeypatch, block_rows, path, lambda sol: (
        repr(sol.answers), repr(sol.values), repr(sol.errors),
        repr([c.__dict__ if hasattr(c, "__dict__") else c for c in sol.checks])))
    assert got[0] == got[1]


class _Block:
    def __init__(self, unknowns, equations):
        self.unknowns, self.equations = unknowns, equations


@pytest.mark.parametrize("spoil", ["none", "missing", "later", "zero", "inf", "nonlinear",
                                   "two"])
@pytest.mark.parametrize("seed", range(2))
def test_runs_of_ones_read_as_one_by_one(seed, spoil):
    """A run of one-unknown blocks (solve_ones) read as arrays against row by row: the
    same blocks taken, coefficients and constants bit for bit, the run ending at the
    same block (a value not set yet, a row using a later block's unknown, a zero or
    non-finite coefficient, a row not linear, a block of two unknowns)."""
    from momentum_cli import solve_ones

    rng = random.Random(seed)
    n = 400
    own = [f"y{j}" for j in range(n)]
    given = [f"g{j}" for j in range(50)]
    values = {nm: rng.uniform(-2, 2) for nm in given}

    def row(j):
        k = rng.random()
        g = Var(rng.choice(given))
        if k < 0.5:
            return Add((Mul((Const(rng.uniform(1, 9)), Var(own[j]))), Mul((Const(-1.0), g))))
        if k < 0.8:
            return Add((Var(own[j]), Mul((Const(0.5), Add((g, Var(own[j]))))), Const(1.25)))
        return Add((Mul((Var(own[j]), Const(-2.0))), g, Const(3.0)))

    rows = [row(j) for j in range(n)]
    at = rng.randrange(100, 300)
    if spoil == "missing":
        rows[at] = Add((Var(own[at]), Var("nowhere")))
    elif spoil == "later":
        rows[at] = Add((Var(own[at]), Var(own[at + 5])))
    elif spoil == "zero":
        rows[at] = Add((Mul((Var(own[at]), Var("zero"))), Const(1.0)))
        values["zero"] = 0.0
    elif spoil == "inf":
        values[given[1]] = math.inf
    elif spoil == "nonlinear":
        rows[at] = Add((Mul((Var(own[at]), Var(own[at]))), Const(-1.0)))
    eqs = [_Eq(r) for r in rows]
    blocks = [_Block([own[j]], [j]) for j in range(n)]
    if spoil == "two":
        blocks[at] = _Block([own[at], "other"], [at])
    order = list(range(n))
    with rowcode.remembered():
        for e in eqs:  # met often enough to be compiled, as in a large solve
            rowcode.shape_of(e.residual)
        start = rng.randrange(0, 20)
        want = solve_ones._read_one_by_one(eqs, blocks, order, start, values)
        got = solve_ones._read_as_arrays(eqs, blocks, order, start, values)
    if got is None:  # a run too short to read as arrays
        assert len(want[0]) < solve_ones.MIN_RUN or want[3] - start < solve_ones.MIN_RUN
        return
    assert [b.unknowns for b in got[0]] == [b.unknowns for b in want[0]]
    assert [_bits(v) for v in got[1]] == [_bits(v) for v in want[1]]
    assert [_bits(v) for v in got[2]] == [_bits(v) for v in want[2]]
    assert got[3] == want[3]
