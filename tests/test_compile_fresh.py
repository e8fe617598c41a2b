"""compile's shortcuts of the ninth session give what the plain paths give: an impact's
rows that name an unknown it made are kept unprinted (impact_phase.FRESH: off, every repeat
of a principle is printed and compared), vel's miss on a chain of states (as sv asks for
each component), the tree templates' node making, and the why-texts as compiled
f-strings; compared line by line (every node and its sharing, the unknowns in order, the
transitions' texts) on every example and on generated chains, cradles and scenegen scenes.
"""
from __future__ import annotations

import pytest

from momentum_cli.bench import chain_text
from test_hard import cradle_text
from test_impact_contacts import EXAMPLES, ROOT, _compiled
from test_impact_phase import _mixed


def _plain(text: str) -> list:
    """Every repeat printed and compared, vel as sv, no template, no text plan."""
    from momentum_cli import impact_phase, why_texts

    was = impact_phase.FRESH, why_texts.ENABLED
    impact_phase.FRESH = why_texts.ENABLED = False
    try:
        return _compiled(text, False)
    finally:
        impact_phase.FRESH, why_texts.ENABLED = was


def _same(text: str) -> None:
    want = _plain(text)
    got = _compiled(text, True)
    assert len(got) == len(want)
    for a, b in zip(got, want):
        assert a == b


def _two_ways_in(n: int) -> str:
    """Two impacts into one state (no simple chain of states: vel through sv), bodies
    that sit out impacts, and a principle met in several impacts."""
    out = ['problem "two ways in"\n']
    for k in range(1, n + 1):
        out.append(f"body p{k}: particle(mass = {1 + k} kg)\n")
    rest = ", ".join(f"p{k} at rest" for k in range(2, n + 1))
    out.append(f"state 1: p1.v = (1 m/s, 0), {rest}\nstate 2\nstate 3\nstate 4\n")
    out.append("impact 1 -> 2:\n    contact a: p2 with p1 normal (1, 0): restitution 1\n")
    out.append("impact 2 -> 4:\n    contact b: p3 with p2 normal (1, 0): restitution 0.5\n")
    out.append("impact 1 -> 3:\n    contact c: p3 with p1 normal (1, 0): restitution 0.7\n")
    out.append("impact 3 -> 4:\n    contact d: p2 with p1 normal (1, 0): restitution 0.2\n")
    out.append("find p1.vx@4, p3.vx@4\n")
    return "".join(out)


@pytest.mark.parametrize("name", EXAMPLES)
def test_examples_compile_the_same_without_the_shortcuts(name):
    _same((ROOT / name).read_text(encoding="utf-8"))


@pytest.mark.parametrize("n", [2, 3, 40])
def test_chains_compile_the_same_without_the_shortcuts(n):
    _same(chain_text(n))


@pytest.mark.parametrize("kind", ["sequence", "simultaneous"])
@pytest.mark.parametrize("n", [2, 3, 30])
def test_cradles_compile_the_same_without_the_shortcuts(n, kind):
    _same(cradle_text(n, kind))


@pytest.mark.parametrize("n", [3, 8])
def test_mixed_and_merging_impacts_compile_the_same_without_the_shortcuts(n):
    _same(_mixed(n))
    _same(_two_ways_in(n))


def test_random_scenes_compile_the_same_without_the_shortcuts():
    import scenegen

    n = 0
    for cat in scenegen.categories():
        for seed in range(6):
            sc = scenegen.generate(seed, cat)
            if sc is None:
                continue
            _same(scenegen.render(sc))
            n += 1
    assert n > 20


def test_a_sequence_keeps_its_repeated_principles_unprinted():
    """The cradle's rows of a body met in two impacts are kept as Fresh (no text made),
    and each is an equation of the system, once."""
    from momentum_cli.compile import Fresh, _Compiler
    from momentum_cli.scene import build
    from momentum_cli.source import Source
    from momentum_cli.syntax import parse

    c = _Compiler(build(parse(Source("t.mom", cradle_text(6, "sequence")))), {})
    system = c.run()
    fresh = [v for v in c._by_principle.values() if type(v) is Fresh]
    assert len(fresh) == 2 * 4  # b2 .. b5, x and y: each met in two impacts
    assert all(e._texts is None for v in fresh for e in v)
    rows = [e for v in fresh for e in v]
    assert len({id(e) for e in rows}) == len(rows)
    assert all(system.equations[e.index] is e for e in rows)


def test_compiled_texts_are_what_format_makes():
    from momentum_cli.why_texts import compiled

    fmts = ["{0}: {{not a field}} at {2}'s \"point\"", "{1}\\{0}", "", "plain"]
    vals = ["b1", "b2", "c1's contact point"]
    assert compiled(fmts)(vals) == [f.format(*vals) for f in fmts]
    assert compiled(["{0!r}"]) is None
