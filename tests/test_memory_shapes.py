"""The thirteenth session's memory cuts hold what they held before: the shared empty
hints list (records.EMPTY_LIST) cannot be added to and reads as `[]`; a packed
structure (`Structure.pack`, arrays for the walk's integer lists) gives the blocks, the
matching and each unknown's block the unpacked one gives; the report's rows (their roles,
the unknowns their block solves) are those of rows built from the blocks directly."""
from __future__ import annotations

import copy
import pickle
import sys
from pathlib import Path

import pytest

from momentum_cli import analyse as A
from momentum_cli.bench import chain_text
from momentum_cli.records import EMPTY_LIST, FrozenEmptyList
from momentum_cli.report.model import build_report
from momentum_cli.scene import build
from momentum_cli.solve import solve_scene
from momentum_cli.source import Source
from momentum_cli.syntax import parse

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tests"))
from test_hard import cradle_text  # noqa: E402

EXAMPLES = sorted((ROOT / "examples").rglob("*.mom"))


def _solved(text: str):
    return solve_scene(build(parse(Source("x.mom", text))))


def test_the_shared_empty_list_reads_as_an_empty_list_and_cannot_grow():
    assert EMPTY_LIST == [] and repr(EMPTY_LIST) == "[]" and not EMPTY_LIST
    assert list(EMPTY_LIST) == [] and len(EMPTY_LIST) == 0
    for grow in (lambda x: x.append(1), lambda x: x.extend([1]), lambda x: x.insert(0, 1),
                 lambda x: x.__iadd__([1]), lambda x: x.__setitem__(slice(0, 0), [1])):
        with pytest.raises(TypeError):
            grow(EMPTY_LIST)
    assert EMPTY_LIST == []  # still empty
    assert EMPTY_LIST + [1] == [1]  # a new list, as `[] + [1]`
    again = pickle.loads(pickle.dumps(EMPTY_LIST))
    assert type(again) is FrozenEmptyList and again == []
    assert copy.deepcopy(EMPTY_LIST) == []


@pytest.mark.parametrize("text", [chain_text(30), cradle_text(8, "sequence")])
def test_unknowns_of_a_scene_without_hints_share_the_empty_list(text):
    """Hint-free states' unknowns share it; impulses (a `> 0` hint each) have their own
    lists; the solve reads them as before (the values of the general path: hints off
    the shortcuts are the same numbers, the text the same)."""
    sol = _solved(text)
    us = list(sol.system.unknowns.values())
    states = [u for u in us if u.kind == "state"]
    assert states and all(u.hints is EMPTY_LIST for u in states)
    impulses = [u for u in us if u.kind == "impulse"]
    assert impulses and all(type(u.hints) is list and len(u.hints) == 1 for u in impulses)


def test_a_scene_with_hints_gives_its_unknowns_their_own_lists():
    text = (ROOT / "examples").joinpath("ball_bounce_rebound.mom")
    sol = _solved(text.read_text(encoding="utf-8"))
    assert any(u.hints and u.hints is not EMPTY_LIST for u in sol.system.unknowns.values())


def _system(text):
    from momentum_cli.compile import compile_scene

    return compile_scene(build(parse(Source("t.mom", text))))


@pytest.mark.parametrize("text", [chain_text(n) for n in (3, 700)] +
                         [cradle_text(n, k) for n in (4, 400)
                          for k in ("sequence", "simultaneous")])
def test_a_packed_structure_answers_as_the_unpacked_one(text, monkeypatch):
    """Packed (from any size: PACK_FROM lowered), the structure's lazily made dicts and
    its needed blocks are those of the same structure unpacked."""
    monkeypatch.setattr(A, "PACK_FROM", 0)
    system = _system(text)
    names = list(system.unknowns) + ["nobody.vx@1"]
    plain, packed = A.analyse(system), A.analyse(system)
    packed.pack()
    assert all(type(x).__name__ == "array" for i, x in enumerate(packed._walk) if i not in (4, 5))
    for ask in [[n] for n in names[::7]] + [names[::3], names]:
        assert packed.needed_blocks(ask) == plain.needed_blocks(ask)
    assert list(packed.match_eq.items()) == list(plain.match_eq.items())
    assert list(packed.match_var.items()) == list(plain.match_var.items())
    assert list(packed.block_of_var.items()) == list(plain.block_of_var.items())


def test_a_small_structure_is_left_as_it_is():
    st = A.analyse(_system(chain_text(3)))
    walk = st._walk
    st.pack()
    assert st._walk is walk


def _rows_by_blocks(sol, rep):
    """Each row's role and the unknowns its block solves, from the blocks and the
    structure directly (what build_report's dicts held before)."""
    st = sol.structure
    block_of = {k: b for b in sol.blocks for k in b.equations}
    checked = set(st.redundant) | set(st.constant_eqs)
    want = []
    for k in range(len(sol.system.equations)):
        b = block_of.get(k)
        role = "solved" if b is not None else "check" if k in checked else \
            "undetermined" if k in st.under_eqs else "not needed"
        want.append((k, role, list(b.unknowns) if b is not None else []))
    got = [(r.index, r.role, list(r.solves)) for t in rep.transitions for r in t["equations"]]
    got += [(r.index, r.role, list(r.solves)) for rows in rep.other_equations.values() for r in rows]
    return sorted(got), sorted(want)


@pytest.mark.parametrize("path", EXAMPLES[::4], ids=lambda p: p.name)
def test_report_rows_have_the_roles_and_block_unknowns_of_the_blocks(path):
    from momentum_cli.diagnostics import ProblemError

    try:
        sol = _solved(path.read_text(encoding="utf-8"))
    except ProblemError:
        pytest.skip("does not solve")
    rep = build_report("x.mom", sol, 6, "file", lazy=False)
    got, want = _rows_by_blocks(sol, rep)
    assert got == want


@pytest.mark.parametrize("text", [chain_text(40), cradle_text(12, "sequence")])
def test_report_rows_of_big_scenes_too(text):
    sol = _solved(text)
    got, want = _rows_by_blocks(sol, build_report("x.mom", sol, 6, "file", lazy=False))
    assert got == want and len(got) == len(sol.system.equations)


@pytest.mark.parametrize("text", [chain_text(600), cradle_text(300, "sequence")])
def test_bodies_drawn_alike_share_one_outline_equal_to_their_own(text, monkeypatch):
    """A big file's bodies drawn alike share one outline tuple; the scene's bodies equal
    those the builder makes without its memos (each body its own tuple)."""
    from momentum_cli import scene as SC

    shared = build(parse(Source("x.mom", text)))
    monkeypatch.setattr(SC, "CONTACT_MEMO", False)
    own = build(parse(Source("x.mom", text)))
    assert list(shared.bodies.values()) == list(own.bodies.values())
    assert len({id(b.outline) for b in shared.bodies.values()}) < len(shared.bodies) // 2
    assert len({id(b.outline) for b in own.bodies.values()}) == len(own.bodies)
