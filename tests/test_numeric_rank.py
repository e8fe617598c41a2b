"""Structure and numbers agree (issue 9, reproductions 1 and 6).

A block that structure calls determined but numbers call singular is re-analysed with
its dependent rows as checks; a structurally under-determined part is rank-revealed, so
determined quantities are answered and only the truly free ones named; an inconsistency
names every statement of its conflict. Expected numbers are closed forms derived here.
"""
from __future__ import annotations

import math
import re
from pathlib import Path

import pytest
from metamorphic import Outcome, rename, rename_map, reorder

from momentum_cli.diagnostics import ProblemError
from momentum_cli.linalg import rank_reveal
from momentum_cli.scene import build
from momentum_cli.solve import solve_scene
from momentum_cli.source import Source
from momentum_cli.syntax import parse

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
PRECISIONS = ("float", "refine", "exact")
G = 9.81


def _solve(text: str, precision: str = "float", name: str = "t.mom"):
    sol = solve_scene(build(parse(Source(name, text))), precision=precision)
    return {n: si for n, _v, _u, si in sol.answers}


def _error(text: str, precision: str = "float"):
    try:
        solve_scene(build(parse(Source("t.mom", text))), precision=precision)
    except ProblemError as exc:
        return exc.diagnostics[0]
    raise AssertionError("expected a ProblemError")


def _named(message: str) -> set[str]:
    return {w.strip(",") for w in message.split()}


# ---- reproduction 1: the ballistic pendulum, both namings ------------------------------------
PENDULUMS = ["ballistic_pendulum_pin_from_impact.mom",
             "ballistic_pendulum_pin_from_impact_rough.mom"]


@pytest.mark.parametrize("precision", PRECISIONS)
@pytest.mark.parametrize("f", PENDULUMS)
def test_ballistic_pendulum_closed_form_in_both_namings(f, precision):
    m, M, v0 = 0.010, 2.0, 400.0
    v = m * v0 / (m + M)  # momentum: the bullet and block leave together
    h = v * v / (2 * G)  # energy: they rise until they stop
    lost = 0.5 * m * v0 * v0 - 0.5 * (m + M) * v * v
    text = (EXAMPLES / f).read_text()
    swapped = text.replace("bullet", "QQQ").replace("block", "bullet").replace("QQQ", "block")
    for t in (text, swapped, reorder(text)):
        a = _solve(t, precision)
        assert math.isclose(a["block.vx@2"], v, rel_tol=1e-14)
        assert math.isclose(a["bullet.vx@2"], v, rel_tol=1e-14)
        assert math.isclose(a["rise"], h, rel_tol=1e-12)
        assert math.isclose(a["T_lost@1->2"], lost, rel_tol=1e-12)


def test_ballistic_pendulum_renamed_by_the_grammar():
    text = (EXAMPLES / PENDULUMS[0]).read_text()
    mapping = rename_map(text)
    assert sorted(mapping, key=mapping.get) == sorted(mapping, reverse=True)
    out = Outcome(rename(text, mapping))
    assert out.error is None
    assert math.isclose(out.answers[f"{mapping['block']}.vx@2"][0], 4 / 2.01, rel_tol=1e-14)


# ---- a duplicated constraint: velocities answered, only the split is free -------------------
def _without_split(name: str, drop: str) -> str:
    return (EXAMPLES / "hard" / name).read_text().replace(f", {drop}", "")


@pytest.mark.parametrize("precision", PRECISIONS)
def test_duplicate_contact_answers_the_velocities(precision):
    m, M, u, U, e = 1e-6, 1e6, 1000.0, -2.0, 0.5
    vg = (m * u + M * U - M * e * (u - U)) / (m + M)
    vb = (m * u + M * U + m * e * (u - U)) / (m + M)
    a = _solve(_without_split("bad_duplicate_contact.mom", "J_n[a]@1->2"), precision)
    assert math.isclose(a["grain.vx@2"], vg, rel_tol=1e-13)
    assert math.isclose(a["barge.vx@2"], vb, rel_tol=1e-13)


