"""The report's one walk printing both lines of an equation (reader.si_lines) against the
two walks it replaces: `Equation.text()` and the leaf-by-leaf numeric line (`_Sub`), in
SI in radians and in degrees (an angle's value as `(-30 deg)`), byte for byte.

Random trees (every node shape, NaN and unit numbers, kept and unknown names, angles
inside and outside functions), and every equation of the examples and of generated big
scenes, with the number caches shared across the equations as the report shares them.
"""
from __future__ import annotations

from hypothesis import given, settings
from hypothesis import strategies as st
from test_report_fast import _slow_line
from test_report_printer import NAMES, NUMBERS, TREES, _outcome

from momentum_cli.compile import Equation
from momentum_cli.expr import to_text
from momentum_cli.report.reader import Reader, _Sub, angle_names, si_lines


class _System:
    """What `is_angle` reads of a system: its unknowns' quantities."""

    def __init__(self, angles):
        self.unknowns = {n: _Unknown("angle" if n in angles else "vx") for n in
                         ("a", "b", "c", "m_rod", "rod.vx@2", "g")}


class _Unknown:
    def __init__(self, qty):
        self.qty = qty


def _slow(lhs, rhs, values, keep, sig, system, degrees):
    leaf = _Sub(values, keep, system, Reader("si", degrees), {}, {}, False).leaf
    return f"{to_text(lhs)} = {to_text(rhs)}", \
        f"{to_text(lhs, True, sig, leaf)} = {to_text(rhs, True, sig, leaf)}"


@settings(max_examples=300, deadline=None)
@given(TREES, TREES, st.dictionaries(NAMES, st.one_of(st.none(), NUMBERS)),
       st.sets(NAMES), st.sampled_from([6, 4, 1]), st.sets(NAMES), st.booleans())
def test_one_walk_equals_the_two_walks_on_random_trees(lhs, rhs, values, keep, sig, angles,
                                                       degrees):
    system = _System(angles)
    six: dict = {}
    shown = six if sig == 6 else {}
    angle = angle_names(system) if degrees else None
    want = _outcome(lambda: _slow(lhs, rhs, values, keep, sig, system, degrees))
    eq = Equation(lhs, rhs, "p", "g", None)
    for _ in range(2):  # the second time with the numbers cached by the first
        assert _outcome(lambda: si_lines(eq, values, keep, sig, six, shown, angle)) == want
    if not isinstance(_outcome(eq.text), str):  # printed already: the numeric line alone
        return
    assert _outcome(lambda: si_lines(eq, values, keep, sig, six, shown, angle)) == want


def test_one_walk_equals_the_two_walks_on_every_example_and_big_scene():
    from helpers import solved_scenes

    checked = degrees = 0
    for name, sol, keeps in solved_scenes():
        system, values = sol.system, sol.values
        integrated = {k for integ in system.integrations for k in integ.equations}
        for units in ("file", "si"):
            reader = Reader("si", bool(getattr(system.scene.file_units, "degrees", False))
                            and units == "file")
            angle = angle_names(system) if reader.degrees else None
            degrees += reader.degrees
            for sig in (6, 4):
                six: dict = {}
                shown = six if sig == 6 else {}
                for k, e in enumerate(system.equations):
                    if k in integrated:  # printed as it was integrated, not by its tree
                        continue
                    keep = keeps.get(k, set())
                    want = (to_text(e.lhs) + " = " + to_text(e.rhs),
                            _slow_line(e, values, keep, system, reader, sig))
                    fresh = Equation(e.lhs, e.rhs, e.principle, e.group, e.span)
                    assert si_lines(fresh, values, keep, sig, six, shown, angle) == want, \
                        (name, k)
                    assert want[0] == e.text()
                    checked += 1
    assert checked > 2000 and degrees > 10


def test_the_report_takes_the_walk_and_the_printers_alike(monkeypatch):
    """Whole plain reports of the examples (lazy, as a batch renders them) with every
    scene's rows through the printers (compiled at first sight), and through the one
    walk, are the same text."""
    from helpers import solved_scenes

    from momentum_cli.report import model, printer
    from momentum_cli.report.text import render

    monkeypatch.setattr(printer, "COMPILE_AFTER", 0)  # every shape's printers at once

    n = 0
    for name, sol, _keeps in solved_scenes():
        for units in ("file", "si", "us"):
            monkeypatch.setattr(model, "PRINTERS_FROM", 10**9)
            walk = render(model.build_report(name, sol, 4, units, lazy=True), 4)
            monkeypatch.setattr(model, "PRINTERS_FROM", 0)
            printed = render(model.build_report(name, sol, 4, units, lazy=True), 4)
            assert walk == printed, (name, units)
            n += 1
    assert n > 150


def test_the_checks_take_the_walks_and_the_compiled_trees_alike(monkeypatch):
    """The residual and energy checks of every example and big scene with their trees by
    treecode (compiled at first sight) and by the walks: the same checks, value for value."""
    from helpers import solved_scenes

    from momentum_cli.report import model, treecode

    monkeypatch.setattr(treecode, "COMPILE_AFTER", 0)
    n = 0
    for _name, sol, _keeps in solved_scenes():
        got = []
        for start in (10**9, 0):
            monkeypatch.setattr(model, "TREECODE_FROM", start)
            got.append([(c.name, c.status, c.detail, c.value) for c in
                        model._residual_checks(sol) + model._energy_checks(sol, 4)])
        assert got[0] == got[1]
        n += len(got[0])
    assert n > 100


def test_both_lines_with_the_numbers_placed_once_equal_each_line_alone():
    """`reader.lines_in` (a US line's numbers placed once for its two lines) against
    `symbolic_line` and `numeric_line`, on every equation of the examples, in US, SI and
    the file's units."""
    from helpers import solved_scenes

    from momentum_cli.report.reader import lines_in, numeric_line, reader_for, symbolic_line

    n = 0
    for name, sol, keeps in solved_scenes():
        system, values = sol.system, sol.values
        for units in ("us", "file", "si"):
            reader = reader_for(units, system.scene.file_units)
            for k, e in enumerate(system.equations):
                keep = keeps.get(k, set())
                want = (symbolic_line(e, system, reader, 4),
                        numeric_line(e, values, keep, system, reader, 4))
                assert lines_in(e, values, keep, system, reader, 4) == want, (name, k)
                n += 1
    assert n > 2000
