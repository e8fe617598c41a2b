"""Stages 3-4: the equations derived from a scene, and their structure."""
from __future__ import annotations

from momentum_cli.analyse import analyse
from momentum_cli.compile import compile_scene
from momentum_cli.scene import build
from momentum_cli.source import Source
from momentum_cli.syntax import parse

ROD_DROP = """
gravity 9.81 m/s^2 down
body rod: rod(mass = 10 kg, length = 1 m)
point A = rod.end(-)
state 2: rod.angle = 30 deg, rod.v = (0, -4 m/s), rod.omega = 0
state 3
impact 2 -> 3:
    contact A with ground normal (0, 1): restitution 1, smooth
find rod.omega@3
"""


def system(text):
    return compile_scene(build(parse(Source("t.mom", text))))


def test_an_impact_gives_momentum_in_x_and_y_angular_momentum_and_restitution():
    s = system(ROD_DROP)
    principles = [e.principle for e in s.equations]
    assert "linear impulse-momentum x: rod" in principles
    assert "linear impulse-momentum y: rod" in principles
    assert "angular impulse-momentum about G: rod" in principles
    assert "restitution at A (Newton)" in principles
    assert set(s.unknowns) == {"rod.vx@3", "rod.vy@3", "rod.omega@3", "J_n[A]@2->3"}


def test_a_smooth_contact_has_no_tangential_impulse_and_the_why_says_so():
    s = system(ROD_DROP)
    assert not any(n.startswith("J_t") for n in s.unknowns)
    why = s.transitions[0].why[0]
    assert "conserved along (-1, 0)" in why and "about A" in why


def test_positions_do_not_change_in_an_impact():
    s = system(ROD_DROP)
    # the angle at state 3 is the given angle at state 2, not an unknown
    assert "rod.angle@3" not in s.unknowns
    assert any("rod.angle@2" in e.text() for e in s.equations)


def test_equations_remember_their_source_line():
    s = system(ROD_DROP)
    restitution = next(e for e in s.equations if e.principle.startswith("restitution"))
    assert restitution.span.line == 8


def test_structure_is_square_and_solved_as_one_coupled_block():
    st = analyse(system(ROD_DROP))
    assert not st.under and not st.redundant
    sizes = sorted(len(b.unknowns) for b in st.blocks)
    assert sizes == [1, 3]  # vx@3 alone; omega, vy and J_n coupled


def test_missing_restitution_leaves_the_impact_under_determined():
    text = ROD_DROP.replace("restitution 1, smooth", "restitution ?, smooth")
    st = analyse(system(text))
    assert {"rod.omega@3", "rod.vy@3", "J_n[A]@2->3", "e[A]"} <= st.under


def test_a_redundant_stated_principle_becomes_a_check_not_a_block():
    text = ROD_DROP + "conserve momentum x of {rod} over 2 -> 3\n"
    s = system(text)
    st = analyse(s)
    stated = [k for k, e in enumerate(s.equations) if e.kind == "stated"]
    assert stated and all(k in st.redundant for k in stated)


def test_a_stated_principle_that_does_not_hold_is_reported_and_dropped():
    text = ROD_DROP + "conserve momentum y of {rod} over 2 -> 3\n"
    s = system(text)
    assert s.invalid_stated and "not conserved" in s.invalid_stated[0][1]
    assert not any(e.kind == "stated" for e in s.equations)


def test_blocks_come_in_dependency_order():
    st = analyse(system(ROD_DROP))
    seen: set[int] = set()
    for b in st.blocks:
        assert b.depends <= seen
        seen.add(b.index)
