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


def solve_outcome(path) -> str:
    """What solving the file at `path` gives, as text to compare between two ways of
    solving it: its values, its blocks (method, iterations, residual, rejected roots) and
    answers, or its errors' messages."""
    text = open(path, encoding="utf-8").read()
    try:
        sol = solve_text(text, str(path))
    except ProblemError as exc:
        return repr([d.message for d in exc.diagnostics])
    blocks = [(b.unknowns, b.method, b.iterations, repr(b.residual), b.rejected, b.unphysical)
              for b in sol.blocks]
    return repr((sorted(sol.values.items()), blocks, sol.answers))


def solved_scenes():
    """(name, Solution, {equation index: the unknowns its block keeps}) for every example
    that solves and for a generated chain and sequential cradle: the scenes on which the
    report's fast printers are compared with the walks they replace."""
    from conftest import EXAMPLES
    from test_hard import cradle_text

    from momentum_cli.bench import chain_text

    scenes = [(p.name, p.read_text(encoding="utf-8")) for p in sorted(EXAMPLES.glob("*.mom"))]
    scenes += [("chain.mom", chain_text(40)), ("cradle.mom", cradle_text(30, "sequence"))]
    for name, text in scenes:
        try:
            sol = solve_text(text, name)
        except ProblemError:
            continue
        yield name, sol, {k: set(b.unknowns) for b in sol.blocks for k in b.equations}


def solve_keeping_system(monkeypatch, text: str, name: str = "test.mom", **kw):
    """(solution, the system `solve._solve` was given): solve_scene hands back only the
    solution, and the bounds tests re-run parts of the solve on the system."""
    import momentum_cli.solve as S

    kept = {}
    solve = S._solve

    def spy(system, *a, **k):
        sol = solve(system, *a, **k)
        kept["system"] = system
        return sol

    monkeypatch.setattr(S, "_solve", spy)
    try:
        sol = solve_scene(build(parse(Source(name, text))), **kw)
    finally:
        monkeypatch.setattr(S, "_solve", solve)
    return sol, kept["system"]


def example_both_ways(monkeypatch, module, path, summary):
    """[summary(solution) with `module.ENABLED` on, then off] for the example at `path`;
    a solve that fails gives its repr instead (the same failure either way)."""
    got = []
    for on in (True, False):
        monkeypatch.setattr(module, "ENABLED", on)
        try:
            sol, _ = solve_keeping_system(monkeypatch, path.read_text(), path.name)
        except Exception as exc:  # noqa: BLE001 - compared, not raised
            got.append(repr(exc))
            continue
        got.append(summary(sol))
    return got
