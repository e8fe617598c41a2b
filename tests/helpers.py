"""Helpers shared by the tests: solve text or a file in-process, read answers."""
from __future__ import annotations

from momentum_cli.diagnostics import ProblemError
from momentum_cli.scene import build
from momentum_cli.solve import solve_scene
from momentum_cli.source import Source
from momentum_cli.syntax import parse


def solve_text(text: str, name: str = "test.mom", solve_all: bool = False):
    """The Solution of a problem given as text (raises ProblemError)."""
    return solve_scene(build(parse(Source(name, text))), solve_all)


def answers(text: str, **kw) -> dict[str, float]:
    """{find name: SI value} for a problem given as text."""
    sol = solve_text(text, **kw)
    return {name: si for name, _v, _u, si in sol.answers}


def error_of(text: str, name: str = "test.mom"):
    """The first Diagnostic raised for a problem given as text (fails if none)."""
    try:
        solve_text(text, name)
    except ProblemError as exc:
        return exc.diagnostics[0]
    raise AssertionError("expected a ProblemError")
