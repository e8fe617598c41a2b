"""The streamed report (`build_report(..., lazy=True)`: its transitions, blocks, unknowns
and diagrams made as a renderer reads them) against the report built whole: the same
plain text (full and brief), JSON, rich text and documents, byte for byte, on every
example and on generated chains, cradles and scenegen scenes (rigid bodies, friction,
pins, unknown restitution)."""
from __future__ import annotations

import io
import pickle
import sys
from pathlib import Path

import pytest

from momentum_cli.bench import chain_text
from momentum_cli.report import json_out, text
from momentum_cli.report.model import Lazy, build_report
from momentum_cli.scene import build
from momentum_cli.solve import ProblemError, solve_scene
from momentum_cli.source import Source
from momentum_cli.syntax import parse

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tests"))
from test_hard import cradle_text  # noqa: E402

EXAMPLES = sorted(p for p in (ROOT / "examples").glob("*.mom"))


def _solved(text_: str, name: str = "x.mom"):
    try:
        return solve_scene(build(parse(Source(name, text_))))
    except ProblemError:
        return None


def _outputs(sol, lazy: bool, name: str, units: str = "file", rich: bool = False) -> list:
    """What each renderer makes of a fresh report (a lazy one is read once each)."""
    rep = lambda: build_report(name, sol, 6, units, lazy=lazy)  # noqa: E731
    out = [text.render(rep(), 6), text.render(rep(), 6, detail="brief"),
           text.render(rep(), 4), json_out.dumps(json_out.report_fields(rep()))]
    if rich:
        from rich.console import Console

        from momentum_cli.report.formats import render_document
        from momentum_cli.report.rich_out import render

        for detail in ("full", "brief"):
            buf = io.StringIO()
            render(rep(), Console(file=buf, width=120, color_system=None), 6, detail=detail)
            out.append(buf.getvalue())
        for mode in ("markdown", "html", "latex"):
            out.append(render_document(mode, [rep()], 6, "full"))
    return out


def _same(text_: str, name: str = "x.mom", rich: bool = False, units=("file",)) -> bool:
    sol = _solved(text_, name)
    if sol is None:
        return False
    for u in units:
        whole = _outputs(sol, False, name, u, rich)
        streamed = _outputs(sol, True, name, u, rich)
        assert len(whole) == len(streamed)
        for a, b in zip(whole, streamed):
            assert a == b
    return True


@pytest.mark.parametrize("path", EXAMPLES, ids=lambda p: p.name)
def test_examples_stream_the_same_report(path):
    _same(path.read_text(encoding="utf-8"), str(path), rich=True)


@pytest.mark.parametrize("n", [2, 3, 40])
def test_chains_stream_the_same_report(n):
    assert _same(chain_text(n))


@pytest.mark.parametrize("kind", ["sequence", "simultaneous"])
@pytest.mark.parametrize("n", [2, 5, 30])
def test_cradles_stream_the_same_report(n, kind):
    assert _same(cradle_text(n, kind))


def test_random_scenes_stream_the_same_report():
    """Rigid bodies, friction, pins, unknown e, the ground: every category of scenegen."""
    import scenegen

    n = 0
    for cat in scenegen.categories():
        for seed in range(4):
            sc = scenegen.generate(seed, cat)
            if sc is not None and _same(scenegen.render(sc)):
                n += 1
    assert n > 20


def test_a_lazy_report_reads_like_lists_and_pickles_as_lists():
    sol = _solved(cradle_text(4, "sequence"))
    whole = build_report("x", sol, 6)
    rep = build_report("x", sol, 6, lazy=True)
    for field in ("transitions", "blocks", "unknowns"):
        lazy = getattr(rep, field)
        assert isinstance(lazy, Lazy)
        assert len(lazy) == len(getattr(whole, field)) and bool(lazy)
        if field != "transitions":  # (their rows are lazy too: compared as text above)
            assert list(lazy) == list(lazy) == getattr(whole, field)  # made again, the same
    assert len(rep.diagrams) == len(whole.diagrams) == 3
    assert rep.blocks[0] == whole.blocks[0] and rep.unknowns[-1] == whole.unknowns[-1]
    back = pickle.loads(pickle.dumps(rep))
    assert type(back.transitions) is list and type(back.diagrams) is list
    assert text.render(back, 6) == text.render(whole, 6)
