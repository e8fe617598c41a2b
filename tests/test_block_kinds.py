"""Small blocks solved and bounded by their kind's generated code (block_kinds) against
the general path (`_solve_block`, `_solve_one`, `bounds._square`, `bounds._one`): the
same values in the same order, the same reports, sizes, bounds, answers and checks, bit
for bit; and the generated replay of a factored matrix against `linalg.solve_factored`."""
from __future__ import annotations

import random

import pytest

import momentum_cli.linalg as L
import momentum_cli.solve as S
from momentum_cli import block_kinds, rowcode
from momentum_cli.bench import chain_text
from momentum_cli.diagnostics import ProblemError
from momentum_cli.scene import build
from momentum_cli.solve import solve_scene
from momentum_cli.source import Source
from momentum_cli.syntax import parse


def _quality(q) -> tuple:
    return tuple(repr(v) for v in (q.method, q.precision, q.cond, q.backward, q.bound,
                                   q.iterations, q.components, q.exact))


def _outcome(text: str, name: str, precision: str = "float"):
    """Everything the solve hands on: values (in order), reports, bounds, answers, checks."""
    try:
        sol = solve_scene(build(parse(Source(name, text))), precision=precision)
    except ProblemError as exc:
        return repr([d.message for d in exc.diagnostics])
    blocks = [(b.index, b.unknowns, b.equations, b.method, repr(b.cond), repr(b.matrix),
               repr(b.rhs), _quality(b.quality) if b.quality is not None else None)
              for b in sol.blocks]
    return repr(([(k, repr(v)) for k, v in sol.values.items()], blocks, sol.answers,
                 [(k, repr(v)) for k, v in (sol.size or {}).items()],
                 [(k, repr(v)) for k, v in (sol.errors or {}).items()],
                 sol.answer_errors, [(c.name, c.status, c.detail) for c in sol.checks]))


def _fused_count(monkeypatch) -> list:
    """Counts the blocks the kinds' code solved (so a test knows it ran)."""
    seen = [0]
    take = block_kinds.take

    def spy(*a, **k):
        got = take(*a, **k)
        seen[0] += got is not None
        return got

    monkeypatch.setattr(block_kinds, "take", spy)
    return seen


def _both(monkeypatch, text: str, name: str, eager: bool = True, precision="float"):
    """(fused, general) outcomes; `eager`: every kind gets its code at once, in scenes
    of any size (small ones included)."""
    if eager:
        monkeypatch.setattr(block_kinds, "AFTER", 0)
        monkeypatch.setattr(S, "KINDS_FROM", 0)
        monkeypatch.setattr(rowcode, "PLAIN_SMALL", False)
    seen = _fused_count(monkeypatch)
    got = []
    for on in (True, False):
        monkeypatch.setattr(block_kinds, "FUSE", on)
        block_kinds._KINDS.clear()
        got.append(_outcome(text, name, precision))
    return got, seen[0]


def test_every_example_solves_the_same_by_kinds(monkeypatch):
    from conftest import EXAMPLES

    fused = 0
    for path in sorted(EXAMPLES.rglob("*.mom")):
        (on, off), seen = _both(monkeypatch, path.read_text(encoding="utf-8"), path.name)
        assert on == off, path.name
        fused += seen
    assert fused > 100  # the kinds' code did run


@pytest.mark.parametrize("n", [80, 200])
def test_cradles_solve_the_same_by_kinds(monkeypatch, n):
    from test_hard import cradle_text

    (on, off), seen = _both(monkeypatch, cradle_text(n, "sequence"), "cradle.mom",
                            eager=False)
    assert on == off
    # past AFTER sightings, each of its three kinds of block takes its code
    assert seen >= 3 * (n - 2 - block_kinds.AFTER)


