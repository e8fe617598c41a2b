"""The symbolic line by per-kind templates (report/sym_template.py) against the shape's
compiled printer alone (and so against `Equation.text()`, which test_report_shapes
compares that printer with).

A template is made from the first row of a shape and its numbers and then fills in the
names of every later row: the later rows here get names that could change what the
printer decides (equal neighbours that merge as x^2, a name that begins with '-', names
holding the characters of compound texts or a number's text), on random trees, every
example's equations and generated chains and cradles.
"""
from __future__ import annotations

import math
import random
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from test_report_printer import TREES, _outcome

from momentum_cli.compile import Equation
from momentum_cli.expr import Add, Const, Known, Mul, Var
from momentum_cli.report import printer, sym_template

ROOT = Path(__file__).resolve().parent.parent
HOSTILE = ["a", "b", "a", "-a", "a b", "a*b", "(a + b)", "x^2", "inf", "nan", "2", "-1",
           "(a)", "rod.vx@2", "e[b2-b1]", "J_n[b2-b1]@1->2", "m_b1", "", "0.5", "(-2)",
           "-2", "(-0.5)", "2^2"]


def _printers(key: tuple):
    """(the compiled symbolic printer alone, the same with templates) of shape `key`."""
    was = sym_template.ENABLED
    try:
        sym_template.ENABLED = False
        plain = printer._compile(key)[0]
        sym_template.ENABLED = True
        templated = printer._compile(key)[0]
    finally:
        sym_template.ENABLED = was
    return plain, templated


def _shape(e, expr: bool = False):
    toks: list = [printer._EXPR] if expr else []
    leaves: list = []
    if expr:
        printer._walk(e, toks, leaves)
    else:
        printer._walk(e.lhs, toks, leaves)
        toks.append(printer._EQ)
        printer._walk(e.rhs, toks, leaves)
    return tuple(toks), leaves


def _renamed(leaves: list, rng: random.Random) -> list:
    """The leaves with other names (numbers kept: a template's numbers are its key)."""
    out = []
    for x in leaves:
        if type(x) is Var:
            out.append(Var(rng.choice(HOSTILE)))
        elif type(x) is Known:
            out.append(Known(rng.choice(HOSTILE), x.value))
        else:
            out.append(x)
    return out


def _same_on_renamings(key, leaves, rng, n=12, seen=None):
    plain, templated = seen[key] if seen is not None and key in seen else _printers(key)
    if seen is not None:
        seen[key] = plain, templated
    for ls in [leaves] + [_renamed(leaves, rng) for _ in range(n)]:
        want = _outcome(lambda: plain(ls, None, None, 6, {}))  # noqa: B023
        assert _outcome(lambda: templated(ls, None, None, 6, {})) == want  # noqa: B023
        # the template made: used again
        assert _outcome(lambda: templated(ls, None, None, 6, {})) == want  # noqa: B023


@settings(max_examples=300, deadline=None)
@given(TREES, TREES, st.integers(0, 2**32))
def test_templates_of_random_trees_print_as_the_printer(lhs, rhs, seed):
    rng = random.Random(seed)
    key, leaves = _shape(Equation(lhs, rhs, "p", "g", None))
    _same_on_renamings(key, leaves, rng)
    key, leaves = _shape(lhs, expr=True)  # a term of a long sum: (text, precedence)
    _same_on_renamings(key, leaves, rng)


