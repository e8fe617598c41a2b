"""The README's examples are the program's real behaviour."""
from __future__ import annotations

import math
import re

from conftest import ROOT
from helpers import answers, error_of

from momentum_cli.source import Source

README = (ROOT / "README.md").read_text(encoding="utf-8")


def _blocks(lang: str) -> list[str]:
    return re.findall(rf"```{lang}\n(.*?)```", README, flags=re.S)


def test_the_language_example_solves_to_the_seeds_answer():
    text = _blocks("text")[0]
    got = answers(text)
    # DESIGN.md: the rod dropped on a smooth floor leaves with omega = -14.16 rad/s
    assert math.isclose(got["rod.omega@3"], -14.1637424, rel_tol=1e-6)


def test_the_error_sample_is_what_the_program_prints():
    sample = next(b for b in _blocks("text") if ": error: " in b).rstrip("\n")
    first = sample.splitlines()[0]
    name, line = first.split(":")[0], int(first.split(":")[1])
    source_line = re.search(r"\|\s(body .*)$", sample, flags=re.M).group(1)
    text = "\n" * (line - 1) + source_line + "\n"
    d = error_of(text, name)
    assert d.format(Source(name, text)) == sample


def test_the_simulation_sample_is_what_the_program_prints():
    """The README's bouncing ball is examples/simulate/ball_bounces.mom, and the event
    rows it shows are rows of that example's golden event table."""
    problem = next(b for b in _blocks("text") if "simulate from 1:" in b)
    example = (ROOT / "examples/simulate/ball_bounces.mom").read_text(encoding="utf-8")
    code = [ln for ln in example.splitlines() if ln and not ln.startswith("#")]
    assert [ln for ln in problem.splitlines() if ln] == code
    sample = next(b for b in _blocks("text") if "$ momentum simulate" in b)
    golden = (ROOT / "examples/simulate/ball_bounces.sim.out").read_text(encoding="utf-8")
    rows = [ln for ln in sample.splitlines()[1:] if ln.strip() and ln.strip() != "..."]
    assert rows and all(ln in golden.splitlines() for ln in rows)
