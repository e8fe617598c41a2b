"""A batch makes a statement that differs from an earlier one only in its numbers (or its
`problem` title) from that one's nodes (statement_template): the same documents and
errors as parsing every file whole, on every example with all its numbers changed (in
length too: the columns after them move), and on texts written here where a changed
literal is not a number the nodes hold (a state, a unit's power, a comment)."""
from __future__ import annotations

import random
import re
from pathlib import Path

import pytest

from momentum_cli import statement_memo, statement_template, syntax
from momentum_cli.source import Source

from test_statement_memo import both

ROOT = Path(__file__).resolve().parent.parent / "examples"
EXAMPLES = sorted(p for p in list(ROOT.glob("*.mom")) + list(ROOT.glob("simulate/*.mom")) +
                  list(ROOT.glob("hard/*.mom")) if "cradle_1000" not in p.name)
ANY_NUMBER = re.compile(r"(?<![A-Za-z_0-9.])(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?")
TEXTS = ["0", "7", "12.5", "3e2", "0.000125", "1e-07", "450000", ".5", "2.", "1E3"]


def renumbered(text: str, rng: random.Random, p: float) -> str:
    """Each number-like literal (state numbers, powers and comments too) replaced with
    probability p by one of TEXTS (other lengths: the columns after it move)."""
    return ANY_NUMBER.sub(lambda m: rng.choice(TEXTS) if rng.random() < p else m.group(),
                          text)


def retitled(text: str, k: int) -> str:
    return re.sub(r'^problem "([^"]*)"', lambda m: f'problem "{m.group(1)} #{k * 37}"', text,
                  count=1, flags=re.M)


def test_examples_with_new_numbers_parse_the_same():
    rng = random.Random(31)
    sources = []
    for p in EXAMPLES:
        text = p.read_text(encoding="utf-8")
        sources.append(Source(p.name, text))
        for k in range(3):  # masses, speeds, ...: the numbers the nodes hold
            sources.append(Source(f"{p.name}~{k}", retitled(renumbered(text, rng, 0.25), k)))
    whole, batch = both(sources)
    for s, w, b in zip(sources, whole, batch):
        assert w == b, s.name
    assert sum(w[0] == "ok" for w in whole) > len(EXAMPLES)


BASE = ('problem "a rod struck"\n'
        'gravity 9.81 m/s^2 into plane\n'
        'let L = 1.2 m  # 1.2 m long\n'
        'body rod: rod(mass = 4 kg, length = L)\n'
        'body puck: particle(mass = 0.5 kg, radius = 25 mm)\n'
        'point P = rod at (0.4 m, 0)\n'
        'state 1 "before": rod.angle = 0, rod at rest, puck.v = (0, 10 m/s), \\\n'
        '    puck.pos = (0.4 m, -1.25e-2 m)\n'
        'state 2 "after"\n'
        'impact 1 -> 2:\n'
        '    contact hit: P with puck normal (0, 1): restitution 0.5, smooth\n'
        'find rod.vy@2, rod.omega@2 in rad/s, x = 3*puck.vy@2 + 10 m/s\n')


@pytest.mark.parametrize("old, new", [
    ("0.5 kg", "15 kg"),
    ("0.5 kg, radius = 25 mm", "0.015 kg, radius = 2.5e1 mm"),
    ("(0.4 m, -1.25e-2 m)", "(12345 m, -1 m)"),  # on a continuation line
    ("(0, 10 m/s)", "(0.25, 1 m/s)"),
    ("(0.4 m, 0)", "(0.41234 m, 10)"),
    ("restitution 0.5", "restitution 1"),
    ("3*puck.vy@2 + 10 m/s", "300*puck.vy@2 + 1 m/s"),
    ('problem "a rod struck"', 'problem "another rod, 2"'),
    ('state 1 "before"', 'state 1 "before 2"'),  # a string that is not a title
    ("m/s^2 into", "m/s^3 into"),  # a unit's power: not a number the nodes hold
    ("# 1.2 m long", "# 12 m long"),  # a comment
    ("rod.vy@2,", "rod.vy@1,"),  # a state
    ('state 2 "after"', 'state 3 "after"'),
    ("impact 1 -> 2", "impact 1 -> 3"),
    ("normal (0, 1)", "normal (0, 12)"),
])
def test_one_change(old, new):
    assert old in BASE
    changed = BASE.replace(old, new)
    whole, batch = both([Source("a.mom", BASE), Source("b.mom", changed)])
    assert whole == batch and whole[0][0] == "ok"


