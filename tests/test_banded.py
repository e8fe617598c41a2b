"""Large linear blocks by LAPACK's banded LU (banded.py) against the Python elimination,
exact rationals and the chain's closed form.

A simultaneous impact of a chain of touching balls, ball 1 at u, the rest at rest, each
contact with Newton's law: every separation after is -e times the approach before, so
v_k = v_1 + e u for k >= 2, and momentum gives v_1 = (m_1 - e (M - m_1)) u / M, with M
the total mass. Evaluated in rationals from the very floats of the masses.
"""
from __future__ import annotations

import math
import random
from fractions import Fraction as F

import pytest

import momentum_cli.linalg as L
from momentum_cli import banded
from momentum_cli.bench import chain_text
from momentum_cli.diagnostics import ProblemError
from momentum_cli.scene import build
from momentum_cli.solve import solve_scene
from momentum_cli.source import Source
from momentum_cli.syntax import parse

pytest.importorskip("scipy")


@pytest.fixture(autouse=True)
def _banded_from_1000(monkeypatch):
    """The banded path from 1,000 unknowns here (linalg.BIG is higher, where it pays for
    its imports), so that chains of a few hundred balls keep these tests fast."""
    monkeypatch.setattr(L, "BIG", 1000)


def _solve(text: str, precision: str = "float"):
    return solve_scene(build(parse(Source("chain.mom", text))), precision=precision)


def _python(monkeypatch):
    """Every block by the Python elimination (the reference path)."""
    monkeypatch.setattr(L, "BIG", 10**9)


def _closed_form(n: int, decades: float, e: float) -> dict[str, F]:
    masses = [F(10 ** (decades * math.sin(k))) for k in range(1, n + 1)]
    M = sum(masses)
    v1 = (masses[0] - F(e) * (M - masses[0])) / M
    return {"b1.vx@2": v1, f"b{n}.vx@2": v1 + F(e)}


def _errors(sol, want: dict[str, F]) -> dict[str, tuple[F, float]]:
    """Each answer's exact error and the bound the report prints for it."""
    out = {}
    for name, _shown, _unit, si in sol.answers:
        if name in want:
            out[name] = (abs(F(si) - want[name]), sol.answer_errors[name])
    return out


def _methods(sol) -> set[str]:
    return {b.quality.method for b in sol.blocks if b.quality is not None and
            len(b.unknowns) > 100}


@pytest.mark.parametrize("n,decades", [(600, 6.0), (700, 3.0)])
def test_big_chain_is_within_its_bound_of_the_closed_form(n, decades, monkeypatch):
    text = chain_text(n, decades)
    want = _closed_form(n, decades, 0.5)
    new = _solve(text)
    assert _methods(new) == {"banded-lu"}
    _python(monkeypatch)
    old = _solve(text)
    assert _methods(old) == {"sparse-lu"}
    got_new, got_old = _errors(new, want), _errors(old, want)
    assert set(got_new) == set(want)
    for name, (err, bound) in got_new.items():
        assert err <= F(bound), (name, float(err), bound)
        # as close as the Python elimination (to a few units in the last place)
        old_err = got_old[name][0]
        assert err <= 8 * old_err + F(4 * 2.0**-53) * abs(want[name]), \
            (name, float(err), float(old_err))
        assert bound <= 2 * got_old[name][1]


def test_every_value_within_the_components_bound_of_the_python_path(monkeypatch):
    text = chain_text(550, 6.0)  # 1099 unknowns
    new = _solve(text)
    _python(monkeypatch)
    old = _solve(text)
    big = [b for b in old.blocks if len(b.unknowns) > 100]
    assert len(big) == 1
    nb = [b for b in new.blocks if len(b.unknowns) > 100][0]
    assert nb.unknowns == big[0].unknowns and nb.equations == big[0].equations
    q_old, q_new = big[0].quality, nb.quality
    assert math.isclose(q_new.cond, q_old.cond, rel_tol=1e-6)
    for j, name in enumerate(nb.unknowns):
        x_old, x_new = old.values[name], new.values[name]
        tol = (q_old.components[j] + q_new.components[j]) * abs(x_old)
        assert abs(x_new - x_old) <= tol, (name, x_old, x_new, tol)
    # the rest of the scene is untouched: the same floats in the small blocks
    small = {n for b in old.blocks if len(b.unknowns) <= 100 for n in b.unknowns}
    assert small and all(old.values[k] == new.values[k] for k in small)


