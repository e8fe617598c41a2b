"""The checks' trees by code compiled per shape (report/treecode.py) against the walks
(`expr.evaluate`, `model.value_and_magnitude`): the same floats, bit for bit (the code
declines where the walk raises), on every residual and kinetic energy of every example,
of chains, cradles and scenegen scenes, and on random trees with powers, functions,
zero factors and missing unknowns."""
from __future__ import annotations

import math
import struct
import sys
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from momentum_cli.bench import chain_text
from momentum_cli.expr import Add, Const, Fn, Known, Mul, Pow, Var, evaluate
from momentum_cli.report import treecode
from momentum_cli.report.model import value_and_magnitude
from momentum_cli.scene import build
from momentum_cli.solve import ProblemError, solve_scene
from momentum_cli.source import Source
from momentum_cli.syntax import parse

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tests"))
from test_hard import cradle_text  # noqa: E402

EXAMPLES = sorted(p for p in (ROOT / "examples").glob("*.mom"))


def _bits(x):
    if isinstance(x, tuple):
        return tuple(_bits(y) for y in x)
    if type(x) is complex:  # (-1) ** 0.5: both walks give a complex
        return ("complex", _bits(x.real), _bits(x.imag))
    return struct.pack("<d", x) if type(x) is float else x


def _outcome(f, e, values):
    try:
        return ("ok", _bits(f(e, values)))
    except Exception as exc:  # noqa: BLE001 - whatever the walk raises
        return ("raise", type(exc))


def _agree(e, values) -> int:
    """Compare both walks with their code (compiled at once); how many ran compiled.
    The code never raises: where the walk raises, it declines (None) and the walk runs."""
    n = 0
    for fast, slow in ((treecode.evaluate, evaluate),
                       (treecode.value_and_magnitude, value_and_magnitude)):
        want = _outcome(slow, e, values)
        for _ in range(2):  # the second sight runs the compiled code
            got = fast(e, values)
            if want[0] == "raise":
                assert got is None
            elif got is not None:
                assert ("ok", _bits(got)) == want
                n += 1
    return n


def _trees(text_: str, name: str = "x.mom"):
    try:
        sol = solve_scene(build(parse(Source(name, text_))))
    except ProblemError:
        return None, []
    trees = [e.residual for e in sol.system.equations]
    for t in sol.system.transitions:
        if t.kind == "impact":
            trees += list(t.energy)
    return sol.values, trees


def _check(text_: str, name: str = "x.mom") -> int:
    values, trees = _trees(text_, name)
    return sum(_agree(e, values) for e in trees)


@pytest.mark.parametrize("path", EXAMPLES, ids=lambda p: p.name)
def test_examples_trees_by_their_code_equal_the_walks(path):
    _check(path.read_text(encoding="utf-8"), str(path))


def test_big_scenes_trees_by_their_code_equal_the_walks():
    n = _check(chain_text(30))
    for kind in ("sequence", "simultaneous"):
        n += _check(cradle_text(12, kind))
    assert n > 100  # the compiled code did run


def test_random_scenes_trees_by_their_code_equal_the_walks():
    import scenegen

    for cat in scenegen.categories():
        for seed in range(3):
            sc = scenegen.generate(seed, cat)
            if sc is not None:
                _check(scenegen.render(sc))


NAMES = ["a", "b", "c", "missing"]
LEAF = st.one_of(
    st.builds(Const, st.sampled_from([0.0, -0.0, 1.0, -1.0, 0.5, 2.0, 1e300, -3.25])),
    st.builds(Known, st.just("k"), st.sampled_from([0.0, 0.1, -2.0, 7.0])),
    st.builds(Var, st.sampled_from(NAMES)))
TREE = st.recursive(LEAF, lambda inner: st.one_of(
    st.lists(inner, min_size=2, max_size=4).map(lambda xs: Add(tuple(xs))),
    st.lists(inner, min_size=2, max_size=4).map(lambda xs: Mul(tuple(xs))),
    st.builds(Pow, inner, st.sampled_from([2, 2.0, -1.0, 0.5, 3])),
    st.builds(Fn, st.sampled_from(["sin", "exp", "ln", "abs"]), inner)), max_leaves=12)


@settings(max_examples=300, deadline=None)
@given(TREE, st.sampled_from([0.0, 1.5, -2.0, 1e200]))
def test_random_trees_by_their_code_equal_the_walks(e, b):
    _agree(e, {"a": 0.25, "b": b, "c": -1.0})


def test_a_shape_met_again_with_other_leaves_is_told_apart():
    """Two trees of one top (a sum of two) but other shapes: each by its own code."""
    x, y = Var("a"), Var("b")
    trees = [Add((Mul((Known("k", 2.0), x)), y)), Add((Mul((Known("k", 0.0), x)), y)),
             Add((Mul((Const(3.0), y)), x)), Add((x, Mul((Const(3.0), y))))]
    for _ in range(3):
        for e in trees:
            _agree(e, {"a": 1.0, "b": math.pi})