@pytest.mark.parametrize("precision", PRECISIONS)
def test_double_pin_answers_the_motion(precision):
    M, L, m, d, e, u = 1e6, 1000.0, 1e-6, 999.999, 0.5, 300.0
    I_O = M * L * L / 3
    w = (1 + e) * u / (d + I_O / (m * d))  # rotation about O; Newton's law at P
    vp = u - I_O * w / (m * d)
    a = _solve(_without_split("bad_double_pin.mom", "Jx[p1]@1->2"), precision)
    assert math.isclose(a["rod.omega@2"], w, rel_tol=1e-9)
    assert math.isclose(a["pellet.vy@2"], vp, rel_tol=1e-12)


@pytest.mark.parametrize("precision", PRECISIONS)
def test_asking_for_the_split_names_only_the_split(precision):
    d = _error((EXAMPLES / "hard" / "bad_duplicate_contact.mom").read_text(), precision)
    assert d.code == "singular"
    assert {"J_n[a]@1->2", "J_n[b]@1->2"} <= _named(d.message)
    assert not {"grain.vx@2", "barge.vx@2"} & _named(d.message)


def test_structural_under_determination_stays_when_numbers_agree():
    d = _error((EXAMPLES / "hard" / "bad_restitution_unknown.mom").read_text())
    assert d.code == "under-determined"
    assert _named(d.message) >= {"e[hit]", "J_n[hit]@1->2", "grain.vx@2", "barge.vx@2"}


# ---- reproduction 6: every statement of the conflict ------------------------------------------
def test_inconsistent_restitution_speed_names_every_statement():
    text = (EXAMPLES / "hard" / "bad_inconsistent_restitution_speed.mom").read_text()
    for precision in PRECISIONS:
        d = _error(text, precision)
        assert d.code == "inconsistent"
        note = next(n for n in d.notes if n.startswith("the conflicting statements"))
        lines = {int(x) for x in re.findall(r"line (\d+)", note)}
        # the initial velocities, the stated speed, momentum, restitution
        assert lines == {11, 12, 14, 15}, note


def test_inconsistent_restitution_speed_golden():
    """The error as the golden `.err` (written by test_bad_values.py, which owns every
    bad_* file's golden) shows it: the diagnostic comes first, then the `expect` note."""
    path = EXAMPLES / "hard" / "bad_inconsistent_restitution_speed.mom"
    source = Source(f"examples/hard/{path.name}", path.read_text())
    try:
        solve_scene(build(parse(source)))
    except ProblemError as exc:
        got = exc.diagnostics[0].format(source) + "\n"
    assert path.with_suffix(".err").read_text(encoding="utf-8").startswith(got)


# ---- the rank tool ----------------------------------------------------------------------------
def test_rank_reveal_scale_is_no_dependency():
    # masses twelve decades apart: independent rows, however small the remainder
    rows = [{0: 1e-6, 1: 1.0}, {0: 1e6, 1: 1.0}]
    for exact in (False, True):
        rr = rank_reveal(rows, [1.0, 2.0], 2, exact=exact)
        assert not rr.dependent and not rr.free


def test_rank_reveal_finds_a_dependency_and_its_rows():
    # row 2 = 3 row 0 - row 1 (rounded data still cancels to round-off)
    a, b = [0.1, 0.7, 0.3], [0.2, -0.3, 0.9]
    c = [3 * x - y for x, y in zip(a, b)]
    rows = [dict(enumerate(r)) for r in (a, b, c)]
    rr = rank_reveal(rows, [1.0, 1.0, 2.0], 3)
    assert [i for i, _, _ in rr.dependent] == [2]
    assert set(rr.dependent[0][1]) == {0, 1, 2}  # its left null vector: all three rows
    assert rr.free == [0, 1, 2]
    assert abs(rr.dependent[0][2]) > 0  # 2 != 3*1 - 1: inconsistent right-hand side
    # the same rows in rationals: exactly dependent only if the data is
    exact = rank_reveal([{0: 1.0, 1: 2.0}, {0: 2.0, 1: 4.0}], [1.0, 2.0], 2, exact=True)
    assert [i for i, _, _ in exact.dependent] == [1] and exact.dependent[0][2] == 0
