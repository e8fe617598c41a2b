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