def test_templates_are_used():
    """The second file's changed statements are made, not parsed: the parser is not
    called for them; a changed state number is parsed."""
    calls = []
    fast = syntax._fast_parser()

    def counted(text):
        calls.append(text)
        return fast.parse(text)

    changed = BASE.replace("0.5 kg", "15.25 kg").replace('"a rod struck"', '"b"')
    with statement_memo.enabled():
        first = statement_memo.parse(BASE, counted)
        n = len(calls)
        second = statement_memo.parse(changed, counted)
        assert len(calls) == n  # nothing parsed
        third = statement_memo.parse(changed.replace("state 2 ", "state 3 "), counted)
        assert len(calls) == n + 1
    assert first is not None and second is not None and third is not None
    assert second == list(syntax.parse(Source("b.mom", changed)).statements)
    assert not statement_template._shapes  # emptied with the batch's tables


LOOPS = ('problem "a row"\n'
         'let v0 = 3 m/s\n'
         'for i in 1..4:\n'
         '    body b[i]: particle(mass = 0.1 kg * 2^(i-1), radius = 15 mm)\n'
         'state 1 "start":\n'
         '    b[1].v = (v0, 0)\n'
         '    for i in 2..4:\n'
         '        b[i] at rest\n'
         'for i in 2..4:\n'
         '    state i "after"\n'
         'for i in 1..3:\n'
         '    impact i -> i+1:\n'
         '        contact c[i]: b[i+1] with b[i] normal (1, 0): restitution 0.9, smooth\n'
         'find b[4].vx@4, J_n[c[3]]@3->4\n')


@pytest.mark.parametrize("by_lines", [False, True])
def test_loops_use_templates(by_lines):
    """Written-out loops: a variant's statements whose numbers changed (inside a loop's
    body too) are made from the templates, their spans mapped to the file (loop
    iteration included) exactly as the whole parse maps them."""
    from momentum_cli.loops import expand

    calls = []
    fast = syntax._fast_parser()

    def counted(text, line=1):
        calls.append(text)
        return fast.parse(text, line)

    variants = [LOOPS, LOOPS.replace("0.1 kg", "0.1255 kg").replace('"a row"', '"a row 2"'),
                LOOPS.replace("restitution 0.9", "restitution 0.75").replace("0.1 kg", "17.5 kg"),
                LOOPS.replace("(v0, 0)", "(v0, 25)")]  # numbers of the same form
    with statement_memo.enabled():
        for k, text in enumerate(variants):
            n = len(calls)
            loops = expand(text)
            syntax._SPANS[0] = loops  # as syntax._parse_nodes sets it around the hook
            try:
                got = statement_memo.parse(loops.text, counted, loops, by_lines)
            finally:
                syntax._SPANS[0] = None
            if k and not by_lines:
                assert len(calls) == n, calls[n:]  # every changed statement made from a template
            assert got is not None
            want = syntax.parse(Source("a.mom", text)).statements
            assert tuple(got) == want
            assert any(s.span.where for s in got)  # spans in loops carry their iteration


@pytest.mark.parametrize("first, then", [
    ("m/s^.5 into", "m/s^2 into"),  # a number after the unit, then the unit's own power
    ("m/s^2 into", "m/s^.5 into"),
    ("m/s^1e-07 into", "m/s^2 into"),  # an error, then a unit
    ("(0.4 m, 0)", "(0.4 m, 0.5)"),
    ("(0.4 m, 0)", "(4 m, 5e-1)"),
])
def test_a_number_of_another_form_is_not_made_from_a_template(first, then):
    """A template holds what its numbers' form tokenizes to: `m/s^2` is a unit, `m/s^.5`
    a unit to a power; a number of another form (dot, exponent) is parsed, not made."""
    assert first in BASE or then in BASE
    a, b = BASE.replace("m/s^2 into", first), BASE.replace("m/s^2 into", then)
    if "(0.4 m, 0)" in (first, then):
        a, b = BASE.replace("(0.4 m, 0)", first), BASE.replace("(0.4 m, 0)", then)
    whole, batch = both([Source("a.mom", a), Source("b.mom", b), Source("c.mom", a)])
    assert whole == batch
