"""compile's whole-impact paths give what _impulse_phase gives: impact_phase (an impact of
particles at simple contacts, replayed whole from one template per kind, or contact by
contact) and why_texts (why-lines and linear-law texts from per-kind format strings),
switched on and off one at a time, compared line by line (every equation node and its
sharing, unknowns in column order, transitions' texts, sources, losses) on every example
and on generated chains, cradles and scenegen scenes (tests/test_impact_contacts.py).
"""
from __future__ import annotations

import pytest

from momentum_cli.bench import chain_text
from test_hard import cradle_text
from test_impact_contacts import EXAMPLES, ROOT, _compiled

# (impact_phase.ENABLED, impact_phase.TEMPLATE, why_texts.ENABLED)
ON = (True, True, True)
WAYS = [(True, False, True), (True, True, False), (False, True, True)]


def _with(flags, text: str, fast: bool = True) -> list:
    from momentum_cli import impact_phase, why_texts

    was = (impact_phase.ENABLED, impact_phase.TEMPLATE, why_texts.ENABLED)
    impact_phase.ENABLED, impact_phase.TEMPLATE, why_texts.ENABLED = flags
    try:
        return _compiled(text, fast)
    finally:
        impact_phase.ENABLED, impact_phase.TEMPLATE, why_texts.ENABLED = was


def _same_every_way(text: str) -> None:
    want = _with((False, False, False), text, fast=False)  # the elements, no template
    for flags in [ON] + WAYS:
        got = _with(flags, text)
        assert len(got) == len(want), flags
        for a, b in zip(got, want):
            assert a == b, flags


@pytest.mark.parametrize("name", EXAMPLES)
def test_examples_compile_the_same_with_the_impact_paths(name):
    _same_every_way((ROOT / name).read_text(encoding="utf-8"))


@pytest.mark.parametrize("n", [2, 3, 9, 40])
def test_chains_compile_the_same_with_the_impact_paths(n):
    _same_every_way(chain_text(n))


@pytest.mark.parametrize("kind", ["sequence", "simultaneous"])
@pytest.mark.parametrize("n", [2, 3, 9, 40])
def test_cradles_compile_the_same_with_the_impact_paths(n, kind):
    _same_every_way(cradle_text(n, kind))


def _mixed(n: int) -> str:
    """Particles of several radii meeting in a row, on the ground and with unknown or
    given velocities later: the kinds a cradle does not make (round contacts, the ground,
    several contacts an impact, a state given after the impacts, repeated states)."""
    out = ['problem "mixed impacts"\n']
    for k in range(1, n + 1):
        r = "" if k % 3 == 0 else f", radius = {10 + k} mm"
        out.append(f"body p{k}: particle(mass = {0.1 + 0.05 * k} kg{r})\n")
    rest = ", ".join(f"p{k} at rest" for k in range(2, n + 1))
    out.append(f"state 1: p1.v = (2 m/s, 0.5 m/s), {rest}\n")
    for k in range(2, n + 1):
        out.append(f"state {k}\n")
    out.append(f"state {n + 1}: p{n}.vy = 0\n")
    for k in range(1, n):
        e = "0.5" if k % 2 else "1"
        out.append(f"impact {k} -> {k + 1}:\n    contact c{k}: p{k + 1} with p{k} normal "
                   f"(1, 0): restitution {e}, smooth\n")
        if k % 4 == 0:
            out.append(f"    contact g{k}: p{k} with ground normal (0, 1): restitution 0.3\n")
    out.append(f"impact {n} -> {n + 1}:\n    contact last: p{n} with ground normal "
               "(0.6, 0.8): restitution 0.2\n")
    out.append(f"find p1.vx@{n + 1}, p{n}.vx@{n + 1}, T@1, T@{n + 1}\n")
    return "".join(out)


@pytest.mark.parametrize("n", [3, 8, 13])
def test_mixed_impacts_compile_the_same_with_the_impact_paths(n):
    _same_every_way(_mixed(n))


def test_random_scenes_compile_the_same_with_the_impact_paths():
    """Rigid bodies, friction, pins, unknown e, the ground: every category of scenegen."""
    import scenegen

    n = 0
    for cat in scenegen.categories():
        for seed in range(8):
            sc = scenegen.generate(seed, cat)
            if sc is None:
                continue
            _same_every_way(scenegen.render(sc))
            n += 1
    assert n > 30


def test_the_impact_paths_are_taken():
    """A cradle takes the whole-impact template and the text plans (a kind that failed
    to generate would fall back silently: equal, but slow)."""
    from momentum_cli import tree_template, why_texts

    _with(ON, cradle_text(5, "sequence"))
    _with(ON, _mixed(6))
    kinds = {k[0] for k, f in tree_template._CACHE.items() if f is not None}
    assert "impact" in kinds
    plans = {k[0] for k, p in why_texts._PLANS.items() if p is not None}
    assert {"why", "linear"} <= plans


def test_why_texts_keep_names_with_braces_and_their_sort_order():
    """Stand-in names sort as the real ones do, and braces in a name are not fields."""
    from momentum_cli.elements.base import ImpulseSource
    from momentum_cli.system_laws import linear_head
    from momentum_cli.why_texts import linear_texts

    from momentum_cli.compile import _Compiler
    from momentum_cli.why_texts import why_lines

    comp = object.__new__(_Compiler)  # _why reads nothing of it when given the bodies

    for names in (("zeta{", "alpha}"), ("alpha}", "zeta{")):
        srcs = [ImpulseSource(("A", None), "P{0}", (1.0, 0.0), False, f"contact {names[0]}"),
                ImpulseSource(("B", None), "Q", (0.0, 1.0), False, f"contact {names[1]}"),
                ImpulseSource(("A", "B"), "R", None, False, "pin {x}")]
        for bodies in (["A", "B"], ["B", "A"], ["A"]):
            assert why_lines(comp, srcs, bodies) == comp._why(srcs, None, bodies)
        par = srcs[:1] + [ImpulseSource(("B", None), "Q", (-1.0, 0.0), False,
                                         f"contact {names[1]}")]
        got = linear_texts(par, ["A", "B"])
        head = linear_head(par, ["A", "B"])
        assert got[:2] == (head[0], head[1])
        assert got[2] == ["linear momentum of {A, B} along y: sum of m v before = sum of m v "
                          "after"]
