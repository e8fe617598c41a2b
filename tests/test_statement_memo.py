"""A batch parses each distinct statement once (statement_memo): the same documents,
errors and printed reports as parsing every file whole, on every example, on numeric
variants of them (the statements that differ parsed, the others shared) and on a
hostile corpus (lines cut, swapped, duplicated; odd values; CRLF; other encodings); and
the same unit strings from unit_system's walk, which takes each shared statement's."""
from __future__ import annotations

import random
import re
from functools import partial
from pathlib import Path

import pytest

from momentum_cli import statement_memo, syntax, unit_system
from momentum_cli.diagnostics import ProblemError
from momentum_cli.report.text import render
from momentum_cli.run import Rendered, SourceTextError, decode_source, solve_many, solve_source
from momentum_cli.source import Source

ROOT = Path(__file__).resolve().parent.parent / "examples"
EXAMPLES = sorted(p for p in list(ROOT.glob("*.mom")) + list(ROOT.glob("simulate/*.mom")) +
                  list(ROOT.glob("hard/*.mom")) if "cradle_1000" not in p.name)
NUMBER = re.compile(r"(?<=[=(,] )(\d+\.?\d*)(?=[ ,)\n])")


def variant(text: str, rng: random.Random) -> str:
    """The file with some of its given numbers (after `= `, `( ` or `, `) scaled: what
    a batch of variants of one problem looks like."""
    return NUMBER.sub(lambda m: f"{float(m.group(1)) * rng.uniform(0.5, 2):.4g}"
                      if rng.random() < 0.3 else m.group(1), text)


def parsed(source: Source):
    """The document's statements as text (repr: -0.0 and 0.0 differ) and its unit
    system (unit_system.detect, which walks each shared statement once), or the error."""
    from momentum_cli.unit_system import _units, detect

    try:
        doc = syntax.parse(source)
        return "ok", repr(doc.statements), detect(doc), _units(doc) if \
            unit_system.UNITS[0] is None else unit_system.UNITS[0](doc, _units)
    except ProblemError as exc:
        return "error", [(d.code, d.message, d.span) for d in exc.diagnostics]
    except RecursionError:
        return "too deep", None


def both(sources):
    """Each source parsed whole, then all of them in one batch through the table."""
    whole = [parsed(s) for s in sources]
    with statement_memo.enabled():
        batch = [parsed(s) for s in sources]
    assert syntax.STATEMENTS[0] is None and unit_system.UNITS[0] is None  # hooks off again
    return whole, batch


def texts():
    return [(p.name, p.read_text(encoding="utf-8")) for p in EXAMPLES]


def test_examples_and_variants_parse_the_same():
    rng = random.Random(13)
    sources = []
    for name, text in texts():
        sources.append(Source(name, text))
        sources += [Source(f"{name}~{k}", variant(text, rng)) for k in range(3)]
    whole, batch = both(sources)
    for s, w, b in zip(sources, whole, batch):
        assert w == b, s.name
    assert sum(w[0] == "ok" for w in whole) > len(EXAMPLES)


def test_statements_are_shared_between_variants():
    """The table is used: the second variant's unchanged statements are the first's
    nodes (shared frozen records), its changed ones are new."""
    text = (ROOT / "seed_rod_drop_smooth.mom").read_text(encoding="utf-8")
    other = text.replace("mass = 10 kg", "mass = 12.5 kg")
    from momentum_cli.unit_system import detect

    with statement_memo.enabled():
        a = syntax.parse(Source("a.mom", text)).statements
        b = syntax.parse(Source("b.mom", other)).statements
        for doc in (a, b):
            detect(syntax.Document(Source("a.mom", text), doc))
        assert len(statement_memo._units) == len(a) + 1  # the changed statement: one more
    shared = sum(x is y for x, y in zip(a, b))
    assert len(a) == len(b) and shared == len(a) - 1
    (body_a,) = [x for x in a if type(x).__name__ == "BodyDecl"]
    (body_b,) = [x for x in b if type(x).__name__ == "BodyDecl"]
    assert body_a is not body_b and body_a != body_b


