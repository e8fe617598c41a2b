"""Stage 6, report: plain text is deterministic and says what the rich one says."""
from __future__ import annotations

import io
import re

from conftest import EXAMPLES
from helpers import solve_text

from momentum_cli.numbers import fmt_num
from momentum_cli.report.model import build_report
from momentum_cli.report.text import render, render_quiet

SMOOTH = (EXAMPLES / "seed_rod_drop_smooth.mom").read_text()


def report():
    return build_report("rod.mom", solve_text(SMOOTH))


def test_plain_report_has_every_section_in_order():
    text = render(report())
    heads = ["Bodies", "Effects and constraints", "Knowns (SI)", "Energy 1 -> 2",
             "Impact 2 -> 3", "Solving, block by block", "Solution (SI)", "Checks", "Answers"]
    pos = [text.index("\n" + h) for h in heads]
    assert pos == sorted(pos)


def test_plain_report_is_ascii_and_has_no_escape_codes():
    text = render(report())
    assert text.isascii() and "\x1b" not in text


def test_the_why_of_the_impact_is_shown():
    assert "conserved along (-1, 0)" in render(report())


def test_each_equation_shows_symbols_then_numbers():
    text = render(report())
    assert "I_rod*(rod.omega@3 - rod.omega@2)" in text
    assert "0.833333*(rod.omega@3 - 0)" in text


def test_elastic_impact_check_says_no_energy_lost():
    rep = report()
    check = next(c for c in rep.checks if c.name.startswith("kinetic energy"))
    assert check.status == "ok" and "lost 0 J" in check.detail


def test_quiet_prints_name_value_unit_lines():
    lines = render_quiet(report()).splitlines()
    assert all(re.fullmatch(r"\S+ = \S+( \S+)?", ln) for ln in lines)
    assert lines[0].startswith("rod.omega@3 = -14.16")


def test_numbers_are_formatted_by_our_function():
    assert fmt_num(-0.0) == "0" and fmt_num(1234567.0) == "1.23457e6"
    assert fmt_num(0.1 + 0.2) == "0.3" and fmt_num(float("nan")) == "nan"


def test_rich_renderer_prints_the_same_answers():
    from rich.console import Console

    from momentum_cli.report.rich_out import render as rich_render

    buf = io.StringIO()
    rich_render(report(), Console(file=buf, width=120, color_system=None), 6)
    out = buf.getvalue()
    assert "-14.1637" in out and "Answers" in out and "why:" in out