def test_hard_chain_masses_over_24_decades_against_exact(monkeypatch):
    """The bench's hard chain (49 unknowns, masses 1e-12 .. 1e12 kg) through the banded
    path (threshold lowered): within the printed bounds of the exact answers, and as
    close as the Python elimination."""
    from momentum_cli.bench import hard_chain_text

    text = hard_chain_text()
    exact = {name: F(si) for name, _s, _u, si in _solve(text, "exact").answers}
    monkeypatch.setattr(L, "BIG", 20)
    new = _solve(text)
    assert any(b.quality is not None and b.quality.method == "banded-lu" for b in new.blocks)
    _python(monkeypatch)
    old = _solve(text)
    for name, (err, bound) in _errors(new, exact).items():
        assert err <= F(bound), (name, float(err), bound)
        old_err = _errors(old, exact)[name][0]
        assert err <= 8 * old_err + F(4 * 2.0**-53) * abs(exact[name])


def test_refine_keeps_its_guarantee_on_the_banded_path(monkeypatch):
    n = 600
    want = _closed_form(n, 6.0, 0.5)
    sol = _solve(chain_text(n), "refine")
    assert {b.quality.method for b in sol.blocks if len(b.unknowns) > 100} == {"banded-lu"}
    for name, (err, bound) in _errors(sol, want).items():
        assert err <= F(bound)
        assert err <= F(4 * 2.0**-53) * abs(want[name]) + F(1e-300), (name, float(err))


def test_duplicate_contact_in_a_big_block_is_resolved_alike(monkeypatch):
    """A contact declared twice (under another name): its dependent row is set aside and
    checked, and the rest solved, alike on both paths."""
    monkeypatch.setattr(L, "BIG", 20)  # 80 unknowns: the singular path is slow in rationals
    text = chain_text(40)
    line = "    contact b21 with b20 normal (1, 0): restitution 0.5\n"
    assert line in text
    text = text.replace(line, line + line.replace("contact b21", "contact extra: b21"), 1)
    seen = []
    real = banded.solve_float

    def spy(*a):
        got = real(*a)
        seen.append(got[1] if got is not None else None)
        return got

    monkeypatch.setattr(banded, "solve_float", spy)
    new = _solve(text)
    assert seen and all(c is not None for c in seen)  # the banded path solved
    _python(monkeypatch)
    old = _solve(text)
    assert [(c.name, c.status) for c in new.checks] == [(c.name, c.status) for c in old.checks]
    assert [b.equations for b in new.blocks] == [b.equations for b in old.blocks]
    for (name, _s, _u, x), (_n, _s2, _u2, y) in zip(new.answers, old.answers):
        assert abs(x - y) <= new.answer_errors[name] + old.answer_errors[name]


def test_ill_conditioned_big_block_is_refused_alike(monkeypatch):
    monkeypatch.setattr(L, "BIG", 20)
    text = chain_text(40, decades=14.0)  # masses over 28 decades: beyond float64
    with pytest.raises(ProblemError) as new:
        _solve(text)
    _python(monkeypatch)
    with pytest.raises(ProblemError) as old:
        _solve(text)
    a, b = new.value.diagnostics[0], old.value.diagnostics[0]
    assert a.code == b.code == "ill-conditioned"
    assert a.notes == b.notes


