"""Newton run once from each distinct start solves every example exactly as Newton run
from every start (a repeated start is deterministic: it ends where it ended before)."""
from pathlib import Path

import pytest

from momentum_cli import solve
from momentum_cli.diagnostics import ProblemError
from momentum_cli.run import read_source
from momentum_cli.scene import build
from momentum_cli.syntax import parse

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
FILES = ["collar_slides_on_spinning_rod.mom", "seed_pendulum_wall.mom", "disk_climbs_curb.mom",
         "bounce_find_e.mom", "ballistic_pendulum.mom", "find_e_no_energy_lost.mom",
         "elastic_no_energy_lost.mom", "ball_bounce_rebound.mom"]


def _outcome(path, monkeypatch, dedupe):
    monkeypatch.setattr(solve, "DEDUPE_STARTS", dedupe)
    calls = []
    inner = solve._newton_from
    monkeypatch.setattr(solve, "_newton_from", lambda *a: calls.append(1) or inner(*a))
    try:
        sol = solve.solve_scene(build(parse(read_source(str(path)))))
    except ProblemError as exc:
        return repr([d.message for d in exc.diagnostics]), len(calls)
    blocks = [(b.unknowns, b.method, b.iterations, repr(b.residual), b.rejected, b.unphysical)
              for b in sol.blocks]
    return repr((sorted(sol.values.items()), blocks, sol.answers)), len(calls)


@pytest.mark.parametrize("name", FILES)
def test_distinct_starts_give_the_same_solution(name, monkeypatch):
    path = EXAMPLES / name
    fast, n_fast = _outcome(path, monkeypatch, True)
    slow, n_slow = _outcome(path, monkeypatch, False)
    assert fast == slow
    assert n_fast <= n_slow
