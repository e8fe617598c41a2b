"""Newton run once from each distinct start solves every example exactly as Newton run
from every start (a repeated start is deterministic: it ends where it ended before)."""
from pathlib import Path

import pytest
from helpers import solve_outcome

from momentum_cli import solve

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
FILES = ["collar_slides_on_spinning_rod.mom", "seed_pendulum_wall.mom", "disk_climbs_curb.mom",
         "bounce_find_e.mom", "ballistic_pendulum.mom", "find_e_no_energy_lost.mom",
         "elastic_no_energy_lost.mom", "ball_bounce_rebound.mom"]


def _outcome(path, monkeypatch, dedupe):
    monkeypatch.setattr(solve, "DEDUPE_STARTS", dedupe)
    calls = []
    inner = solve._newton_from
    monkeypatch.setattr(solve, "_newton_from", lambda *a: calls.append(1) or inner(*a))
    return solve_outcome(path), len(calls)


@pytest.mark.parametrize("name", FILES)
def test_distinct_starts_give_the_same_solution(name, monkeypatch):
    path = EXAMPLES / name
    fast, n_fast = _outcome(path, monkeypatch, True)
    slow, n_slow = _outcome(path, monkeypatch, False)
    assert fast == slow
    assert n_fast <= n_slow