# ---- the module on its own ----------------------------------------------------------------
def _random_band(n: int, width: int, seed: int):
    """A diagonally strong banded matrix with its rows and columns shuffled."""
    rnd = random.Random(seed)
    pr = list(range(n))
    pc = list(range(n))
    rnd.shuffle(pr)
    rnd.shuffle(pc)
    rows = [dict() for _ in range(n)]
    for i in range(n):
        for j in range(max(0, i - width), min(n, i + width + 1)):
            if i == j or rnd.random() < 0.6:
                v = rnd.uniform(-1, 1) * 10 ** rnd.uniform(-2, 2)
                if i == j:
                    v = (3 + rnd.random()) * 10 ** rnd.uniform(-2, 2)
                rows[pr[i]][pc[j]] = v
    b = [rnd.uniform(-1, 1) for _ in range(n)]
    return rows, b


@pytest.mark.parametrize("seed", range(4))
def test_banded_solve_matches_exact_rationals(seed):
    n = 150
    rows, b = _random_band(n, 2, seed)
    got = banded.solve_float(rows, b, n, L.PATTERNS, L.EPS)
    assert got is not None
    x, cond, back, comps = got
    ref, q = L.solve_rows(rows, b, n)  # n < BIG: the Python elimination
    exact = L._exact(rows, b, n)
    # the same estimate from another factorisation: alike to its conditioning
    assert math.isclose(cond, q.cond, rel_tol=max(1e-9, 100 * cond * L.EPS))
    assert back <= 4 * L.EPS
    worst = worst_ref = 0.0
    for j in range(n):
        err = abs(F(x[j]) - exact[j])
        assert err <= F(comps[j]) * abs(F(x[j])) + F(1e-300)
        worst = max(worst, float(err / abs(exact[j])))
        worst_ref = max(worst_ref, float(abs(F(ref[j]) - exact[j]) / abs(exact[j])))
    # as accurate as the Python elimination, up to the luck of rounding
    assert worst <= 100 * worst_ref + 8 * L.EPS, (worst, worst_ref)
    # the snap, the backward error's scale and the components as the general path has them
    assert math.isclose(max(comps), q.bound, rel_tol=max(1e-6, 100 * cond * L.EPS))


def test_wide_or_ragged_blocks_go_the_python_way():
    n = 120
    rnd = random.Random(5)
    dense_ish = [{j: rnd.uniform(1, 2) for j in rnd.sample(range(n), 10)} for _ in range(n)]
    for i in range(n):
        dense_ish[i][i] = 50.0
    assert banded.solve_float(dense_ish, [1.0] * n, n, L.PATTERNS, L.EPS) is None
    empty_col = [{0: 1.0} for _ in range(n)]
    assert banded.solve_float(empty_col, [1.0] * n, n, L.PATTERNS, L.EPS) is None
    assert banded.solve_float(empty_col[:-1], [1.0] * (n - 1), n, L.PATTERNS, L.EPS) is None


def test_exactly_singular_band_reports_infinite_condition():
    n = 50
    rows = [{i: 1.0, i + 1: 1.0} if i < n - 1 else {0: 1.0, n - 1: 1.0} for i in range(n)]
    # an even cycle: the alternating vector is a null vector
    x, cond, _back, _c = banded.solve_float(rows, [1.0] * n, n, L.PATTERNS, L.EPS)
    assert x == [] or cond > L.SINGULAR_COND


def test_many_components_are_ordered_one_after_another():
    """A block of independent 2x2 pieces: each piece walked on its own (linear time),
    the band two wide, the solution the exact one to rounding."""
    n = 400
    rows = []
    for i in range(0, n, 2):
        rows.append({i: 2.0, i + 1: 1.0})
        rows.append({i: 1.0, i + 1: 3.0})
    b = [float(k % 7) for k in range(n)]
    got = banded.order(rows, n)
    assert sorted(got[0]) == list(range(n)) and sorted(got[1]) == list(range(n))
    x, cond, _back, _c = banded.solve_float(rows, b, n, L.PATTERNS, L.EPS)
    exact = L._exact(rows, b, n)
    assert all(abs(F(v) - e) <= F(4 * L.EPS) * abs(e) for v, e in zip(x, exact))