@pytest.mark.parametrize("text", [
    'problem "x"\n  body a: particle(mass = 1 kg)\n',  # an indented first statement
    '3 problem "x"\nbody a: particle(mass = 1 kg)\n',  # text before the first statement
    'problem "x"\nbody a: particle(mass = \\\n1 kg)\nfind a.vx@1\n',  # a continuation
    'problem "x"\nbody a: particle(mass =\n1 kg)\n',  # a bracket over two lines
    'problem "x"\nbody a: particle(mass = 1 kg) \\\nfind a.vx@1\n',  # joins the next statement
    'problem "x"\nbody a: particle(mass = 1 kg) \\ \t\n',  # ... at the end of the text
    'problem "x"\n# a comment \\\nbody a: particle(mass = 1 kg)\n',
    'problem "x"\nbody a: particle(\nmass = 1 kg)\n',  # ... whose next line starts a word
    'problem "x"\r\nbody a: particle(mass = 1 kg)\r\n',
    'problem "x"\nbody a: particle(mass = 1 kg)',  # no final newline
    'problem "x"\nbody a: particle(mass = 1 kg)\n\tstate 1: a at rest\n',
    "# only a comment\n",
])
def test_texts_the_cut_does_not_fit_parse_the_same(text):
    whole, batch = both([Source("t.mom", text), Source("u.mom", text)])
    assert whole == batch


def test_continuations_inside_a_statement_are_cut_by_statement():
    """A `\\` that joins two lines of one statement keeps the cut (the examples write
    long `state` and `find` lines so): the table is used, the nodes are the whole parse's."""
    text = ('problem "x"\ngravity 9.81 m/s^2 down\nbody a: particle(mass = 1 kg)\n'
            'state 1: a.v = (1 m/s, 0), \\\n    a.pos = (0, 0)\nstate 2\n'
            'impact 1 -> 2:\n    contact a with ground: restitution 0.5\n'
            'find a.v@2, \\  \n    J_n[a]@1->2\n')
    fast = syntax._fast_parser()
    assert statement_memo.parse(text, fast.parse) is not None
    statement_memo.clear()
    whole, batch = both([Source("t.mom", text), Source("u.mom", text)])
    assert whole == batch and whole[0][0] == "ok"


def test_hostile_corpus_parses_the_same():
    from fuzz_corpus import corpus

    sources = []
    for name, data in corpus(300, seed=5):
        try:
            sources.append(decode_source(name, data))
        except SourceTextError as exc:
            sources.append(exc.source)
    whole, batch = both(sources)
    for s, w, b in zip(sources, whole, batch):
        assert w == b, s.name


def test_a_batch_prints_what_each_file_alone_prints():
    """The whole path: a batch of variants (solve_many, here in this process) against
    each file solved alone, report text and diagnostics byte for byte."""
    rng = random.Random(5)
    picked = ["seed_rod_drop_smooth.mom", "seed_billiards_find_e.mom",
              "ballistic_pendulum.mom", "newtons_cradle_sequence.mom"]
    sources = []
    for name in picked:
        text = (ROOT / name).read_text(encoding="utf-8")
        sources += [Source(f"{name}~{k}", variant(text, rng) if k else text)
                    for k in range(4)]
    fn = partial(render, sig=6, detail="full")
    alone = [solve_source(s, False, 6, "float") for s in sources]
    batch = list(solve_many(sources, False, 6, "float", render=fn))
    for s, a, b in zip(sources, alone, batch):
        assert a.status == b.status and a.diagnostics == b.diagnostics, s.name
        if a.report is not None:
            assert isinstance(b.report, Rendered) and b.report.text == fn(a.report), s.name
    assert sum(a.status == "solved" for a in alone) >= len(picked)


def test_the_hooks_are_on_only_while_a_file_of_a_batch_is_solved():
    """A batch left half-read (its generator not finished) leaves the parse as it was;
    the tables are emptied when the batch ends."""
    text = (ROOT / "seed_rod_drop_smooth.mom").read_text(encoding="utf-8")
    batch = solve_many([Source(f"{k}.mom", text) for k in range(3)], False, 6, "float")
    assert next(batch).status == "solved"
    assert syntax.STATEMENTS[0] is None and unit_system.UNITS[0] is None
    assert statement_memo._table  # kept for the next file
    batch.close()
    assert not statement_memo._table and not statement_memo._units
