"""The impulse diagrams' shortcut for the commonest application (`diagram.PLAIN`:
impulses alone, a known arm; and the plain text made straight from a transition,
`LazyDiagrams.text`) against `_impulses`' general steps: the same diagrams and lines,
field by field (a float's bits through repr), on every example, chains, cradles
(sequence and simultaneous) and scenegen scenes."""
from __future__ import annotations

import sys
from pathlib import Path

import pytest

from momentum_cli.bench import chain_text
from momentum_cli.report import diagram
from momentum_cli.report.reader import reader_for
from momentum_cli.scene import build
from momentum_cli.solve import ProblemError, solve_scene
from momentum_cli.source import Source
from momentum_cli.syntax import parse

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tests"))
from test_hard import cradle_text  # noqa: E402

EXAMPLES = sorted(p for p in (ROOT / "examples").glob("*.mom"))


def _same(text_: str, name: str = "x.mom", monkeypatch=None) -> bool:
    try:
        sol = solve_scene(build(parse(Source(name, text_))))
    except ProblemError:
        return False
    reader = reader_for("file", sol.system.scene.file_units)
    got = {}
    for plain in (True, False):
        monkeypatch.setattr(diagram, "PLAIN", plain)
        ds = diagram.build_diagrams(sol, reader)
        lazy = diagram.lazy_diagrams(sol, reader)
        got[plain] = (repr(ds), [d.lines("  ") for d in ds],
                      [repr(lazy.of(d.kind, d.key)) for d in ds])
        # the plain text made straight from each transition (`LazyDiagrams.text`, by
        # `_Builder.plain_lines` where it applies) is the diagram's own lines
        for indent in ("", "  "):
            assert [lazy.text(d.kind, d.key, indent) for d in ds] == \
                [d.lines(indent) for d in ds]
    assert got[True] == got[False]
    return True


@pytest.mark.parametrize("path", EXAMPLES, ids=lambda p: p.name)
def test_examples_diagrams_by_the_shortcut_equal_the_general_steps(path, monkeypatch):
    _same(path.read_text(encoding="utf-8"), str(path), monkeypatch)


def test_big_scenes_diagrams_by_the_shortcut_equal_the_general_steps(monkeypatch):
    assert _same(chain_text(30), monkeypatch=monkeypatch)
    for kind in ("sequence", "simultaneous"):
        assert _same(cradle_text(12, kind), monkeypatch=monkeypatch)


def test_random_scenes_diagrams_by_the_shortcut_equal_the_general_steps(monkeypatch):
    import scenegen

    n = 0
    for cat in scenegen.categories():
        for seed in range(4):
            sc = scenegen.generate(seed, cat)
            if sc is not None and _same(scenegen.render(sc), monkeypatch=monkeypatch):
                n += 1
    assert n > 20