def test_names_that_would_change_the_text_are_printed_by_the_printer():
    x = Var("x")
    cases = [
        (Mul((Var("p"), Var("q"))), Const(0.0)),  # p*q, or x^2 if the names are equal
        (Mul((Const(-1.0), Known("e", 0.5), Add((x, Var("y"))))), Const(1.0)),
        (Add((x, Var("y"))), Mul((Const(-2.0), Var("z")))),  # a name that begins with '-'
        (Mul((Const(2.0), Var("p"))), Const(0.0)),  # a name that reads as the number
        (Mul((Known("k", 1.0), Add((x, Var("y"))))), Const(0.0)),  # k as "(x + y)"
        (Mul((Var("p"), Const(-2.0))), Const(0.0)),  # p as "(-2)", the number's text
        (Mul((Const(2.0), Const(2.0), Var("p"))), Const(0.0)),  # p as the merged "2^2"
    ]
    rng = random.Random(7)
    for lhs, rhs in cases:
        key, leaves = _shape(Equation(lhs, rhs, "p", "g", None))
        _same_on_renamings(key, leaves, rng, n=200)
    plain, templated = _printers(_shape(Equation(cases[0][0], cases[0][1], "p", "g",
                                                 None))[0])
    for a, b, want in (("p", "q", "p*q = 0"), ("p", "p", "p^2 = 0")):
        ls = [Var(a), Var(b), Const(0.0)]
        assert templated(ls, None, None, 6, {}) == plain(ls, None, None, 6, {}) == want
    plain, templated = _printers(_shape(Equation(cases[5][0], cases[5][1], "p", "g",
                                                 None))[0])
    for a, want in (("p", "p*(-2) = 0"), ("(-2)", "(-2)^2 = 0")):
        ls = [Var(a), Const(-2.0), Const(0.0)]
        assert templated(ls, None, None, 6, {}) == plain(ls, None, None, 6, {}) == want
    plain, templated = _printers(_shape(Equation(cases[6][0], cases[6][1], "p", "g",
                                                 None))[0])
    for a, want in (("p", "2^2*p = 0"), ("2^2", "2^2^2 = 0")):
        ls = [Const(2.0), Const(2.0), Var(a), Const(0.0)]
        assert templated(ls, None, None, 6, {}) == plain(ls, None, None, 6, {}) == want


def test_other_numbers_and_other_precisions_are_printed_as_the_printer():
    lhs = Mul((Const(-1.0), Known("e", 0.5), Add((Var("a"), Var("b")))))
    key, leaves = _shape(Equation(lhs, Const(0.0), "p", "g", None))
    plain, templated = _printers(key)
    for c in (-1.0, -2.0, 2.0, 0.0, -0.0, math.nan, math.inf, -math.inf, 1e-7, 3, -1):
        ls = [Const(c)] + leaves[1:]
        assert templated(ls, None, None, 6, {}) == plain(ls, None, None, 6, {})
        assert templated(ls, None, None, 3, {}) == plain(ls, None, None, 3, {})


def _scene_equations(text: str, name: str = "x"):
    import momentum_cli.solve as S
    from momentum_cli.scene import build
    from momentum_cli.source import Source
    from momentum_cli.syntax import parse

    return S.solve_scene(build(parse(Source(name, text)))).system.equations


def _all_rows_same(eqs, seen: dict, rng) -> int:
    n = 0
    for e in eqs:
        try:
            key, leaves = _shape(e)
        except RecursionError:
            continue
        if len(key) > printer.MAX_TOKENS:
            continue
        _same_on_renamings(key, leaves, rng, n=2, seen=seen)
        n += 1
    return n


def test_every_example_equation_prints_as_the_printer():
    from momentum_cli.diagnostics import ProblemError

    seen: dict = {}
    rng = random.Random(3)
    n = 0
    for path in sorted((ROOT / "examples").rglob("*.mom")):
        try:
            eqs = _scene_equations(path.read_text(encoding="utf-8"), str(path))
        except (ProblemError, ValueError, ArithmeticError):
            continue
        n += _all_rows_same(eqs, seen, rng)
    assert n > 500


@pytest.mark.parametrize("n", [3, 40, 301])
def test_chains_and_cradles_print_as_the_printer(n):
    from test_hard import cradle_text

    from momentum_cli.bench import chain_text

    seen: dict = {}
    rng = random.Random(n)
    for text in (chain_text(n), cradle_text(n, "sequence"), cradle_text(n, "simultaneous")):
        assert _all_rows_same(_scene_equations(text), seen, rng) > 0
