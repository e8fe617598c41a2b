"""A small solve (fewer equations than rowcode.COMPILE_AFTER) walks its trees instead of
shaping them (rowcode.remembered): every example, and generated chains and cradles on
both sides of the limit, solve to the same values, bounds, checks, answers, blocks and
analysis, bit for bit, as with their trees shaped (and their shapes' walks compiled at
once or on second sight)."""
from __future__ import annotations

import pytest
from test_rowcode import scenes, solved

from momentum_cli import rowcode


def _solve(monkeypatch, text, name, plain_small, after=64):
    monkeypatch.setattr(rowcode, "PLAIN_SMALL", plain_small)
    monkeypatch.setattr(rowcode, "COMPILE_AFTER", after)
    for table in (rowcode._GS, rowcode._AFF, rowcode._VAL, rowcode._VGS, rowcode._SEEN):
        table.clear()
    return solved(text, name, True)


@pytest.mark.parametrize("name,text", [pytest.param(n, t, id=n) for n, t in scenes()])
def test_small_solve_walked_equals_shaped(monkeypatch, name, text):
    walked = _solve(monkeypatch, text, name, True)
    assert walked == _solve(monkeypatch, text, name, False)
    assert walked == _solve(monkeypatch, text, name, False, after=1)


def test_the_walks_are_taken_within_a_small_solve_only():
    with rowcode.remembered(rowcode.COMPILE_AFTER - 1):
        assert rowcode._PLAIN[0]
        with rowcode.remembered(10**6):  # the outermost decides
            assert rowcode._PLAIN[0]
    assert not rowcode._PLAIN[0]
    with rowcode.remembered(rowcode.COMPILE_AFTER):
        assert not rowcode._PLAIN[0]
    with rowcode.remembered():
        assert not rowcode._PLAIN[0]
