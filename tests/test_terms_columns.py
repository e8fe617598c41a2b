"""A large sum's terms walked per shape as arrays (terms_columns) against the compiled
walk term by term (`rowcode.value_grad_size`): the same value, size and derivatives (in
the same dict order), bit for bit; and the chains' answers with and without it."""
from __future__ import annotations

import math
import random

import pytest

from momentum_cli import bounds, rowcode, terms_columns
from momentum_cli.bench import chain_text
from momentum_cli.expr import Add, Const, Mul, Var

from helpers import solve_keeping_system

np = pytest.importorskip("numpy")


def _vgs(e, values):
    with rowcode.remembered():
        got = rowcode.value_grad_size(e, values, bounds._grad_size, terms_columns.walk_sum)
    if got is None:
        return None
    v, out, z = got
    return repr(v), repr(z), [(k, repr(s)) for k, s in out.items()]


def _both(monkeypatch, e, values):
    taken = []
    walk = terms_columns.walk_sum

    def spy(*a, **k):
        got = walk(*a, **k)
        taken.append(got is not None)
        return got

    monkeypatch.setattr(terms_columns, "walk_sum", spy)
    monkeypatch.setattr(terms_columns, "ENABLED", True)
    on = _vgs(e, values)
    monkeypatch.setattr(terms_columns, "ENABLED", False)
    off = _vgs(e, values)
    return on, off, taken


def _random_sum(rng, n_terms: int, names: list[str]):
    """Kinetic-energy-like terms of a few shapes, interleaved, some unknowns repeated
    across terms, zero numbers (a zero product), and sums of terms without a shape of
    their own (a number times a long sum) in between."""
    def term():
        k = rng.random()
        a, b = rng.choice(names), rng.choice(names)
        if k < 0.4:
            return Mul((Const(0.5), Const(rng.uniform(0.1, 9)),
                        Add((Mul((Var(a), Var(a))), Mul((Var(b), Var(b)))))))
        if k < 0.7:
            return Mul((Const(0.5), Const(rng.uniform(0.1, 9)), Var(a), Var(a)))
        if k < 0.85:
            return Mul((Const(rng.choice([0.0, 2.0])), Var(a), Add((Const(1.5), Var(b)))))
        return Mul((Const(-1.0), Var(a)))

    terms = [term() for _ in range(n_terms)]
    for at in sorted(rng.sample(range(n_terms), 3)):
        terms.insert(at, Mul((Const(-1.0), Add(tuple(term() for _ in range(300))))))
    return Add(tuple(terms))


@pytest.mark.parametrize("seed", range(6))
def test_random_sums_walk_as_term_by_term(monkeypatch, seed):
    rng = random.Random(seed)
    names = [f"v{j}" for j in range(rng.choice([50, 2000]))]
    e = _random_sum(rng, rng.choice([300, 1200]), names)
    values = {nm: rng.choice([-1, 1]) * 10 ** rng.uniform(-5, 5) for nm in names}
    on, off, taken = _both(monkeypatch, e, values)
    assert on == off and on is not None
    assert True in taken


def test_a_term_not_finite_or_missing_declines(monkeypatch):
    rng = random.Random(3)
    names = [f"v{j}" for j in range(500)]
    e = _random_sum(rng, 600, names)
    values = {nm: rng.uniform(-2, 2) for nm in names}
    values["v7"] = math.inf
    on, off, _ = _both(monkeypatch, e, values)
    assert on == off
    del values["v7"]
    with rowcode.remembered():
        assert rowcode.value_grad_size(e, values, bounds._grad_size,
                                       terms_columns.walk_sum) is None


@pytest.mark.parametrize("n, kw", [(400, {}), (900, {"decades": 9.0, "e": 0.3})])
def test_chains_answer_the_same_with_and_without_arrays(monkeypatch, n, kw):
    got = []
    for on in (True, False):
        monkeypatch.setattr(terms_columns, "ENABLED", on)
        sol, _ = solve_keeping_system(monkeypatch, chain_text(n, **kw), "chain.mom")
        got.append((repr(sol.answers), repr(sol.answer_errors)))
    assert got[0] == got[1]


def test_terms_of_several_shapes_each_with_its_own_unknowns(monkeypatch):
    """Interleaved shapes, every unknown in one term only (the derivatives added in one
    update), once at the top and once inside a number times a sum."""
    rng = random.Random(9)
    terms = []
    for j in range(900):
        a, b = f"a{j}", f"b{j}"
        k = j % 3 if j % 7 else 1
        if k == 0:
            terms.append(Mul((Const(0.5), Const(rng.uniform(1, 9)), Var(a), Var(a))))
        elif k == 1:
            terms.append(Mul((Const(0.5), Const(rng.uniform(1, 9)),
                              Add((Mul((Var(a), Var(a))), Mul((Var(b), Var(b))))))))
        else:
            terms.append(Mul((Const(-2.0), Var(a), Add((Const(1.5), Var(b))))))
    values = {f"{p}{j}": rng.uniform(-3, 3) for j in range(900) for p in "ab"}
    inner = Add(tuple(terms[:450]))
    e = Add(tuple(terms[450:]) + (Mul((Const(-1.0), inner)),))
    on, off, taken = _both(monkeypatch, e, values)
    assert on == off and on is not None
    assert taken.count(True) == 2
