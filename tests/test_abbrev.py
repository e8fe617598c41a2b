"""Long lists of names in a report (a big chain's bodies, a block's unknowns and lines)
are shown as their first few, `...`, their last and their count; short ones whole."""
from __future__ import annotations

from momentum_cli.bench import chain_text
from momentum_cli.report.abbrev import LIMIT, abbreviate, name_list
from momentum_cli.report.model import build_report
from momentum_cli.report.text import render
from momentum_cli.run import _build_scene, decode_source
from momentum_cli.solve import solve_scene


def test_a_short_list_is_shown_whole():
    names = [f"b{k}" for k in range(1, LIMIT + 1)]
    assert abbreviate(names) == (", ".join(names), None)
    assert name_list(names, "bodies") == ", ".join(names)
    assert abbreviate([]) == ("", None)


def test_a_long_list_shows_its_ends_and_its_count():
    names = [f"b{k}" for k in range(1, 1001)]
    assert abbreviate(names) == ("b1, b2, b3, ..., b1000", 1000)
    assert name_list(names, "bodies") == "b1, b2, b3, ..., b1000 (1000 bodies)"
    assert abbreviate(range(20)) == ("0, 1, 2, ..., 19", 20)  # not only lists, not only str


def test_a_40_ball_chain_report_names_its_bodies_briefly():
    n = 40
    text = chain_text(n)
    sol = solve_scene(_build_scene(decode_source("chain.mom", text)))
    out = render(build_report("chain.mom", sol, 6, "file"), 6)
    checks = out[out.index("\nChecks\n"):out.index("\nAnswers\n")]
    ke = next(line for line in checks.splitlines() if "kinetic energy" in line)
    assert f"T of {{b1, b2, b3, ..., b{n}}} ({n} bodies): T1 = " in ke
    assert "b4," not in ke
    block = next(line for line in out.splitlines() if line.startswith("  block 1: "))
    # the impact's unknowns: each ball's velocity after it (n) and each contact's impulse
    assert f"({2 * n - 1} unknowns; linear" in block and ", ..., " in block
    assert max(map(len, checks.splitlines())) < 400
