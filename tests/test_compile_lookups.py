"""The compile's direct lookups equal the general ones: the state chains' break positions
built as tuples (aliases.StateChains.build) equal the sorted lists of every position, and
a velocity found on a chain in one call (compile._on_chain_v, its unknown made inline)
makes the same system as two calls of `sv`, node for node and in the same column order,
on every example and on generated scenes (long sequences, states out of file order, a
body in many impacts, velocities given late)."""
from __future__ import annotations

from pathlib import Path

import pytest

from momentum_cli.tracks import VELOCITIES
from momentum_cli.bench import chain_text
from structure_dump import system_lines
from test_hard import cradle_text

ROOT = Path(__file__).resolve().parent.parent


def _bouncing(n: int, reverse: bool, late_given) -> str:
    """Two balls struck n times in a row (each ball in every impact), states written in
    file order or reversed, the last state's velocity of `a` given or not (or only its
    x component: vx and vy then break at different states)."""
    states = [f'state {k}' for k in range(2, n + 2)]
    if late_given == "vx":
        states[-1] += ": a.vx = 0.1 m/s"
    elif late_given:
        states[-1] += ": a.v = (0.1 m/s, 0)"
    if reverse:
        states.reverse()
    impacts = "\n".join(f"impact {k} -> {k + 1}:\n"
                        f"    contact c{k}: b with a normal (1, 0): restitution 0.5, smooth"
                        for k in range(1, n + 1))
    return ('problem "bouncing"\nbody a: particle(mass = 1 kg)\n'
            'body b: particle(mass = 2 kg)\n'
            'state 1: a.v = (2 m/s, 0), b at rest\n' + "\n".join(states) + "\n" +
            impacts + f"\nfind a.vx@{n + 1}, b.vx@{n + 1}, T_lost@1->2\n")


# a's velocity after the first impact is given only at the state after the second, which
# does not move it: the head of a's velocity at state 2 is state 3's given value
_GIVEN_FORWARD = '''problem "given later"
body a: particle(mass = 1 kg)
body b: particle(mass = 2 kg)
body c: particle(mass = 3 kg)
state 1: a.v = (1 m/s, 0), b at rest, c at rest
state 2
state 3: a.v = (-0.2 m/s, 0)
impact 1 -> 2:
    contact ab: b with a normal (1, 0): restitution ?, smooth
impact 2 -> 3:
    contact bc: c with b normal (1, 0): restitution 0.5, smooth
find b.vx@2, c.vx@3, e[ab]
'''


def _texts():
    out = [(str(p.relative_to(ROOT)), p.read_text(encoding="utf-8"))
           for p in sorted((ROOT / "examples").glob("*.mom"))]
    out += [("chain", chain_text(60)), ("cradle", cradle_text(40, "sequence")),
            ("cradle together", cradle_text(12, "simultaneous"))]
    out += [("given forward", _GIVEN_FORWARD)]
    out += [(f"bouncing {n} {r} {g}", _bouncing(n, r, g))
            for n in (3, 9, 20) for r in (False, True) for g in (False, True, "vx")]
    return out


TEXTS = _texts()


def _scene(text: str, name: str):
    from momentum_cli.scene import build
    from momentum_cli.source import Source
    from momentum_cli.syntax import parse

    return build(parse(Source(name, text)))


def _reference_breaks(states, into, busy, where, bodies) -> dict:
    """StateChains.build's positions as it first made them: lists, sorted, then tuples
    (a particle's omega, always 0, has none where it is moved)."""
    breaks: dict = {}
    for sid, st in states.items():
        c, p = where[sid]
        for (b, q) in st.givens:
            breaks.setdefault((b, q, c), []).append(p)
    for sid, ts in into.items():
        c, p = where[sid]
        for b in busy[ts[0].key]:
            for q in VELOCITIES:
                if q == "omega" and b in bodies and bodies[b].is_particle:
                    continue
                breaks.setdefault((b, q, c), []).append(p)
    return {k: tuple(sorted(v)) for k, v in breaks.items()}


@pytest.mark.parametrize("name,text", TEXTS, ids=[n for n, _ in TEXTS])
def test_chain_breaks_equal_sorted_lists(name, text):
    from momentum_cli.compile import _Compiler
    from momentum_cli.diagnostics import ProblemError

    try:
        comp = _Compiler(_scene(text, name), {})
        comp._positions()
    except ProblemError:
        return
    chains = comp._chains
    if chains is None:
        return
    ref = _reference_breaks(comp.scene.states, comp._into, comp._busy, chains.where,
                            comp.scene.bodies)
    got = {(b, q, c): pts for b, tr in chains.tracks.items() for (q, c), pts in tr.breaks.items()}
    assert got == ref
    assert all(type(v) is tuple for v in got.values())


