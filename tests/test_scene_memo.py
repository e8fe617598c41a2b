"""The scene builder's memos give the scene the full walk gives: one-shape bodies and
contact clauses of literal numbers (and named constants) remembered by those, and a
literal's unit factor remembered by unit and dimension (`scene._literal`). Compared by
repr (every field, the sign of zeros, the notes) and by the error, on every example,
chains, cradles and generated scenes of varied shapes, units and contact laws."""
from __future__ import annotations

from pathlib import Path

import pytest

from momentum_cli import scene as SC
from momentum_cli.bench import chain_text
from momentum_cli.diagnostics import ProblemError
from momentum_cli.source import Source
from momentum_cli.syntax import parse
from test_hard import cradle_text

ROOT = Path(__file__).resolve().parent.parent
EXAMPLES = sorted(str(p.relative_to(ROOT)) for p in ROOT.glob("examples/**/*.mom"))

SHAPES = ["particle(mass = m, radius = r)", "disk(mass = 2 kg, radius = 10 cm)",
          "sphere(mass = 300 gram, radius = 2 in)", "particle(mass = 0.25 lb)",
          "rod(mass = 1.5 kg, length = 80 cm)", "particle(mass = -0.0 kg)",
          "disk(mass = m, radius = 0 m)"]
PROPS = ["restitution 0.5, smooth", "restitution 0.8, friction 0.3", "restitution 1, smooth",
         "restitution ?", "restitution e1", "separation 2 m/s", "restitution 0.5, rough",
         "restitution 0.5 poisson, friction 0.2"]


def _varied(n: int, shapes=SHAPES[:5], props=PROPS[:4], normal="(1, 0)") -> str:
    lines = ['problem "varied"', "let m = 0.1 kg", "let r = 15 mm", "unknown e1"]
    lines += [f"body b{i}: {shapes[i % len(shapes)]}" for i in range(1, n + 1)]
    lines += [f"state {i}" + (": b1.v = (1 m/s, 0)" if i == 1 else "") for i in range(1, n + 1)]
    for i in range(1, n):
        lines.append(f"impact {i} -> {i + 1}:")
        lines.append(f"    contact c{i}: b{i + 1} with b{i} normal {normal}: "
                     f"{props[i % len(props)]}")
    lines.append(f"find b{n}.vx@{n}")
    return "\n".join(lines) + "\n"


TEXTS = [(name, (ROOT / name).read_text(encoding="utf-8")) for name in EXAMPLES] + \
    [(f"chain {n}", chain_text(n)) for n in (3, 70, 700)] + \
    [(f"cradle {n} {k}", cradle_text(n, k)) for n in (70, 130) for k in ("sequence",
                                                                        "simultaneous")] + \
    [("varied", _varied(90)), ("varied all", _varied(90, SHAPES, PROPS)),
     ("varied normal", _varied(80, normal="(1 m, 0 m)")),
     ("varied bad shape", _varied(80, SHAPES[5:], PROPS[:1])),
     ("varied bad law", _varied(80, SHAPES[:1], PROPS[4:]))]


def _outcome(text: str, memo: bool, monkeypatch) -> str:
    SC._LITERALS.clear()
    SC._FACTORS.clear()
    monkeypatch.setattr(SC, "CONTACT_MEMO", memo)
    monkeypatch.setattr(SC, "CONTACT_MEMO_FROM", 1 if memo else 10 ** 9)
    if not memo:  # every literal through the evaluator
        monkeypatch.setattr(SC._Builder, "_literal", SC._Builder._value)
    try:
        doc = parse(Source("t.mom", text))
    except ProblemError:
        return "parse error"
    try:
        return repr(SC.build(doc))
    except ProblemError as exc:
        return f"error {exc}"
    finally:
        monkeypatch.undo()


@pytest.mark.parametrize("name,text", TEXTS, ids=[t[0] for t in TEXTS])
def test_memos_build_the_scene_of_the_full_walk(name, text, monkeypatch):
    want = _outcome(text, False, monkeypatch)
    assert _outcome(text, True, monkeypatch) == want
    # and again with the caches already filled (a batch of files in one process)
    assert _outcome(text, True, monkeypatch) == want


def test_generated_scenes_use_the_memos(monkeypatch):
    """The big generated scenes build (not only errors) and the memos are hit."""
    for text in (_varied(90), _varied(90, SHAPES[:5], PROPS[:4] + PROPS[5:6])):
        assert not _outcome(text, True, monkeypatch).startswith(("error", "parse"))
    hits = {"body": 0, "contact": 0}
    seen_body, seen_contact = [], []
    real_build = SC._Builder.run

    def run(self):
        out = real_build(self)
        seen_body.append(self._bodies_seen)
        seen_contact.append(self._contacts_seen)
        return out

    monkeypatch.setattr(SC._Builder, "run", run)
    SC.build(parse(Source("t.mom", _varied(90))))
    hits["body"] = len(seen_body[0])
    hits["contact"] = len(seen_contact[0])
    assert 0 < hits["body"] < 90 and 0 < hits["contact"] < 89
