"""rowcode.affine_many (a large block's rows formed shape by shape on arrays) against
rowcode.affine equation by equation: the same coefficients and constants to the bit, in
the same dict order, and the same exceptions, on every example and on generated scenes."""
from __future__ import annotations

import glob
import os
import struct

import pytest

from momentum_cli import rowcode
from momentum_cli.bench import chain_text
from momentum_cli.diagnostics import ProblemError
from momentum_cli.scene import build
from momentum_cli.solve import solve_scene
from momentum_cli.source import Source
from momentum_cli.syntax import parse

pytest.importorskip("numpy")


def _bits(row):
    coef, const = row
    return [(k, struct.pack("d", v)) for k, v in coef.items()], struct.pack("d", const)


def _outcome(f):
    try:
        return "ok", [_bits(r) for r in f()]
    except Exception as exc:  # noqa: BLE001 - the comparison is of the exception too
        return "raised", type(exc).__name__


def _check_scene(text: str, name: str) -> int:
    try:
        sol = solve_scene(build(parse(Source(name, text))))
    except ProblemError:
        return 0
    eqs = sol.system.equations
    checked = 0
    with rowcode.remembered():
        for blk in sol.structure.blocks:
            exprs = [eqs[k].residual for k in blk.equations]
            bset = set(blk.unknowns)
            want = _outcome(lambda: [rowcode.affine(e, bset, sol.values) for e in exprs])
            got = _outcome(lambda: rowcode.affine_many(exprs, bset, sol.values))
            assert got == want, (name, blk.unknowns)
            checked += 1
        # every equation against all its unknowns as one "block" (mixed shapes)
        exprs = [e.residual for e in eqs]
        every = set(sol.values)
        assert _outcome(lambda: rowcode.affine_many(exprs, every, sol.values)) == \
            _outcome(lambda: [rowcode.affine(e, every, sol.values) for e in exprs])
    return checked


EXAMPLES = sorted(p for p in glob.glob("examples/*.mom") + glob.glob("examples/hard/*.mom")
                  if os.path.getsize(p) < 40_000)  # the generated 1000-ball files: below


@pytest.mark.parametrize("path", EXAMPLES)
def test_examples(path, monkeypatch):
    monkeypatch.setattr(rowcode, "MANY", 1)  # every shape on arrays, even met once
    with open(path, encoding="utf-8") as fh:
        _check_scene(fh.read(), path)


def test_generated_chain_and_cradle(monkeypatch):
    import sys

    sys.path.insert(0, "tests")
    from test_hard import cradle_text

    monkeypatch.setattr(rowcode, "MANY", 2)
    assert _check_scene(chain_text(300), "chain.mom") > 0
    assert _check_scene(cradle_text(40, "sequence"), "cradle.mom") > 0
    assert _check_scene(cradle_text(40, "simultaneous"), "cradle.mom") > 0


def test_missing_value_and_nonlinear_raise_as_one_by_one(monkeypatch):
    from momentum_cli.expr import Const, Var, add, mul

    monkeypatch.setattr(rowcode, "MANY", 1)
    x, y = Var("x"), Var("y")
    lin = [add(mul(Const(2.0), x), mul(Const(3.0), y)) for _ in range(4)]
    nonlin = [mul(x, x) for _ in range(3)]
    for exprs, vals in ((lin, {"y": 1.5}), (lin, {}), (lin + nonlin, {"y": 1.0}),
                        (nonlin + lin, {})):
        assert _outcome(lambda: rowcode.affine_many(exprs, {"x"}, vals)) == \
            _outcome(lambda: [rowcode.affine(e, {"x"}, vals) for e in exprs])


# ---- sums of many terms (a scene's energy): values, derivatives and sizes on arrays ----------
def _walks(sol, exprs):
    from momentum_cli.bounds import _grad_size

    out = []
    with rowcode.remembered():
        for e in exprs:
            try:
                v = ("ok", struct.pack("d", rowcode.evaluate(e, sol.values)))
            except Exception as exc:  # noqa: BLE001
                v = ("raised", type(exc).__name__)
            g = rowcode.grad_size_big(e, sol.values, _grad_size)
            if g is not None:
                d, z = g
                g = ([(k, struct.pack("d", x)) for k, x in d.items()], struct.pack("d", z))
            out.append((v, g))
    return out


