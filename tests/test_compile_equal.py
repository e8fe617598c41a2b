"""Build, compile and analyse give what they gave before their fast paths: every
equation node for node, the unknowns in column order, the transitions' info and the
structure (matching, blocks in order), on every example and on generated big scenes.

The digests in tests/data/structure_digests.json were recorded with the code before the
rewrite (tests/structure_dump.py; regenerate only for an intended change of output).
"""
from __future__ import annotations

import json
from pathlib import Path

import pytest

from momentum_cli.bench import chain_text
from structure_dump import digest
from test_hard import cradle_text

ROOT = Path(__file__).resolve().parent.parent
DIGESTS = json.loads((ROOT / "tests" / "data" / "structure_digests.json").read_text())
EXAMPLES = sorted(k for k in DIGESTS if k.startswith("examples/"))


@pytest.mark.parametrize("name", EXAMPLES)
def test_examples_compile_and_analyse_as_before(name):
    assert digest((ROOT / name).read_text(encoding="utf-8"), name) == DIGESTS[name]


@pytest.mark.parametrize("n", [2, 3, 40, 301])
def test_chain_compiles_as_before(n):
    assert digest(chain_text(n)) == DIGESTS[f"chain {n}"]


@pytest.mark.parametrize("kind", ["sequence", "simultaneous"])
@pytest.mark.parametrize("n", [2, 3, 25, 201])
def test_cradle_compiles_as_before(n, kind):
    assert digest(cradle_text(n, kind)) == DIGESTS[f"cradle {kind} {n}"]


def _structure_order(s) -> tuple:
    """Everything of a Structure, the iteration order of its dicts and sets included."""
    return (s.incidence, list(s.match_eq.items()), list(s.match_var.items()), list(s.under),
            list(s.under_eqs), s.redundant,
            [(b.index, b.equations, b.unknowns, list(b.depends)) for b in s.blocks],
            list(s.block_of_var.items()), s.constant_eqs)


def _systems():
    from momentum_cli.compile import compile_scene
    from momentum_cli.diagnostics import ProblemError
    from momentum_cli.scene import build
    from momentum_cli.source import Source
    from momentum_cli.syntax import parse

    texts = [(name, (ROOT / name).read_text(encoding="utf-8")) for name in EXAMPLES]
    texts += [("chain", chain_text(60)), ("cradle", cradle_text(30, "sequence"))]
    for name, text in texts:
        try:
            yield name, compile_scene(build(parse(Source(name, text))))
        except ProblemError:
            continue


def test_integer_analyse_equals_the_string_keyed_one():
    """On every example, also with some unknowns known and some equations excluded (as
    solve and the numeric rank check call it)."""
    import reference_analyse as R

    from momentum_cli.analyse import analyse

    n = 0
    for name, system in _systems():
        names = list(system.unknowns)
        for excluded, known in ((frozenset(), None),
                                (frozenset(range(0, len(system.equations), 3)), None),
                                (frozenset(), {v: 1.0 for v in names[::2]}),
                                (frozenset({len(system.equations) - 1}),
                                 {v: 1.0 for v in names[1::3]})):
            assert _structure_order(analyse(system, excluded, known)) == \
                _structure_order(R.analyse(system, excluded, known)), name
            n += 1
    assert n > 200


def test_literal_directions_and_numbers_keep_the_sign_of_their_zeros():
    """scene evaluates a literal direction (and number) once per value: 0 and -0 are two
    (a parser may fold `-0.0` into one literal)."""
    import math

    from momentum_cli import syntax as S
    from momentum_cli.scene import _Builder
    from momentum_cli.source import Source, Span
    from momentum_cli.syntax import parse
    from momentum_cli.units import NONE

    sp = Span(1, 1, 1, 2)

    def vec(x):
        return S.VecLit(sp, S.Num(sp, x), S.Num(sp, 1.0))

    def same(p, q):
        return all(x == y and math.copysign(1.0, x) == math.copysign(1.0, y)
                   for x, y in zip(p, q))

    for order in ((0.0, -0.0, 2.5), (-0.0, 0.0, 2.5)):
        builder = _Builder(parse(Source("t.mom", "body a: particle(mass = 1 kg)\n")))
        for x in order:  # the remembered answer is the one evaluated afresh
            assert same(builder.unit_vector(vec(x), "n"), builder._unit_vector(vec(x), "n"))
            assert same([builder.value(S.Num(sp, x), NONE, "x")],
                        [builder._value(S.Num(sp, x), NONE, "x")])
