"""The solve's fast paths give bit for bit what the plain ones give.

rowcode's compiled walks (one function per shape of tree) against expr._affine_float and
bounds.derivatives_and_size on random trees; and whole solves with every fast path on
(rowcode, bounds' one-unknown step, the memo's 1x1 bypass, the batched blocks) against
the same solves with them off, on every example and on generated chains and cradles:
every value, size, error bound, block report, check and answer, floats by repr (signed
zeros count), dicts in their order."""
from __future__ import annotations

import math
import random

import pytest
from conftest import EXAMPLES
from test_bounds_fused import _tree
from test_hard import cradle_text

from momentum_cli import bounds, rowcode
from momentum_cli.bench import chain_text
from momentum_cli.diagnostics import ProblemError
from momentum_cli.expr import Add, Const, Known, Mul, NonLinear, Var, affine
from momentum_cli.scene import build
from momentum_cli.solve import solve_scene
from momentum_cli.source import Source
from momentum_cli.syntax import parse


def _reprs(x):
    if isinstance(x, float):
        # a NaN's sign is not compared: the interpreter's generic and specialized float
        # additions give two NaNs' sum one or the other sign (tests/test_bounds_fused.py)
        return repr(x) + ("-" if x == x and math.copysign(1.0, x) < 0 else "")
    if isinstance(x, dict):
        return [(_reprs(k), _reprs(v)) for k, v in x.items()]
    if isinstance(x, (tuple, list)):
        return [_reprs(v) for v in x]
    if isinstance(x, set):
        return sorted(map(str, x))
    if hasattr(x, "_fields"):
        return [type(x).__name__, *(_reprs(getattr(x, f)) for f in x._fields)]
    return x


def outcome(f, *args):
    try:
        return _reprs(f(*args))
    except (KeyError, ValueError, ZeroDivisionError, OverflowError, NonLinear) as exc:
        return type(exc).__name__


@pytest.fixture(autouse=True)
def compile_at_once(monkeypatch):
    """Every shape compiled at first sight (the solve waits for the second): the compiled
    walks are what these tests are about."""
    monkeypatch.setattr(rowcode, "COMPILE_AFTER", 0)
    monkeypatch.setattr(rowcode, "GUESS_AFTER", 0)  # shapes read at once too


def test_compiled_walks_equal_the_walks_on_random_trees():
    rng = random.Random(3)
    values = {"x": 2.0, "y": -0.5, "z": 0.0, "w": 1e200, "v": -0.0}
    shaped = 0
    for _ in range(4000):
        e = _tree(rng, 4)
        shaped += rowcode.shape(e) is not None
        assert outcome(bounds.fast_derivatives_and_size, e, values) == \
            outcome(bounds.derivatives_and_size, e, values), e
        for block in (set(), {"x"}, {"x", "y"}, {"x", "y", "z", "w", "v", "missing"},
                      {"missing"}):
            assert outcome(rowcode.affine, e, block, values) == \
                outcome(affine, e, block, values), (block, e)
    assert shaped > 1000  # most trees took the compiled walks


def test_large_trees_walked_by_parts_equal_the_walk(monkeypatch):
    """grad_size_big on trees made 'large' by a tiny token limit: the sums and products
    above the compiled parts are walked as bounds walks them."""
    monkeypatch.setattr(rowcode, "MAX_TOKENS", 6)
    rng = random.Random(8)
    values = {"x": 2.0, "y": -0.5, "z": 0.0, "w": 1e200, "v": -0.0}
    done = 0
    for _ in range(4000):
        e = _tree(rng, 5)
        got = rowcode.grad_size_big(e, values, bounds._grad_size)
        if got is not None:
            done += 1
            assert _reprs(got) == outcome(bounds.derivatives_and_size, e, values), e
    assert done > 1000


def test_evaluate_by_parts_equals_the_walk(monkeypatch):
    from momentum_cli.expr import evaluate

    rng = random.Random(9)
    values = {"x": 2.0, "y": -0.5, "z": 0.0, "w": 1e200, "v": -0.0}
    for limit in (400, 6):
        monkeypatch.setattr(rowcode, "MAX_TOKENS", limit)
        for _ in range(3000):
            e = _tree(rng, 5)
            assert outcome(rowcode.evaluate, e, values) == outcome(evaluate, e, values), e


def _energy_like(rng: random.Random, depth: int):
    """A sum of kinetic-energy-like products, with -(a sum) inside, a zero or a missing
    value here and there, and now and then anything else (powers, functions)."""
    def leaf():
        k = rng.randrange(10)
        if k == 0:
            return Known("m", rng.choice([0.0, 2.0, 2.0, 2.0, 3]))
        if k == 1:
            return Const(rng.choice([0.0, -0.0, 0.5, 1e-300]))
        if rng.random() < 0.01:
            return Var("missing")
        return Var(rng.choice(["x", "y", "z", "w", "v", "x"]))

    terms = []
    for _ in range(rng.randint(2, 7)):
        r = rng.random()
        if r < 0.55:
            terms.append(Mul((Const(rng.choice([0.5, -0.25, 0.0, 2.0])), leaf(),
                              Add((Mul((leaf(), leaf())), Mul((leaf(), leaf())))))))
        elif r < 0.75 and depth:
            terms.append(Mul((Const(rng.choice([-1.0, 0.5, 2])), _energy_like(rng, depth - 1))))
        elif r < 0.9 and depth:
            terms.append(_energy_like(rng, depth - 1))
        elif r < 0.97:
            terms.append(Mul((Const(0.5), leaf(), leaf())))
        else:
            terms.append(_tree(rng, 2))
    return Add(tuple(terms))


