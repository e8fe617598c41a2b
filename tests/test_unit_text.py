"""unit_system.detect's shortcut: a document whose text names no US customary or degree
unit (`Document.si_text`, set by the parse) is SI without degrees without walking its
statements. Checked against the walk itself (a document made without the flag) on every
example, on the hostile corpus, on unit-heavy texts written here, and on big generated
scenes; documents made from others (`--set`) always walk."""
from __future__ import annotations

import sys
from pathlib import Path

import pytest

from momentum_cli import syntax
from momentum_cli.diagnostics import ProblemError
from momentum_cli.run import SourceTextError, decode_source
from momentum_cli.source import Source
from momentum_cli.unit_system import FileUnits, detect, may_name

ROOT = Path(__file__).resolve().parent.parent / "examples"
sys.path.insert(0, str(Path(__file__).resolve().parent))


def _both(source: Source):
    """(the shortcut's answer, the walk's answer, si_text), or None: no document."""
    try:
        doc = syntax.parse(source)
    except (ProblemError, RecursionError):
        return None
    walked = detect(syntax.Document(doc.source, doc.statements))  # si_text False: walk
    return detect(doc), walked, doc.si_text


def _check(sources) -> int:
    shortcut = 0
    for s in sources:
        got = _both(s)
        if got is None:
            continue
        fast, walked, si_text = got
        assert fast == walked, s.name
        if si_text:
            assert walked == FileUnits("si", False), s.name
            shortcut += 1
    return shortcut


def test_examples_detect_the_same():
    paths = sorted(list(ROOT.glob("*.mom")) + list(ROOT.glob("simulate/*.mom")) +
                   list(ROOT.glob("hard/*.mom")))
    assert _check([Source(p.name, p.read_text(encoding="utf-8")) for p in paths]) > 5


def test_hostile_corpus_detects_the_same():
    from fuzz_corpus import corpus

    sources = []
    for name, data in corpus(300, seed=7):
        try:
            sources.append(decode_source(name, data))
        except SourceTextError as exc:
            sources.append(exc.source)
    _check(sources)


BASE = ('problem "x"\nbody a: particle(mass = 1 kg)\nstate 1: a.v = (V, 0)\nstate 2\n'
        'impact 1 -> 2:\n    contact a with ground normal (0, 1): restitution 0.5\n'
        'find a.vx@2\n')


@pytest.mark.parametrize("line, us, degrees", [  # BASE holds one SI name (kg)
    ("let V = 2 m/s", False, False),
    ("let V = 2 ft/s", False, False),  # one US name against kg: a tie is SI
    ("let V = 2 ft/s * (1 + 0 ft/ft)", True, False),
    ("let V = 2ft/s * (1 + 0ft/ft)", True, False),  # glued to its number
    ("let V = 2.ft/s * (1 + 0.ft/ft)", True, False),
    ("let V = 2 ft/s * (1 + 0 lbf*s^2/lbm)", True, False),
    ("let V = 2 m/s * cos(0 deg)", False, True),
    ("let V = 2 m/s * cos(0 °)", False, True),
    ("let V = 2 m/s * cos(0°)", False, True),
    ("let V = 2 m/s  # not 2 ft/s, nor 6.6 ft/s * ft/ft in degrees", False, False),
    ("let V = 2 mi/h * (1 + 0 mi/mi)", True, False),
    ("let V = 2 mph * (1 + 0 mph/mph)", True, False),
    ("let V = 2 in/s * (1 + 0 in/inch)", True, False),
])
def test_unit_heavy_lines(line, us, degrees):
    text = BASE.replace('problem "x"\n', f'problem "x"\n{line}\n')
    doc = syntax.parse(Source("t.mom", text))
    want = FileUnits("us" if us else "si", degrees)
    assert detect(syntax.Document(doc.source, doc.statements)) == want  # the walk
    assert detect(doc) == want


def test_a_hash_inside_a_string_starts_no_comment():
    text = BASE.replace("state 1: a.v = (V, 0)", 'state 1 "a # b": a.v = (2 ft*ft/ft/s, 0)')
    assert may_name(text)
    doc = syntax.parse(Source("t.mom", text))
    assert not doc.si_text and detect(doc) == FileUnits("us", False)


def test_find_in_a_unit_and_a_comment_only_mention():
    text = BASE.replace("find a.vx@2", "find a.vx@2 in ft/s").replace(
        'problem "x"\n', 'problem "x"\nlet V = 1 m/s\n')
    doc = syntax.parse(Source("t.mom", text))
    assert not doc.si_text  # `in ft/s`
    assert detect(doc) == detect(syntax.Document(doc.source, doc.statements))
    comment = BASE.replace('problem "x"\n', 'problem "x"\n# 2 ft/s in a comment\n'
                           'let V = 1 m/s\n')
    doc = syntax.parse(Source("c.mom", comment))
    assert doc.si_text and detect(doc) == FileUnits("si", False)


def test_a_document_with_overrides_walks():
    from momentum_cli.overrides import apply

    text = BASE.replace('problem "x"\n', 'problem "x"\nlet V = 2 m/s\n')
    doc = syntax.parse(Source("t.mom", text))
    assert doc.si_text
    new = apply(doc, [("V", "20 ft*ft/ft/s")])
    assert not new.si_text
    assert detect(new) == FileUnits("us", False)


def test_big_generated_scenes_take_the_shortcut():
    from test_hard import cradle_text

    from momentum_cli.bench import chain_text

    for text in (chain_text(200), cradle_text(200, "sequence")):
        doc = syntax.parse(Source("big.mom", text))
        assert doc.si_text
        assert detect(syntax.Document(doc.source, doc.statements)) == detect(doc)
