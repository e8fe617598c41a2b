"""Lines kept as their text (syntax_lines' deferred items, statement_deferred) and read
by the scene through a recipe per shape (scene_deferred) give what the nodes give: the
same statements when read, the same scene (repr: every field, the sign of zeros, the
notes) and the same errors, at the same line and column, as the parse that makes every
node and the scene's usual code. On every example, chains and cradles of a few sizes,
scenes of varied shapes, units and laws, and files with an error on a line of a shape
the recipes read (a name, a value, a state, a contact the recipe must hand back)."""
from __future__ import annotations

import pickle

import pytest

from momentum_cli import scene as SC
from momentum_cli import syntax, syntax_lines
from momentum_cli.bench import chain_text
from momentum_cli.diagnostics import ProblemError
from momentum_cli.source import Source
from momentum_cli.statement_deferred import deferred_class
from test_hard import cradle_text
from test_scene_memo import PROPS, SHAPES, TEXTS, _varied


def _parse(text: str, defer: bool, monkeypatch):
    """syntax.parse with syntax_lines used whatever the size, keeping lines as text
    (defer) or not."""
    with monkeypatch.context() as m:
        m.setattr(syntax, "LINES_BYTES", 0)
        m.setattr(syntax_lines, "DEFER_BYTES", 0)
        m.setattr(syntax_lines, "DEFER", defer)
        return syntax.parse(Source("t.mom", text))


def _outcome(text: str, defer: bool, monkeypatch):
    try:
        doc = _parse(text, defer, monkeypatch)
    except ProblemError as exc:
        return "parse", [(d.code, d.message, d.span, d.notes) for d in exc.diagnostics]
    try:
        return "scene", repr(SC.build(doc))
    except ProblemError as exc:
        return "error", [(d.code, d.message, d.span, d.notes) for d in exc.diagnostics]


def _long_block(n: int, props: str = "restitution 0.5") -> str:
    """A chain's layout: one impact of n - 1 labelled contact lines."""
    lines = ['problem "long"'] + [f"body b{i}: particle(mass = {i}.5 kg)"
                                  for i in range(1, n + 1)]
    lines += ["state 1: b1.v = (1 m/s, 0)", "state 2", "impact 1 -> 2:"]
    lines += [f"    contact c{i}: b{i + 1} with b{i} normal (1, 0): {props}"
              for i in range(1, n)]
    return "\n".join(lines + [f"find b{n}.vx@2"]) + "\n"


def _masses(n: int, odd: dict) -> str:
    """n particles of mass 2.5e100 kg (one layout), some given another mass of it."""
    lines = ['problem "masses"']
    lines += [f"body b{i}: particle(mass = {odd.get(i, '2.5e100')} kg)" for i in range(1, n + 1)]
    lines += [f"state {i}" + (": b1.v = (1 m/s, 0)" if i == 1 else "") for i in range(1, n + 1)]
    for i in range(1, n):
        lines += [f"impact {i} -> {i + 1}:",
                  f"    contact c{i}: b{i + 1} with b{i} normal (1, 0): restitution 0.5"]
    return "\n".join(lines + [f"find b{n}.vx@{n}"]) + "\n"


def _swap(text: str, old: str, new: str) -> str:
    assert text.count(old) >= 1, old
    return text.replace(old, new, 1)


CRADLE = cradle_text(130, "sequence")
LONG = _long_block(120)
VARIED = _varied(90, SHAPES, PROPS)
BAD = [
    ("duplicate body", _swap(CRADLE, "body b50:", "body b49:")),
    ("contact names an unknown body", _swap(CRADLE, "b61 with b60", "b61 with b99x")),
    ("contact of a body with itself", _swap(CRADLE, "b61 with b60", "b60 with b60")),
    ("impact to an undeclared state", _swap(CRADLE, "impact 50 -> 51", "impact 50 -> 00")),
    ("impact within one state", _swap(CRADLE, "impact 50 -> 51", "impact 50 -> 50")),
    ("two impacts on one pair of states", _swap(CRADLE, "impact 50 -> 51", "impact 49 -> 50")),
    ("restitution out of range", _swap(CRADLE, "restitution 1,", "restitution 3,")),
    ("normal of zero length", _swap(CRADLE, "normal (1, 0)", "normal (0, 0)")),
    ("long block: duplicate label", _swap(LONG, "contact c70:", "contact c69:")),
    ("long block: self contact", _swap(LONG, "b71 with b70", "b70 with b70")),
    ("long block: unknown body", _swap(LONG, "b71 with b70", "b71 with x70")),
    ("long block: restitution out of range", _swap(LONG, "b71 with b70 normal (1, 0): "
                                                   "restitution 0.5", "b71 with b70 normal "
                                                   "(1, 0): restitution 1.5")),
    ("mass that underflows to zero", _masses(40, {20: "2.5e-900"})),
    ("mass too large", _masses(40, {20: "2.5e200"})),
    ("mass below the smallest normal float", _masses(40, {20: "2.5e-310"})),
    ("masses in range", _masses(40, {20: "2.5e-300", 30: "9.9e-100"})),
    ("a point where a body was", _swap(_swap(CRADLE, "body b8: ", "point b8 = b8x at (0, 0)"
                                             "\nbody b8x: "), ", b8 at rest", ", b8x at rest")),
    ("a point on the body it meets", _swap(_swap(CRADLE, "body b8: ", "point b8 = b9 at "
                                                 "(0, 0)\nbody b8x: "), ", b8 at rest", "")),
    ("energy phase with contacts", _swap(LONG, "impact 1 -> 2:", "energy 1 -> 2:")),
    ("interval with contacts", _swap(LONG, "impact 1 -> 2:", "interval 1 -> 2:")),
]
GOOD = [(name, text) for name, text in TEXTS] + [
    ("chain 130", chain_text(130)), ("cradle 300", cradle_text(300, "sequence")),
    ("long block 120", LONG), ("varied", VARIED),
    ("long block, varied laws", _long_block(100, "restitution 0.5 poisson, friction 0.2"))]


@pytest.mark.parametrize("name,text", GOOD + BAD, ids=[t[0] for t in GOOD + BAD])
def test_lines_kept_as_text_give_the_scene_and_errors_of_the_nodes(name, text, monkeypatch):
    want = _outcome(text, False, monkeypatch)
    assert _outcome(text, True, monkeypatch) == want
    SC._LITERALS.clear()  # and with the caches empty (a first file)
    SC._FACTORS.clear()
    assert _outcome(text, True, monkeypatch) == want


@pytest.mark.parametrize("name,text", [("chain", chain_text(130)), ("cradle", CRADLE),
                                       ("long", LONG)])
def test_big_layouts_are_kept_as_text_and_read_as_nodes(name, text, monkeypatch):
    doc = _parse(text, True, monkeypatch)
    plain = _parse(text, False, monkeypatch)
    assert type(doc) is deferred_class(syntax.Document) and type(plain) is syntax.Document
    kept = sum(type(p) is tuple for p in doc.parts)
    assert kept > 10  # most of its bodies (and impacts) are kept as text
    assert doc.statements == plain.statements  # made when read, the same nodes
    assert doc == plain and plain == doc and hash(doc) == hash(plain)
    again = pickle.loads(pickle.dumps(doc))
    assert type(again) is syntax.Document and again == plain


def test_small_texts_are_not_kept(monkeypatch):
    text = chain_text(130)
    with monkeypatch.context() as m:
        m.setattr(syntax, "LINES_BYTES", 0)
        doc = syntax.parse(Source("t.mom", text))
    assert len(text) < syntax_lines.DEFER_BYTES and type(doc) is syntax.Document
