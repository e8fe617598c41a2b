"""rowcode's shape readers give what the walk gives, or nothing.

A reader (one generated function per shape key) reads a tree's numbers and names by
position instead of walking it; `rowcode.shape` tries the readers of the shapes met
before and walks where none fits. Sound means: any reader applied to any tree returns
None or exactly `walk_shape(tree)` (same key, same numbers by repr and type, same
names). Checked by applying every reader to every tree of random trees built to hit
each fact the walk checks (int and NaN numbers, zeros and signed zeros in products,
Known against Var, repeated names, powers and functions), and on every tree a solve
shapes in every example and in generated chains, cradles and random scenes.
"""
from __future__ import annotations

import math
import random

import pytest
from test_rowcode import scenes

from momentum_cli import rowcode
from momentum_cli.compile import compile_scene
from momentum_cli.diagnostics import ProblemError
from momentum_cli.expr import Add, Const, Fn, Known, Mul, Pow, Var
from momentum_cli.scene import build
from momentum_cli.source import Source
from momentum_cli.syntax import parse


def _exact(sh):
    """A shape with its numbers by type and repr (signed zeros and NaNs count)."""
    if sh is None:
        return None
    key, nums, names = sh
    return key, [(type(v), repr(v), math.copysign(1.0, v) if v == v else None)
                 for v in nums], names


def _leaf(rng: random.Random):
    k = rng.randrange(6)
    if k == 0:
        return Const(rng.choice([0.0, -0.0, 1.0, -2.5, math.nan, 3, 1e-300]))
    if k == 1:
        return Known(rng.choice("mn"), rng.choice([0.0, 0.1, -4.0, 2]))
    if k == 2:
        return Fn("sin", Var("x"))
    return Var(rng.choice(["x", "y", "z", "x"]))


def _tree(rng: random.Random, depth: int):
    """A tree of the shapes large scenes have: sums of products of a few leaves."""
    if depth <= 0 or rng.random() < 0.25:
        return _leaf(rng)
    k = rng.randrange(7)
    if k < 3:
        return Add(tuple(_tree(rng, depth - 1) for _ in range(rng.randint(1, 3))))
    if k < 6:
        return Mul(tuple(_tree(rng, depth - 1) for _ in range(rng.randint(1, 3))))
    return Pow(_tree(rng, depth - 1), 2.0)


def _variants(rng: random.Random, e):
    """`e` with one leaf changed (the same layout, another fact): where a reader of
    e's shape must notice the difference."""
    if type(e) in (Add, Mul):
        kids = list(e.terms if type(e) is Add else e.factors)
        i = rng.randrange(len(kids))
        kids[i] = next(iter(_variants(rng, kids[i])), kids[i]) if rng.random() < 0.6 \
            else _leaf(rng)
        yield type(e)(tuple(kids))
    else:
        yield _leaf(rng)


def test_every_reader_on_every_tree_reads_the_walk_or_nothing():
    rng = random.Random(13)
    trees = []
    for _ in range(700):
        e = _tree(rng, 4)
        trees.append(e)
        trees.extend(_variants(rng, e))
        trees.extend(_variants(rng, e))
    walks = [_exact(rowcode.walk_shape(e)) for e in trees]
    keys = list(dict.fromkeys(w[0] for w in walks if w is not None))
    assert len(keys) > 100
    read = 0
    for key in keys:
        f = rowcode._reader(key)
        for e, w in zip(trees, walks):
            got = f(e)
            if got is not None:
                read += 1
                assert got[0] is key or got[0] == key
                assert _exact(got) == w, (key, w)
    # each tree of a shape is read by that shape's reader
    assert read >= sum(w is not None for w in walks)


def test_shape_with_readers_equals_the_walk_on_random_trees(monkeypatch):
    monkeypatch.setattr(rowcode, "COMPILE_AFTER", 0)
    monkeypatch.setattr(rowcode, "GUESS_AFTER", 0)
    rng = random.Random(17)
    for _ in range(3000):
        e = _tree(rng, 4)
        for x in (e, *_variants(rng, e)):
            assert _exact(rowcode.shape(x)) == _exact(rowcode.walk_shape(x))


def _scenes():
    """test_rowcode's scenes (every example, chains, cradles) and 40 generated ones."""
    yield from scenes()
    try:
        import scenegen
    except ImportError:  # numpy missing: the generated scenes are skipped
        return
    from scenegen import generate, render

    for seed in range(40):
        yield f"scenegen {seed}", render(generate(seed))


def _trees(system):
    """What a solve shapes: the residuals, the impacts' energies and the finds, with
    the terms of large sums (read term by term)."""
    out = [e.residual for e in system.equations]
    for t in system.transitions:
        for T in t.energy or ():
            out.append(T)
    out += [f.expr for f in system.finds]
    for e in list(out):
        if type(e) is Add:
            out.extend(e.terms)
    return out


@pytest.mark.parametrize("name,text", [pytest.param(n, t, id=n) for n, t in _scenes()])
def test_shapes_of_every_scene_equal_the_walk(monkeypatch, name, text):
    monkeypatch.setattr(rowcode, "COMPILE_AFTER", 0)
    monkeypatch.setattr(rowcode, "GUESS_AFTER", 0)
    try:
        system = compile_scene(build(parse(Source(name, text))))
    except ProblemError:
        return
    trees = _trees(system)
    for _ in range(2):  # the second time each tree's shape has its reader
        for e in trees:
            assert _exact(rowcode.shape(e)) == _exact(rowcode.walk_shape(e)), name