def _knocks(n: int, seed: int) -> str:
    """A sequence of n-1 two-ball impacts of other masses, restitutions, normals and
    velocities in both directions (blocks of one kind, every matrix and right side new)."""
    rng = random.Random(seed)
    out = ['problem "knocks"']
    for i in range(1, n + 1):
        out.append(f"body b{i}: particle(mass = {rng.choice([0.1, 0.25, rng.uniform(0.01, 9)])!r}"
                   " kg, radius = 15 mm)")
    vs = ", ".join(f"b{i}.v = ({rng.uniform(-1, 3)!r} m/s, {rng.choice([0, 0.5, -0.25])} m/s)"
                   for i in range(1, n + 1))
    out.append(f"state 1: {vs}")
    out += [f"state {i}" for i in range(2, n + 1)]
    for i in range(1, n):
        normal = rng.choice(["(1, 0)", "(0.6, 0.8)", "(1, 0)"])
        e = rng.choice(["1", "0.9", "0", repr(rng.uniform(0.1, 1.0))])
        out.append(f"impact {i} -> {i + 1}:")
        out.append(f"    contact c{i}: b{i + 1} with b{i} normal {normal}: restitution {e}, "
                   "smooth")
    out.append(f"find b{n}.vx@{n}, b1.vy@{n}, J_n[c{n - 1}]@{n - 1}->{n}, T_lost@1->2")
    return "\n".join(out) + "\n"


@pytest.mark.parametrize("seed", range(4))
def test_sequences_of_other_numbers_solve_the_same_by_kinds(monkeypatch, seed):
    (on, off), seen = _both(monkeypatch, _knocks(90, seed), "knocks.mom")
    assert on == off
    assert seen > 0


@pytest.mark.parametrize("precision", ["refine", "exact"])
def test_other_precisions_take_the_general_path(monkeypatch, precision):
    (on, off), seen = _both(monkeypatch, _knocks(30, 7), "knocks.mom", precision=precision)
    assert on == off
    assert seen == 0


@pytest.mark.parametrize("n, kw", [(300, {}), (120, {"decades": 9.0, "e": 0.9})])
def test_chains_solve_the_same_by_kinds(monkeypatch, n, kw):
    (on, off), _seen = _both(monkeypatch, chain_text(n, **kw), "chain.mom")
    assert on == off


def _matrix(rng, n):
    rows = []
    for i in range(n):
        row = {}
        for j in range(n):
            if i == j or rng.random() < 0.6:
                row[j] = rng.choice([rng.gauss(0, 1), 1.0, -1.0, 0.1, 2.0,
                                     rng.uniform(-1, 1) * 10 ** rng.uniform(-8, 8)])
        rows.append(row)
    return rows


@pytest.mark.parametrize("seed", range(6))
def test_replay_code_is_solve_factored(seed):
    """The generated replay of a factored matrix, on the right-hand sides the general
    `solve_factored` takes: zeros of both signs, round-off-sized, huge and tiny ones."""
    rng = random.Random(seed)
    for _ in range(40):
        n = rng.randint(2, 5)
        rows = _matrix(rng, n)
        try:
            F = L.factor_small(rows, n)
        except L.SingularError:
            continue
        kind = block_kinds.Kind((), n)
        kind.cols = tuple(tuple(row) for row in rows)
        coefs = tuple(v for row in rows for v in row.values())
        run, nums = block_kinds._matrix(kind, coefs)
        for _ in range(8):
            b = [rng.choice([0.0, -0.0, rng.gauss(0, 1), 1e-300, -1e300, 1e-17,
                             rng.uniform(-1, 1) * 10 ** rng.uniform(-20, 20)])
                 for _ in range(n)]
            x, q = run(nums, *b)
            x0, q0 = L.solve_factored(F, b)
            assert repr(x) == repr(x0)
            assert _quality(q) == _quality(q0)


def test_a_singular_matrix_is_left_to_the_general_path():
    kind = block_kinds.Kind((), 2)
    kind.cols = ((0, 1), (0, 1))
    assert block_kinds._matrix(kind, (1.0, 2.0, 2.0, 4.0)) is False
