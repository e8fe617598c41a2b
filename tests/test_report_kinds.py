"""A transition's report by its compiled kind (`TransitionInfo.kind_id`, handed down by
compile's impact_phase: what a kind shares made once, names and numbers filled in)
against the full path: the same plain text, streamed and whole (full, brief, 4 figures)
and the same diagrams' lines, byte for byte, on every example, generated chains, cradles
(sequence and simultaneous), scenegen scenes, and impacts of one kind that differ in a
sign, a zero, a restitution or a point."""
from __future__ import annotations

import sys
from pathlib import Path

import pytest

from momentum_cli import impact_phase
from momentum_cli.bench import chain_text
from momentum_cli.report import diagram, text
from momentum_cli.report.model import build_report
from momentum_cli.scene import build
from momentum_cli.solve import ProblemError, solve_scene
from momentum_cli.source import Source
from momentum_cli.syntax import parse

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tests"))
from test_hard import cradle_text  # noqa: E402

EXAMPLES = sorted(p for p in (ROOT / "examples").glob("*.mom"))
SWITCHES = ((diagram, "KINDS"),)  # every per-kind shortcut of the report


def _texts(sol, name: str) -> list:
    out = []
    for lazy in (True, False):
        rep = lambda: build_report(name, sol, 6, "file", lazy=lazy)  # noqa: E731
        out += ["\n".join(text.render_parts(rep(), 6)), text.render(rep(), 6, detail="brief"),
                text.render(rep(), 4)]
    return out


def _same(text_: str, monkeypatch, name: str = "x.mom") -> bool:
    try:
        sol = solve_scene(build(parse(Source(name, text_))))
    except ProblemError:
        return False
    got = []
    for on in (True, False):
        for mod, flag in SWITCHES:
            monkeypatch.setattr(mod, flag, on)
        got.append(_texts(sol, name))
    assert got[0] == got[1]
    return True


def _kinds(text_: str) -> list:
    sol = solve_scene(build(parse(Source("x.mom", text_))))
    return [t.kind_id for t in sol.system.transitions]


@pytest.mark.parametrize("path", EXAMPLES, ids=lambda p: p.name)
def test_examples_by_kind_equal_the_full_path(path, monkeypatch):
    _same(path.read_text(encoding="utf-8"), monkeypatch, str(path))


def test_big_scenes_by_kind_equal_the_full_path(monkeypatch):
    assert _same(chain_text(30), monkeypatch)
    for kind in ("sequence", "simultaneous"):
        assert _same(cradle_text(12, kind), monkeypatch)


def test_random_scenes_by_kind_equal_the_full_path(monkeypatch):
    import scenegen

    n = 0
    for cat in scenegen.categories():
        for seed in range(4):
            sc = scenegen.generate(seed, cat)
            if sc is not None and _same(scenegen.render(sc), monkeypatch):
                n += 1
    assert n > 20


# impacts of one kind (the same normals, radii, restitution and bodies by index) whose
# numbers differ where the text must show it: a zero impulse (no impulse on a body), a
# negative velocity, a zero velocity; and a second kind (another restitution, a wall)
# between them
_MIXED = """problem "impacts of one kind, different numbers"

body b1: particle(mass = 1 kg, radius = 10 mm)
body b2: particle(mass = 2 kg, radius = 10 mm)
body b3: particle(mass = 3 kg, radius = 10 mm)
body b4: particle(mass = 1 kg, radius = 10 mm)
body b5: particle(mass = 1 kg, radius = 10 mm)
body b6: particle(mass = 1 kg, radius = 10 mm)
body b7: particle(mass = 1 kg, radius = 10 mm)

state 1: b1.v = (2 m/s, 0), b2.v = (-1 m/s, 0.5 m/s), b3 at rest, b4.v = (-2 m/s, 0), b5.v = (-2 m/s, 0), b6.v = (5 m/s, -1 m/s), b7.v = (0, -3 m/s)
state 2
state 3
state 4
state 5
state 6
state 7
state 8

impact 1 -> 2:
    contact k1: b2 with b1 normal (1, 0): restitution 0.5, smooth
impact 2 -> 3:
    contact k2: b3 with b2 normal (1, 0): restitution 0.5, smooth
impact 3 -> 4:
    contact k3: b4 with b3 normal (1, 0): restitution 0.5, smooth
impact 4 -> 5:
    contact k4: b5 with b4 normal (1, 0): restitution 0.5, smooth
impact 5 -> 6:
    contact k5: b6 with b5 normal (1, 0): restitution 0, smooth
impact 6 -> 7:
    contact k6: b7 with b6 normal (1, 0): restitution 0, smooth
impact 7 -> 8:
    contact k7: b7 with ground normal (0, 1): restitution 0.5, smooth

find b1.vx@8, b2.vx@8, b3.vx@8, b4.vx@8, b5.vx@8, b6.vx@8, b7.vy@8
"""


def test_one_kind_with_different_numbers_equals_the_full_path(monkeypatch):
    ids = _kinds(_MIXED)
    assert all(k is not None for k in ids)
    assert ids[1] == ids[2] == ids[3]  # one kind, other numbers: the shortcut is taken
    assert ids[4] != ids[3] and ids[6] != ids[3]  # another restitution, a wall: other kinds
    assert _same(_MIXED, monkeypatch)


def test_kind_ids_are_handed_down_only_by_the_whole_impact_path(monkeypatch):
    """One number per plan: two impacts share it only if compile replayed both from one
    plan (the same whole-impact key); the contact-by-contact path hands down none."""
    cradle = cradle_text(6, "sequence")
    ids = _kinds(cradle)
    assert len(set(ids)) <= 2 and None not in ids
    monkeypatch.setattr(impact_phase, "TEMPLATE", False)
    assert set(_kinds(cradle)) == {None}


# impacts of round and point particles (a kind's gaps between its bodies are its radii;
# a particle's only point is its centre), kinds met again after others
_POINTS = """problem "kinds of round and point particles"

body p1: particle(mass = 1 kg, radius = 50 mm)
body p2: particle(mass = 1 kg)
body p3: particle(mass = 1 kg, radius = 50 mm)
body p4: particle(mass = 1 kg)
body p5: particle(mass = 1 kg, radius = 50 mm)

state 1: p1.v = (1 m/s, 0), p2 at rest, p3 at rest, p4 at rest, p5 at rest
state 2
state 3
state 4
state 5

impact 1 -> 2:
    contact k1: p2 with p1 normal (1, 0): restitution 0.5, smooth
impact 2 -> 3:
    contact k2: p3 with p2 normal (1, 0): restitution 0.5, smooth
impact 3 -> 4:
    contact k3: p4 with p3 normal (1, 0): restitution 0.5, smooth
impact 4 -> 5:
    contact k4: p5 with p4 normal (1, 0): restitution 0.5, smooth

find p5.vx@5
"""


def test_kinds_of_round_and_point_particles_equal_the_full_path(monkeypatch):
    ids = _kinds(_POINTS)
    assert None not in ids and len(set(ids)) < len(ids)  # a kind met twice
    assert _same(_POINTS, monkeypatch)
