"""A small square block's bounds step in one loop (`bounds._square`, its kind's parts
keyed from lists) against `propagate`'s general step: the same sizes and error bounds,
bit for bit and in the same order, on every example, cradles and chains."""
from __future__ import annotations

import math

import pytest

from momentum_cli import block_memo, bounds, rowcode
from momentum_cli.bench import chain_text
from momentum_cli.diagnostics import ProblemError

from helpers import solve_keeping_system


def _bits(d: dict) -> list:
    return [(k, repr(v), math.copysign(1.0, v) if v == 0.0 else 0) for k, v in d.items()]


def _solved(monkeypatch, text: str, name: str, precision: str = "float"):
    """(system, reports, values) of a solve, or None where it does not solve."""
    try:
        sol, system = solve_keeping_system(monkeypatch, text, name, precision=precision)
    except ProblemError:
        return None
    return system, sol.blocks, dict(sol.values)


def _same_both_ways(monkeypatch, system, reports, values, exact=False, kinds=True):
    got = []
    monkeypatch.setattr(block_memo, "KINDS", kinds)
    for on in (True, False, True):  # the second time on: the kinds' table warm
        monkeypatch.setattr(bounds, "SQUARE", on)
        with rowcode.remembered():
            size, err = bounds.propagate(system, reports, values, exact)
        got.append((_bits(size), _bits(err)))
    assert got[0] == got[1] == got[2]


def _texts():
    from conftest import EXAMPLES
    from test_hard import cradle_text

    out = [(p.name, p.read_text(encoding="utf-8")) for p in sorted(EXAMPLES.rglob("*.mom"))]
    out.append(("cradle-seq.mom", cradle_text(40, "sequence")))
    out.append(("cradle-sim.mom", cradle_text(40, "simultaneous")))
    out.append(("chain.mom", chain_text(30, 4.0, 0.8)))
    return out


def test_every_example_bounds_the_same(monkeypatch):
    n = 0
    for name, text in _texts():
        got = _solved(monkeypatch, text, name)
        if got is None:
            continue
        system, reports, values = got
        n += any(1 < len(r.unknowns) <= block_memo.SMALL and r.method == "linear"
                 for r in reports)
        _same_both_ways(monkeypatch, system, reports, values)
        _same_both_ways(monkeypatch, system, reports, values, exact=True)
        _same_both_ways(monkeypatch, system, reports, values, kinds=False)
    assert n > 20  # the step is met


@pytest.mark.parametrize("e", ["1", "0.9", "0.37"])
def test_cradles_of_other_restitutions_bound_the_same(monkeypatch, e):
    from test_hard import cradle_text

    text = cradle_text(50, "sequence").replace("restitution 1,", f"restitution {e},")
    system, reports, values = _solved(monkeypatch, text, "cradle.mom")
    _same_both_ways(monkeypatch, system, reports, values)


def test_exact_mode_bounds_the_same(monkeypatch):
    from test_hard import cradle_text

    system, reports, values = _solved(monkeypatch, cradle_text(12, "sequence"), "c.mom",
                                      precision="exact")
    _same_both_ways(monkeypatch, system, reports, values, exact=True)
