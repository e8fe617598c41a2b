"""Runs of one-unknown blocks solved together (solve_ones) against `_solve_one`, one
block at a time: the same values in the same order, the same reports, bounds and
answers, bit for bit; and the scalar solves on arrays against `linalg.solve_one`."""
from __future__ import annotations

import random

import pytest

import momentum_cli.linalg as L
from momentum_cli import solve_ones
from momentum_cli.bench import chain_text
from momentum_cli.diagnostics import ProblemError
from momentum_cli.linalg import SingularError
from momentum_cli.scene import build
from momentum_cli.solve import solve_scene
from momentum_cli.source import Source
from momentum_cli.syntax import parse

np = pytest.importorskip("numpy")


def _quality(q) -> tuple:
    return tuple(repr(v) for v in (q.method, q.precision, q.cond, q.backward, q.bound,
                                   q.iterations, q.components, q.exact))


def _pairs(rng, n):
    out = []
    for _ in range(n):
        a = rng.choice([rng.gauss(0, 1), 1.0, -3.0, 5e-324, 1e-310, 1e308, -1e-300,
                        7.0 * 2.0**-1074, rng.uniform(-1, 1) * 10 ** rng.uniform(-300, 300)])
        b = rng.choice([0.0, -0.0, rng.gauss(0, 1), 1e308, -5e-324,
                        a * rng.choice([1.0, -1.0, 1 + 2.0**-52]),
                        rng.uniform(-1, 1) * 10 ** rng.uniform(-300, 300)])
        out.append((a, b))
    return out


@pytest.mark.parametrize("seed", range(5))
def test_solves_on_arrays_are_solve_one(seed):
    rng = random.Random(seed)
    pairs = _pairs(rng, 400)
    got = solve_ones.solve_ones(np, [a for a, _ in pairs], [b for _, b in pairs])
    for (a, b), g in zip(pairs, got):
        try:
            x, q = L.solve_one(a, b)
        except SingularError:
            assert g is None
            continue
        assert g is not None
        assert [repr(v) for v in g[0]] == [repr(v) for v in x]
        assert _quality(g[1]) == _quality(q)


def _outcome(text: str, name: str):
    """Everything the solve hands on: values (in order), reports, bounds, answers."""
    try:
        sol = solve_scene(build(parse(Source(name, text))))
    except ProblemError as exc:
        return repr([d.message for d in exc.diagnostics])
    blocks = [(b.index, b.unknowns, b.equations, b.method, repr(b.cond), b.matrix, b.rhs,
               _quality(b.quality) if b.quality is not None else None)
              for b in sol.blocks]
    return repr(([(k, repr(v)) for k, v in sol.values.items()], blocks, sol.answers,
                 [(k, repr(v)) for k, v in (sol.size or {}).items()],
                 [(k, repr(v)) for k, v in (sol.errors or {}).items()],
                 sol.answer_errors, [(c.name, c.status, c.detail) for c in sol.checks]))


def _both(monkeypatch, text: str, name: str):
    got = []
    for on in (True, False):
        monkeypatch.setattr(solve_ones, "ENABLED", on)
        got.append(_outcome(text, name))
    return got


@pytest.fixture
def short_runs(monkeypatch):
    """Runs from 2 blocks (not MIN_RUN), numpy loaded: every run a scene has is taken."""
    monkeypatch.setattr(solve_ones, "MIN_RUN", 2)


def test_every_example_solves_the_same_in_runs(monkeypatch, short_runs):
    from conftest import EXAMPLES

    for path in sorted(EXAMPLES.rglob("*.mom")):
        on, off = _both(monkeypatch, path.read_text(encoding="utf-8"), path.name)
        assert on == off, path.name


@pytest.mark.parametrize("n, kw", [(300, {}), (200, {"decades": 9.0, "e": 0.9}),
                                   (150, {"decades": 0.0, "e": 1.0})])
def test_chains_solve_the_same_in_runs(monkeypatch, n, kw):
    monkeypatch.setattr(L, "BIG", 100)  # the banded path (numpy) for these chains
    on, off = _both(monkeypatch, chain_text(n, **kw), "chain.mom")
    assert on == off


@pytest.mark.parametrize("kind", ["sequence", "simultaneous"])
def test_cradles_solve_the_same_in_runs(monkeypatch, short_runs, kind):
    from test_hard import cradle_text

    on, off = _both(monkeypatch, cradle_text(60, kind), "cradle.mom")
    assert on == off


KNOCKS = """problem "two knocks"
let m = 0.1 kg
body b1: particle(mass = m, radius = 15 mm)
body b2: particle(mass = 2 kg, radius = 15 mm)
body b3: particle(mass = 3 kg, radius = 15 mm)
state 1: b1.v = (2 m/s, 0.5 m/s), b2.v = (0, 0.25 m/s), b3.v = (0, -0.125 m/s)
state 2
state 3
impact 1 -> 2:
    contact c1: b2 with b1 normal (1, 0): restitution 1, smooth
impact 2 -> 3:
    contact c2: b3 with b2 normal (1, 0): restitution 1, smooth
find b2.vy@3, b3.vy@3, b1.vy@3
"""


def test_a_run_stops_before_a_block_that_needs_it(monkeypatch):
    """b2.vy@3 needs b2.vy@2: put one after the other, a run takes the first alone, and
    the next run from the second reads the value the first set (as one by one)."""
    import momentum_cli.solve as S

    kept = {}
    solve = S._solve

    def spy(system, structure, *a, **k):
        kept["system"], kept["blocks"] = system, list(structure.blocks)
        return solve(system, structure, *a, **k)

    monkeypatch.setattr(S, "_solve", spy)
    sol = solve_scene(build(parse(Source("knocks.mom", KNOCKS))))
    system, blocks = kept["system"], kept["blocks"]
    by_name = {b.unknowns[0]: b.index for b in blocks if len(b.unknowns) == 1}
    order = [by_name["b2.vy@2"], by_name["b2.vy@3"]]
    monkeypatch.setattr(solve_ones, "MIN_RUN", 1)
    values = {k: v for k, v in sol.values.items() if k not in ("b2.vy@2", "b2.vy@3")}
    one_by_one = dict(values)
    for b in order:
        assert S._solve_one(system, blocks[b], one_by_one) is not None
    nxt, run, retry = solve_ones.run(system, blocks, order, 0, values, S._one_report)
    assert (nxt, [blk.unknowns for blk, _ in run], retry) == (1, [["b2.vy@2"]], 2)
    nxt, run, retry = solve_ones.run(system, blocks, order, 1, values, S._one_report)
    assert (nxt, [blk.unknowns for blk, _ in run]) == (2, [["b2.vy@3"]])
    assert [(k, repr(v)) for k, v in values.items()] == \
        [(k, repr(v)) for k, v in one_by_one.items()]
    assert values["b2.vy@3"] == 0.25  # nothing acts on it in y
