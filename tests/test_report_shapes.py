"""The report's printers compiled per shape (report/printer.py) against the walks.

Every equation of the examples and of generated big scenes, and random trees: the
symbolic line equals `Equation.text()` and the numeric line `reader.numeric_line` (SI,
radians), byte for byte, with every shape compiled at first sight.
"""
from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from test_report_printer import NAMES, NUMBERS, TREES, _outcome

from momentum_cli.compile import Equation
from momentum_cli.expr import Const, to_text
from momentum_cli.report import printer
from momentum_cli.report.reader import _si_text


@pytest.fixture
def compile_at_once(monkeypatch):
    monkeypatch.setattr(printer, "COMPILE_AFTER", 0)


def _both(eq, values, keep, sig):
    got = printer.printers(eq)
    assert got is not None
    leaves, (sym, num) = got
    return sym(leaves, None, None, 6, {}), num(leaves, values, keep, sig, {})


@settings(max_examples=300, deadline=None)
@given(TREES, TREES, st.dictionaries(NAMES, st.one_of(st.none(), NUMBERS)),
       st.sets(NAMES), st.sampled_from([6, 3, 1]))
def test_printers_of_random_trees_equal_the_walks(lhs, rhs, values, keep, sig):
    printer.COMPILE_AFTER, was = 0, printer.COMPILE_AFTER
    try:
        eq = Equation(lhs, rhs, "p", "g", None)
        got = _outcome(lambda: _both(eq, values, keep, sig))
        want_sym = _outcome(lambda: f"{to_text(lhs)} = {to_text(rhs)}")
        want_num = _outcome(lambda: f"{_si_text(lhs, values, keep, sig)[0]} = "
                                    f"{_si_text(rhs, values, keep, sig)[0]}")
        if isinstance(got, tuple):
            assert got == (want_sym, want_num)
        else:  # the same error (a complex power) from either path
            assert got in (want_sym, want_num)
    finally:
        printer.COMPILE_AFTER = was


def test_a_product_of_equal_numbers_and_a_minus_one_print_as_the_walks(compile_at_once):
    from momentum_cli.expr import Add, Mul, Var

    x = Var("x")
    for lhs in (Mul((Const(2.0), Const(2.0))), Mul((Const(-1.0), x)), Mul((Const(-1.0),)),
                Mul((Const(-2.0), x, x)), Mul(()), Add(()), Mul((Const(-1.0), Const(1.0)))):
        eq = Equation(lhs, x, "p", "g", None)
        assert _both(eq, {"x": -1.0}, set(), 6) == \
            (eq.text(), f"{_si_text(lhs, {'x': -1.0}, set(), 6)[0]} = -1")


def test_every_equation_of_the_examples_and_big_scenes_prints_as_the_walks(compile_at_once):
    from helpers import solved_scenes

    from momentum_cli.report.reader import numeric_line, reader_for

    checked = 0
    for name, sol, keeps in solved_scenes():
        system, values = sol.system, sol.values
        reader = reader_for("si", system.scene.file_units)
        integrated = {k for integ in system.integrations for k in integ.equations}
        for k, e in enumerate(system.equations):
            if k in integrated:  # printed as it was integrated, not by its tree
                continue
            keep = keeps.get(k, set())
            for sig in (6, 3):
                want = (e.text(), numeric_line(e, values, keep, system, reader, sig))
                assert _both(e, values, keep, sig) == want, (name, k)
                checked += 1
    assert checked > 1000


def test_the_report_takes_the_printers_and_the_walks_alike(monkeypatch):
    """A whole report with the printers off equals the report with them (compiled at
    first sight, and on second sight as in a run)."""
    from helpers import solve_text

    from momentum_cli.bench import chain_text
    from momentum_cli.report.model import build_report
    from momentum_cli.report.text import render

    sol = solve_text(chain_text(30), "chain.mom")
    monkeypatch.setattr(printer, "ENABLED", False)
    slow = [render(build_report("chain.mom", sol, sig, "file"), sig) for sig in (6, 4)]
    monkeypatch.setattr(printer, "ENABLED", True)
    assert render(build_report("chain.mom", sol, 6, "file"), 6) == slow[0]
    monkeypatch.setattr(printer, "COMPILE_AFTER", 0)
    assert render(build_report("chain.mom", sol, 4, "file"), 4) == slow[1]


@pytest.mark.parametrize("after", [0, 1])
def test_statements_of_long_and_short_laws_print_as_the_walks(monkeypatch, after):
    """A system law over 700 bodies (a sum too long for one shape: printed term by term)
    and the two-body laws of a sequence: the same dicts with the printers on and off."""
    from helpers import solve_text
    from test_hard import cradle_text

    from momentum_cli.bench import chain_text
    from momentum_cli.report.reader import reader_for
    from momentum_cli.report.statements import statements

    monkeypatch.setattr(printer, "COMPILE_AFTER", after)
    for text in (chain_text(700), cradle_text(12, "sequence")):
        sol = solve_text(text, "x.mom")
        system = sol.system
        reader = reader_for("file", system.scene.file_units)
        for sig in (6, 3):
            for t in system.transitions:
                monkeypatch.setattr(printer, "ENABLED", True)
                fast = statements(t, sol.values, system, reader, sig)
                monkeypatch.setattr(printer, "ENABLED", False)
                assert fast == statements(t, sol.values, system, reader, sig)
                assert fast or t.kind != "impact"


@settings(max_examples=300, deadline=None)
@given(TREES, TREES, TREES, TREES)
def test_a_shapes_matcher_lists_the_leaves_of_that_shape_only(lhs, rhs, lhs2, rhs2):
    """The matcher compiled for the shape of (lhs, rhs) gives, for any tree pair, the
    leaves `_walk` lists where the walk finds the same shape, and None elsewhere; on the
    pair itself it always matches."""
    def walked(a, b):
        toks: list = []
        leaves: list = []
        printer._walk(a, toks, leaves)
        toks.append(printer._EQ)
        printer._walk(b, toks, leaves)
        return tuple(toks), leaves

    key, leaves = walked(lhs, rhs)
    match = printer._matcher(key)
    got = match(lhs, rhs)
    assert got is not None and [id(x) for x in got] == [id(x) for x in leaves]
    key2, leaves2 = walked(lhs2, rhs2)
    got2 = match(lhs2, rhs2)
    if key2 == key:
        assert got2 is not None and [id(x) for x in got2] == [id(x) for x in leaves2]
    else:
        assert got2 is None


def test_equations_of_alternating_shapes_print_as_the_walks(compile_at_once):
    """Shapes that share their sides' top node types and sizes, in turn: each equation
    is printed by its own shape's printers (the matchers tell them apart)."""
    from momentum_cli.expr import Add, Mul, Pow, Var

    x, y = Var("x"), Var("y")
    lhss = [Add((x, Const(2.0))), Add((x, y)), Add((Mul((Const(3.0), x)), y)),
            Add((x, Pow(y, -1.0))), Add((Const(-1.0), x)), Add((x, Mul((x, Pow(y, -2.0)))))]
    values = {"x": 2.0, "y": -4.0}
    for _ in range(3):
        for lhs in lhss:
            rhs = Mul((Const(2.0), y))
            eq = Equation(lhs, rhs, "p", "g", None)
            assert _both(eq, values, set(), 6) == \
                (eq.text(), f"{_si_text(lhs, values, set(), 6)[0]} = "
                            f"{_si_text(rhs, values, set(), 6)[0]}")
