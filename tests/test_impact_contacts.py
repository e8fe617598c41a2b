"""Compile's fast paths give what the general path gives: every equation node for node
(and which nodes are shared, which fresh), the unknowns in column order, the
transitions' info, sources and losses, the friction sites and notes, on every example
and on generated chains, cradles (a sequence and one simultaneous impact) and random
scenes with rigid bodies, friction, pins and unknown restitution (tests/scenegen.py).
"""
from __future__ import annotations

from pathlib import Path

import pytest

from momentum_cli.bench import chain_text
from structure_dump import system_lines
from test_hard import cradle_text

ROOT = Path(__file__).resolve().parent.parent


def _sharing(system) -> list:
    """Every node of the system's trees as the index of its first appearance: the same
    list means the same sharing of nodes (the report tells numbers apart by identity;
    not 0, 1 and -1, which the replays share as expr.ZERO is)."""
    from momentum_cli.expr import Const

    seen: dict = {}
    out: list = []

    def walk(e):
        stack = [e]
        while stack:
            x = stack.pop()
            if x is None:
                continue
            if type(x) is Const and x.value in (0.0, 1.0, -1.0):
                out.append("Const")  # shared or not: the report gives 0, 1, -1 no dimension
                continue
            k = id(x)
            if k in seen:
                out.append(seen[k])
                continue
            seen[k] = len(seen)
            out.append(type(x).__name__)
            for name in ("terms", "factors"):
                kids = getattr(x, name, None)
                if kids is not None:
                    stack.extend(reversed(kids))
            for name in ("base", "arg"):
                kid = getattr(x, name, None)
                if kid is not None and not isinstance(kid, str):
                    stack.append(kid)

    for e in system.equations:
        walk(e.lhs)
        walk(e.rhs)
    for t in system.transitions:
        for _, a, b in t.contacts:
            walk(a)
            walk(b)
        for a in t.impulses:
            for v in (a.J, a.arm):
                walk(v.x)
                walk(v.y)
            walk(a.torque)
        for law in t.laws:
            walk(law.lhs)
            walk(law.rhs)
            walk(law.locked)
        if t.energy is not None:
            walk(t.energy[0])
            walk(t.energy[1])
    return out


def _compiled(text: str, fast: bool):
    from momentum_cli import impact_contacts, tree_template
    from momentum_cli.compile import _Compiler
    from momentum_cli.diagnostics import ProblemError
    from momentum_cli.scene import build
    from momentum_cli.source import Source
    from momentum_cli.syntax import parse

    from momentum_cli.expr import V2

    was = impact_contacts.ENABLED
    impact_contacts.ENABLED = tree_template.ENABLED = fast
    try:
        scene = build(parse(Source("t.mom", text)))
        c = _Compiler(scene, {})
        if not fast:  # vel's miss as sv asks for each component
            c._on_chain_v = lambda body, sid, w: V2(c.sv(body, "vx", sid),
                                                    c.sv(body, "vy", sid))
        system = c.run()
    except ProblemError as exc:
        return [f"error {exc}"]
    finally:
        impact_contacts.ENABLED = tree_template.ENABLED = was
    losses = []
    for k, ls in c.losses.items():
        losses.append(k)
        for e in ls:
            from structure_dump import node
            node(e, losses)
    sources = [(k, [repr(s) for s in v]) for k, v in c.sources.items()]
    return system_lines(system) + [repr(_sharing(system)), repr(losses), repr(sources)]


def _same(text: str) -> None:
    fast, slow = _compiled(text, True), _compiled(text, False)
    assert len(fast) == len(slow)
    for a, b in zip(fast, slow):
        assert a == b


EXAMPLES = sorted(str(p.relative_to(ROOT)) for p in (ROOT / "examples").glob("*.mom"))


@pytest.mark.parametrize("name", EXAMPLES)
def test_examples_compile_the_same_both_ways(name):
    _same((ROOT / name).read_text(encoding="utf-8"))


@pytest.mark.parametrize("n", [2, 3, 17, 120])
def test_chains_compile_the_same_both_ways(n):
    _same(chain_text(n))


@pytest.mark.parametrize("kind", ["sequence", "simultaneous"])
@pytest.mark.parametrize("n", [2, 5, 60])
def test_cradles_compile_the_same_both_ways(n, kind):
    _same(cradle_text(n, kind))


def test_random_scenes_compile_the_same_both_ways():
    """Rigid bodies, friction, pins, unknown e, the ground: every category of scenegen."""
    import scenegen

    n = 0
    for cat in scenegen.categories():
        for seed in range(12):
            sc = scenegen.generate(seed, cat)
            if sc is None:
                continue
            _same(scenegen.render(sc))
            n += 1
    assert n > 50


def test_a_tree_template_makes_the_builders_nodes_fresh_and_shares_what_it_shares():
    from momentum_cli.expr import V2, ZERO, Const, Known, Var, add, mul, neg
    from momentum_cli.tree_template import _shape, template

    def builder(a, b, k):
        s = add(a, neg(b))  # used twice: one node in both places
        return (mul(Const(0.5), s), add(mul(s, k), ZERO), V2(mul(Const(0.0), a), ZERO),
                add(ZERO, b))

    f = template(("test", 1), builder, 3)
    assert f is not None
    leaves = (Var("x"), Known("y", 2.0), Var("z"))
    got, want = f(*leaves), builder(*leaves)
    assert _shape(got, leaves, {id(ZERO): ZERO}) == _shape(want, leaves, {id(ZERO): ZERO})
    assert got[0].factors[1] is got[1].factors[0]  # the shared sum stays shared
    assert got[2].y is ZERO and got[2].x is ZERO
    again = f(*leaves)
    assert again[0].factors[0] is not got[0].factors[0]  # numbers are fresh each time
    assert got[3] is leaves[1]


def test_chains_and_cradles_take_the_templates():
    """The fast path is the one taken (a kind that failed to generate would fall back
    silently to the builders: equal, but slow)."""
    from momentum_cli import tree_template

    _compiled(chain_text(12), True)
    _compiled(cradle_text(4, "sequence"), True)
    kinds = {k[0] for k, f in tree_template._CACHE.items() if f is not None}
    assert {"contact", "momenta", "terms"} <= kinds