@pytest.mark.parametrize("after", [0, 10**9])
def test_value_and_bound_in_one_walk_equal_the_two_walks(monkeypatch, after):
    """value_grad_size (an answer's value and bound, each term walked once) against
    rowcode.evaluate with grad_size_big, and against the plain walks, on energy-like
    trees made 'large' by a small token limit; the shapes compiled at once, or never
    (each term then by the two walks it stands for)."""
    from momentum_cli.expr import evaluate

    monkeypatch.setattr(rowcode, "MAX_TOKENS", 40)
    monkeypatch.setattr(rowcode, "COMPILE_AFTER", after)
    rng = random.Random(21)
    values = {"x": 2.0, "y": -0.5, "z": 0.0, "w": 1e200, "v": -0.0}
    done = 0
    for _ in range(2000):
        e = _energy_like(rng, 2)
        if rng.random() < 0.3:  # -(a large sum), as an energy lost is written
            e = Mul((Const(-1.0), e))
        with rowcode.remembered():
            got = rowcode.value_grad_size(e, values, bounds._grad_size)
            if got is None:
                continue
            done += 1
            assert _reprs(got[0]) == outcome(rowcode.evaluate, e, values) == \
                outcome(evaluate, e, values), e
            assert _reprs(got[1:]) == outcome(rowcode.grad_size_big, e, values,
                                              bounds._grad_size) == \
                outcome(bounds.derivatives_and_size, e, values), e
    assert done > 120


def snapshot(sol) -> list:
    """Everything a solution holds that the report or JSON reads, comparable exactly."""
    return _reprs([
        sol.values, sol.size, sol.errors, sol.answers, sol.answer_errors, sol.regimes,
        sorted(map(str, sol.snapped or ())), sol.solved_all,
        [[c.name, c.status, c.detail, c.value] for c in sol.checks],
        [[d.severity, d.code, d.message] for d in sol.diagnostics],
        [[b.index, b.unknowns, b.equations, b.method, b.cond, b.iterations, b.residual,
          b.matrix, b.rhs, b.quality, b.rejected, b.unphysical] for b in sol.blocks],
        _structure(sol.structure),
    ])


def _structure(st) -> list:
    """The analysis, comparable exactly (analyse takes the incidence from the shapes the
    solve reads when rowcode is on, from `expr.variables` when off)."""
    return [st.incidence, st.match_eq, st.match_var, st.under, st.under_eqs, st.redundant,
            [[b.index, b.equations, b.unknowns, b.depends] for b in st.blocks],
            st.block_of_var, st.constant_eqs]


def solved(text: str, name: str, fast: bool, precision: str = "float"):
    saved = rowcode.ENABLED, bounds.FAST
    rowcode.ENABLED = bounds.FAST = fast
    try:
        return snapshot(solve_scene(build(parse(Source(name, text))), precision=precision))
    except ProblemError as exc:
        return [[d.code, d.message, d.notes] for d in exc.diagnostics]
    finally:
        rowcode.ENABLED, bounds.FAST = saved


def scenes():
    for path in sorted(EXAMPLES.glob("*.mom")):
        yield path.name, path.read_text(encoding="utf-8")
    for n in (2, 7, 60):
        yield f"chain {n}", chain_text(n)
    for n in (3, 40):
        yield f"cradle-seq {n}", cradle_text(n, "sequence")
        yield f"cradle-sim {n}", cradle_text(n, "simultaneous")


@pytest.mark.parametrize("name,text", [pytest.param(n, t, id=n) for n, t in scenes()])
def test_fast_solve_equals_plain_solve(name, text):
    assert solved(text, name, True) == solved(text, name, False)


def test_fast_solve_equals_plain_solve_compiling_on_second_sight(monkeypatch):
    monkeypatch.setattr(rowcode, "COMPILE_AFTER", 1)
    for name, text in [("chain 25", chain_text(25)), ("cradle 12", cradle_text(12, "sequence"))]:
        rowcode._GS.clear(), rowcode._AFF.clear(), rowcode._VAL.clear(), rowcode._SEEN.clear()
        assert solved(text, name, True) == solved(text, name, False)


@pytest.mark.parametrize("precision", ["refine", "exact"])
def test_fast_solve_equals_plain_solve_in_other_precisions(precision):
    for name, text in [("chain 9", chain_text(9)), ("cradle 6", cradle_text(6, "sequence"))]:
        assert solved(text, name, True, precision) == solved(text, name, False, precision)
