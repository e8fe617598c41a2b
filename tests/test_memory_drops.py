"""What a big solve drops to lower its peak memory gives the same output: a diagram of
more than `text.RUN_LINES` lines written in runs (freed before its transition's rows),
and the residual trees dropped after the solve (`run._shed`) and after the report's
residual check, made again the same when something asks."""
from __future__ import annotations

import math
import sys
from pathlib import Path

import pytest

from momentum_cli.bench import chain_text
from momentum_cli.expr import evaluate, to_text
from momentum_cli.report import text
from momentum_cli.report.model import build_report, diagram_lines
from momentum_cli.run import _shed
from momentum_cli.scene import build
from momentum_cli.solve import solve_scene
from momentum_cli.source import Source
from momentum_cli.syntax import parse

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tests"))
from test_hard import cradle_text  # noqa: E402


def _solved(src: str):
    return solve_scene(build(parse(Source("x.mom", src))))


def test_a_long_diagram_in_runs_is_the_same_text():
    n = text.RUN_LINES  # more than RUN_LINES diagram lines: one line a body and more
    sol = _solved(chain_text(n))
    whole = build_report("x.mom", sol, 6, "file", lazy=False)
    d = diagram_lines(whole, whole.transitions[0], "  ")
    assert len(d) > text.RUN_LINES
    streamed = "\n".join(text.iter_parts(build_report("x.mom", sol, 6, "file", lazy=True), 6))
    assert streamed == text.render(whole, 6)
    assert "\n" + "\n".join(d) + "\n" in streamed  # the diagram's lines, in order, whole


@pytest.mark.parametrize("src", [chain_text(40), cradle_text(12, "sequence"),
                                 cradle_text(12, "simultaneous")])
def test_dropped_residuals_are_made_again_the_same(src):
    sol = _solved(src)
    eqs = sol.system.equations
    before = [e.residual for e in eqs]
    texts = [to_text(r) for r in before]
    nums = [evaluate(r, sol.values) for r in before]
    plain = text.render(build_report("x.mom", sol, 6, "file", lazy=False), 6)
    for e in eqs:  # as the solve leaves them: every residual made
        assert e.residual is not None
    _shed(sol)
    dropped = [k for k, e in enumerate(eqs) if e._residual is None]
    assert dropped and all("impulse-momentum" not in eqs[k].principle for k in dropped)
    rep = build_report("x.mom", sol, 6, "file", lazy=True)
    assert list(rep.checks)  # its residual check (made when first read) drops more
    assert all(e._residual is None for e in eqs if "impulse-momentum" in e.principle)
    assert "\n".join(text.iter_parts(rep, 6)) == plain
    for e, t, x in zip(eqs, texts, nums):
        r = e.residual
        assert to_text(r) == t
        y = evaluate(r, sol.values)
        assert y == x or (math.isnan(x) and math.isnan(y))
