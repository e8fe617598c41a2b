"""Large systems: a body untouched by a transition keeps its state (one variable across
it, found by aliases.StateChains), so a sequence of N impacts costs O(N) unknowns and
equations; the fast alias lookup gives the same system as the state-by-state walk; and
`solve --json` streams a document identical to the one built in memory.
Counts, not times: speed is measured by `momentum bench large` (bench/large.py)."""
from __future__ import annotations

import glob
import io
import json
import os

import pytest

from momentum_cli.aliases import StateChains
from momentum_cli.compile import compile_scene
from momentum_cli.expr import to_text
from momentum_cli.scene import build
from momentum_cli.solve import solve_scene
from momentum_cli.source import Source
from momentum_cli.syntax import parse

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def sequential_cradle(masses, e, v0=2.0, finds=None) -> str:
    """Balls in a row, b1 moving at v0, the others at rest; impact k -> k+1 is b_k on
    b_{k+1} alone, restitution e."""
    n = len(masses)
    lines = ['problem "sequential cradle"']
    lines += [f"body b{k}: particle(mass = {m!r} kg)" for k, m in enumerate(masses, 1)]
    rest = ", ".join(f"b{k} at rest" for k in range(2, n + 1))
    lines.append(f"state 1: b1.v = ({v0} m/s, 0), {rest}")
    lines += [f"state {k}" for k in range(2, n + 1)]
    lines += [f"impact {k} -> {k + 1}:\n    contact b{k + 1} with b{k} normal (1, 0): "
              f"restitution {e}" for k in range(1, n)]
    lines.append("find " + ", ".join(finds or [f"b{k}.vx@{n}" for k in range(1, n + 1)]))
    return "\n".join(lines) + "\n"


def closed_form(masses, e, v0=2.0) -> list[list[float]]:
    """Velocities of every ball at states 1..n: each impact is the two-body law
    v1' = (m1 v1 + m2 v2 - m2 e (v1 - v2)) / (m1 + m2), v2' = v1' + e (v1 - v2)."""
    v = [v0] + [0.0] * (len(masses) - 1)
    states = [list(v)]
    for k in range(len(masses) - 1):
        m1, m2, a, b = masses[k], masses[k + 1], v[k], v[k + 1]
        v[k] = (m1 * a + m2 * b - m2 * e * (a - b)) / (m1 + m2)
        v[k + 1] = v[k] + e * (a - b)
        states.append(list(v))
    return states


def _solve(text: str):
    return solve_scene(build(parse(Source("cradle.mom", text))))


def _answers(sol) -> dict[str, float]:
    return {str(name): si for name, _v, _u, si in sol.answers}


def test_five_ball_cradle_passes_the_velocity_along():
    """Equal masses, e = 1: after impact k ball k is at rest and ball k+1 has v0."""
    n = 5
    finds = [f"b{k}.vx@{s}" for s in range(1, n + 1) for k in range(1, n + 1)]
    got = _answers(_solve(sequential_cradle([0.1] * n, 1, finds=finds)))
    for s in range(1, n + 1):
        for k in range(1, n + 1):
            want = 2.0 if k == s else 0.0
            assert got[f"b{k}.vx@{s}"] == pytest.approx(want, abs=1e-12), (k, s)


def test_unequal_cradle_matches_the_two_body_law_at_every_state():
    """Aliased quantities (b4 at state 2 is b4 at state 1; b1 at state 5 is b1 at 2)
    answer `find` exactly as their own states would."""
    masses, e, n = [1.0, 2.0, 0.5, 3.0, 1.5], 0.8, 5
    finds = [f"b{k}.vx@{s}" for s in range(1, n + 1) for k in range(1, n + 1)]
    got = _answers(_solve(sequential_cradle(masses, e, finds=finds)))
    want = closed_form(masses, e)
    for s in range(1, n + 1):
        for k in range(1, n + 1):
            assert got[f"b{k}.vx@{s}"] == pytest.approx(want[s - 1][k - 1], rel=1e-12,
                                                        abs=1e-12), (k, s)


def test_momentum_is_conserved_through_the_sequence():
    masses, e, n = [1.0, 2.0, 0.5, 3.0, 1.5, 0.7], 0.6, 6
    got = _answers(_solve(sequential_cradle(masses, e)))
    p = sum(m * got[f"b{k}.vx@{n}"] for k, m in enumerate(masses, 1))
    assert p == pytest.approx(masses[0] * 2.0, rel=1e-12)


def _counts(n: int) -> tuple[int, int]:
    system = compile_scene(build(parse(Source("c.mom", sequential_cradle([0.1] * n, 1)))))
    return len(system.unknowns), len(system.equations)


def test_unknowns_and_equations_grow_linearly_with_the_impacts():
    """Each two-ball impact adds the same few unknowns and equations, whatever N."""
    (u1, e1), (u2, e2), (u4, e4) = _counts(20), _counts(40), _counts(80)
    assert u4 - u2 == 2 * (u2 - u1)
    assert e4 - e2 == 2 * (e2 - e1)
    # two balls' vx and vy after each impact, and its contact impulse(s): a handful per ball
    assert u4 <= 8 * 80 and e4 <= 8 * 80