def _big_exprs(sol):
    from momentum_cli.expr import add_all

    exprs = [f.expr for f in sol.system.finds] + \
        [f.alt for f in sol.system.finds if f.alt is not None]
    # a sum of every equation's residual: terms of many shapes, unknowns shared
    exprs.append(add_all([e.residual for e in sol.system.equations]))
    return exprs


def _compare_sums(text: str, name: str, monkeypatch, many: int) -> None:
    try:
        sol = solve_scene(build(parse(Source(name, text))))
    except ProblemError:
        return
    exprs = _big_exprs(sol)
    monkeypatch.setattr(rowcode, "MANY", 10**9)
    want = _walks(sol, exprs)
    monkeypatch.setattr(rowcode, "MANY", many)
    monkeypatch.setattr(rowcode, "FORCE_ARRAYS", True)
    assert _walks(sol, exprs) == want, name


@pytest.mark.parametrize("path", EXAMPLES)
def test_sums_of_terms_on_arrays_examples(path, monkeypatch):
    with open(path, encoding="utf-8") as fh:
        _compare_sums(fh.read(), path, monkeypatch, 2)


def test_sums_of_terms_on_arrays_generated(monkeypatch):
    import sys

    sys.path.insert(0, "tests")
    from test_hard import cradle_text

    for text in (chain_text(300), cradle_text(60, "sequence"), cradle_text(60, "simultaneous")):
        _compare_sums(text, "big.mom", monkeypatch, 2)


# ---- bounds.propagate with a large block's rows on arrays ---------------------------------
def _propagate_bits(sol):
    from momentum_cli.bounds import propagate

    with rowcode.remembered():
        size, err = propagate(sol.system, sol.blocks, sol.values)
    return [(k, struct.pack("d", v)) for k, v in size.items()], \
        [(k, struct.pack("d", v)) for k, v in err.items()]


def _compare_propagate(text: str, name: str, monkeypatch) -> None:
    from momentum_cli import bounds

    try:
        sol = solve_scene(build(parse(Source(name, text))))
    except ProblemError:
        return
    monkeypatch.setattr(bounds, "ROWS_ON_ARRAYS", 10**9)
    want = _propagate_bits(sol)
    monkeypatch.setattr(bounds, "ROWS_ON_ARRAYS", 2)
    monkeypatch.setattr(rowcode, "MANY", 2)
    assert _propagate_bits(sol) == want, name


@pytest.mark.parametrize("path", EXAMPLES)
def test_propagate_rows_on_arrays_examples(path, monkeypatch):
    with open(path, encoding="utf-8") as fh:
        _compare_propagate(fh.read(), path, monkeypatch)


def test_propagate_rows_on_arrays_generated(monkeypatch):
    import sys

    sys.path.insert(0, "tests")
    from test_hard import cradle_text

    for text in (chain_text(300), cradle_text(60, "simultaneous"),
                 cradle_text(60, "sequence")):
        _compare_propagate(text, "big.mom", monkeypatch)


def test_variables_by_shapes_is_variables():
    """rowcode.variables_into names what expr.variables names, on every example's
    equations and energies summed, zero products and all."""
    from momentum_cli.expr import add_all, variables

    for path in EXAMPLES + ["chain"]:
        text = chain_text(40) if path == "chain" else open(path, encoding="utf-8").read()
        try:
            sol = solve_scene(build(parse(Source(path, text))))
        except ProblemError:
            continue
        exprs = [e.residual for e in sol.system.equations]
        exprs += [T for t in sol.system.transitions if t.energy is not None for T in t.energy]
        for e in exprs + [add_all(exprs)]:
            got: set = set()
            with rowcode.remembered():
                rowcode.variables_into(e, got, variables)
            assert got == variables(e), path


def test_variables_by_shapes_of_a_difference_of_sums():
    from momentum_cli.expr import Const, Known, Var, add_all, mul, neg, variables

    a = add_all([mul(Known("m", 2.0), mul(Var(f"v{i}"), Var(f"v{i}"))) for i in range(40)])
    b = add_all([mul(Known("m", 0.0), Var(f"w{i}")) for i in range(20)] +
                [mul(Const(3.0), Var(f"u{i}")) for i in range(30)])
    for e in (add_all([a, neg(b)]), add_all([neg(a), b, mul(Const(0.0), a)])):
        got: set = set()
        with rowcode.remembered():
            rowcode.variables_into(e, got, variables)
        assert got == variables(e)