def _lines(text: str, name: str) -> list[str]:
    from momentum_cli.compile import compile_scene
    from momentum_cli.diagnostics import ProblemError

    try:
        system = compile_scene(_scene(text, name))
    except ProblemError as exc:
        return [f"error {exc}"]
    out = system_lines(system)
    out += [f"{e.principle}: {e.text()}" for e in system.equations]
    out += [repr(list(system.unknowns))]
    out += [repr((u.kind, u.state, u.body, u.qty, u.hints)) for u in system.unknowns.values()]
    return out


@pytest.mark.parametrize("name,text", TEXTS, ids=[n for n, _ in TEXTS])
def test_velocity_on_a_chain_equals_two_calls_of_sv(name, text, monkeypatch):
    """Also a velocity after the impact that moves the body (moved_vel): as vel."""
    import momentum_cli.compile as C

    fast = _lines(text, name)
    with monkeypatch.context() as m:
        m.setattr(C._Compiler, "_on_chain_v", lambda self, body, sid, w: C.V2(
            self.sv(body, "vx", sid), self.sv(body, "vy", sid)))
        m.setattr(C._Compiler, "moved_vel", C._Compiler.vel)
        slow = _lines(text, name)
    assert fast == slow


def test_a_body_in_many_impacts_keeps_its_breaks_sorted():
    """A body in more impacts than a short tuple holds: its positions become a list,
    then one sorted tuple (no quadratic copies), with states written in reverse."""
    from momentum_cli.compile import _Compiler

    comp = _Compiler(_scene(_bouncing(20, True, True), "b"), {})
    comp._positions()
    pts = comp._chains.tracks["a"].breaks[("vx", 0)]
    assert pts == tuple(sorted(pts)) and len(pts) == 21 + 1  # given at 1 and 21, busy 2..21


_BRANCHES = '''problem "one ball struck two ways"
body a: particle(mass = 1 kg)
body b: particle(mass = 2 kg)
body c: particle(mass = 1 kg)
state 1: a.v = (1 m/s, 0), b at rest, c at rest
state 2
state 3
impact 1 -> 2:
    contact ab: b with a normal (1, 0): restitution 1, smooth
impact 1 -> 3:
    contact ac: c with a normal (1, 0): restitution 1, smooth
find a.vx@2, b.vx@2, c.vx@2, a.vx@3, b.vx@3, c.vx@3
'''


def test_states_that_branch_share_the_nodes_of_what_they_keep():
    """Two transitions out of one state: no chains, so the walk finds each quantity's
    state (its node kept in the body's record). A body an impact does not touch keeps
    the node of the state before; the answers are the elastic closed forms."""
    from helpers import answers

    from momentum_cli.compile import _Compiler

    comp = _Compiler(_scene(_BRANCHES, "branches"), {})
    system = comp.run()
    assert comp._chains is None
    for body, sid in (("c", "2"), ("b", "3")):
        for q in ("vx", "vy"):
            assert comp.sv(body, q, sid) is comp.sv(body, q, "1")
            assert f"{body}.{q}@{sid}" not in system.unknowns
    assert comp.vel("a", "2") is comp.vel("a", "2")
    got = answers(_BRANCHES)
    # elastic: v_a' = (m_a - m) / (m_a + m) v, v' = 2 m_a / (m_a + m) v
    want = {"a.vx@2": -1 / 3, "b.vx@2": 2 / 3, "c.vx@2": 0.0,
            "a.vx@3": 0.0, "b.vx@3": 0.0, "c.vx@3": 1.0}
    for k, v in want.items():
        assert abs(got[k] - v) < 1e-12, k


def test_a_velocity_given_later_is_the_head_of_the_states_before():
    """a's velocity after the first impact is given at the state after the second (which
    does not move a): momentum and the restitution's definition give b, e and c."""
    from helpers import answers

    got = answers(_GIVEN_FORWARD)
    vb = (1.0 * 1.0 - 1.0 * (-0.2)) / 2.0  # m_a v_a = m_a v_a' + m_b v_b'
    e = (vb - (-0.2)) / 1.0
    vc = 2.0 * vb * (1 + 0.5) / (2.0 + 3.0)
    for k, v in (("b.vx@2", vb), ("e[ab]", e), ("c.vx@3", vc)):
        assert abs(got[k] - v) < 1e-12, k