def test_untouched_body_has_no_unknown_at_later_states():
    system = compile_scene(build(parse(Source("c.mom", sequential_cradle([0.1] * 6, 1)))))
    names = set(system.unknowns)
    assert "b6.vx@2" not in names and "b6.vx@3" not in names  # b6 keeps its given rest
    assert "b1.vx@2" in names and "b1.vx@3" not in names  # b1 moves only in impact 1 -> 2


def _system_text(text: str, name: str):
    system = compile_scene(build(parse(Source(name, text))))
    return (sorted(system.unknowns), [e.text() for e in system.equations],
            [(f.name, to_text(f.expr)) for f in system.finds])


EXAMPLES = sorted(p for p in glob.glob(os.path.join(ROOT, "examples", "**", "*.mom"),
                                       recursive=True) if os.path.getsize(p) < 20_000)


@pytest.mark.parametrize("path", EXAMPLES)
def test_fast_aliases_give_the_same_system_as_the_walk(path, monkeypatch):
    """The binary search along state chains and the state-by-state walk agree on every
    example that compiles (the same unknowns, equations and find specs)."""
    text = open(path, encoding="utf-8").read()
    try:
        fast = _system_text(text, path)
    except Exception:  # a file that does not compile: nothing to compare
        pytest.skip("does not compile")
    monkeypatch.setattr(StateChains, "build", classmethod(lambda cls, *a: None))
    assert _system_text(text, path) == fast


def test_branching_states_fall_back_to_the_walk():
    """Two transitions out of one state are not a chain: no StateChains."""
    from momentum_cli.scene import build as build_scene

    text = ('problem "branch"\nbody a: particle(mass = 1 kg)\nbody b: particle(mass = 1 kg)\n'
            "state 1: a.v = (1 m/s, 0), b at rest\nstate 2\nstate 3\n"
            "impact 1 -> 2:\n    contact b with a normal (1, 0): restitution 1\n"
            "impact 1 -> 3:\n    contact b with a normal (1, 0): restitution 0\n"
            "find b.vx@2, b.vx@3, a.vx@3\n")
    sc = build_scene(parse(Source("b.mom", text)))
    into = {}
    out = {}
    for t in sc.transitions:
        into.setdefault(t.after, []).append(t)
        out.setdefault(t.before, []).append(t)
    assert StateChains.build(sc.states, into, out, {t.key: {"a", "b"} for t in
                                                     sc.transitions}, {}) is None
    got = _answers(solve_scene(sc))
    assert got["b.vx@2"] == pytest.approx(1.0) and got["b.vx@3"] == pytest.approx(0.5)
    assert got["a.vx@3"] == pytest.approx(0.5)


def test_json_document_is_streamed_byte_for_byte():
    from momentum_cli.report.json_out import DocumentStream, document

    results = [{"file": "a", "x": [1.5, float("nan"), {"é": "\n"}]}, {}, {"y": []}]
    for ascii_only in (True, False):
        for rs in (results, []):
            buf = io.StringIO()
            stream = DocumentStream(buf, "9.9", ascii_only)
            for r in rs:
                stream.append(r)
            stream.close()
            assert buf.getvalue() == document(rs, "9.9", ascii_only)
            json.loads(buf.getvalue())


def test_a_later_given_reaches_back_through_untouched_states(monkeypatch):
    """c is given only at the last state and nothing acts on it: it has that velocity
    at every state (the forward search), by the fast lookup and by the walk alike."""
    text = ('problem "later given"\nbody a: particle(mass = 1 kg)\n'
            "body b: particle(mass = 2 kg)\nbody c: particle(mass = 3 kg)\n"
            "state 1: a.v = (3 m/s, 0), b at rest, c.vy = 0 m/s\nstate 2\n"
            "state 3: c.vx = 2 m/s\n"
            "impact 1 -> 2:\n    contact b with a normal (1, 0): restitution 1\n"
            "impact 2 -> 3:\n    contact b with a normal (1, 0): restitution 1\n"
            "find c.vx@1, c.vx@2, b.vx@2, a.vx@2\n")
    got = _answers(_solve(text))
    # a on b (e = 1): a leaves at (1 - 2) / 3 * 3 = -1 m/s, b at 2 * 1 / 3 * 3 = 2 m/s
    assert got["c.vx@1"] == pytest.approx(2.0) and got["c.vx@2"] == pytest.approx(2.0)
    assert got["a.vx@2"] == pytest.approx(-1.0) and got["b.vx@2"] == pytest.approx(2.0)
    fast = _system_text(text, "g.mom")
    monkeypatch.setattr(StateChains, "build", classmethod(lambda cls, *a: None))
    assert _system_text(text, "g.mom") == fast
