"""The two scans of a whole big text before it is parsed (does it have loops, may it name
a US or degree unit) answer as the plain scans do: loops.may_loop as `_MAYBE.search`,
unit_system's regex scan as its str.find walk, on random texts made of the pieces that
matter (loops over several lines, comments, strings, words that contain a root)."""
from __future__ import annotations

import random

import pytest

from momentum_cli import loops, unit_system

PIECES = ["for ", "for\t", "fore", "before ", "platform ", "  for i in 1..3:", "\tfor ", "..",
          "...", "[", "]", "body ", "body b", "body b[", "body b[1", " b[1..4]", "body  x_1[",
          "\n", "\n", "\n  ", " ", "\t", "#", '"', "# a comment ", "ft", "after", " ft",
          "2 ft", "in", " in ", "kin", "lbf", "*lb", "/s", "3deg", "degree", "_mi", "mph",
          "hp", "x", "state 1", ": ", "1.5", "kg", "=", "(", ")", "°"]


def _texts(seed: int, n: int):
    rnd = random.Random(seed)
    for _ in range(n):
        yield "".join(rnd.choice(PIECES) for _ in range(rnd.randint(0, 40)))


@pytest.mark.parametrize("seed", range(6))
def test_may_loop_answers_as_the_whole_search(seed, monkeypatch):
    monkeypatch.setattr(loops, "SCAN_BYTES", 0)  # every text takes the windows
    for text in _texts(seed, 3000):
        assert loops.may_loop(text) == (loops._MAYBE.search(text) is not None), repr(text)


def test_may_loop_with_more_windows_than_text_searches_it_whole(monkeypatch):
    monkeypatch.setattr(loops, "SCAN_BYTES", 0)
    text = "x = 1 # for \n" * 50 + "body b[1 ..\n  ..] \n"
    assert loops.may_loop(text) == (loops._MAYBE.search(text) is not None) is True
    assert not loops.may_loop("# platform \n" * 100)


def test_a_big_file_without_loops_has_none():
    text = "body b1: particle(mass = 1 kg)\n" * 3000 + "# b1 ... b3000\nfind b1.vx@2\n"
    assert len(text) >= loops.SCAN_BYTES
    assert loops.expand(text) is None
    assert loops.expand(text + "for i in 1..2:\n    find b1.vx@2\n") is not None


@pytest.mark.parametrize("seed", range(6))
def test_may_name_by_regex_answers_as_the_find_walk(seed, monkeypatch):
    for text in _texts(100 + seed, 3000):
        monkeypatch.setattr(unit_system, "SCAN_BYTES", 1 << 60)
        walked = unit_system.may_name(text)
        monkeypatch.setattr(unit_system, "SCAN_BYTES", 0)
        assert unit_system.may_name(text) == walked, repr(text)
