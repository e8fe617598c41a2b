"""Blocks of one kind share a factorization and their bounds' matrix parts (block_memo,
bounds.propagate): whole solves with it equal the
same solves with every block eliminated afresh, bit for bit, on every example and on
generated sequences whose impacts repeat one matrix with other right-hand sides."""
from __future__ import annotations

import pytest
from conftest import EXAMPLES
from test_hard import cradle_text
from test_rowcode import snapshot

from momentum_cli import block_memo
from momentum_cli.bench import chain_text
from momentum_cli.diagnostics import ProblemError
from momentum_cli.scene import build
from momentum_cli.solve import solve_scene
from momentum_cli.source import Source
from momentum_cli.syntax import parse


def solved(text: str, name: str, kinds: bool, precision: str = "float"):
    saved = block_memo.KINDS
    block_memo.KINDS = kinds
    block_memo._solves.clear(), block_memo._factors.clear(), block_memo._kinds.clear()
    try:
        return snapshot(solve_scene(build(parse(Source(name, text))), precision=precision))
    except ProblemError as exc:
        return [[d.code, d.message, d.notes] for d in exc.diagnostics]
    finally:
        block_memo.KINDS = saved


def scenes():
    for path in sorted(EXAMPLES.glob("*.mom")):
        yield path.name, path.read_text(encoding="utf-8")
    yield "chain 30", chain_text(30)
    seq = cradle_text(30, "sequence")
    yield "cradle-seq 30", seq
    yield "cradle-seq 30, e = 0.9", seq.replace("restitution 1,", "restitution 0.9,")
    yield "cradle-seq 30, e = 0.37", seq.replace("restitution 1,", "restitution 0.37,")
    yield "cradle-sim 12", cradle_text(12, "simultaneous")


@pytest.mark.parametrize("name,text", [pytest.param(n, t, id=n) for n, t in scenes()])
def test_shared_factorizations_equal_fresh_solves(name, text):
    assert solved(text, name, True) == solved(text, name, False)


def test_a_sequence_of_one_kind_is_factored_once():
    text = cradle_text(20, "sequence").replace("restitution 1,", "restitution 0.9,")
    block_memo._solves.clear(), block_memo._factors.clear()
    solve_scene(build(parse(Source("c.mom", text))))
    assert len(block_memo._factors) == 1  # 19 impacts, one matrix, 19 right-hand sides


def test_generated_scenes_solve_the_same_every_way():
    """Random impact scenes (rigid bodies, friction, pins, welds, links: tests/scenegen.py):
    shared factorizations against fresh solves, and the whole fast solve (shapes taken by
    the analysis, compiled rows) against the plain walks."""
    import scenegen as g
    from test_rowcode import solved as solved_rowcode

    done = 0
    for seed in range(40):
        sc = g.generate(seed)
        if sc is None:
            continue
        text = g.render(sc)
        name = f"generated {seed}"
        assert solved(text, name, True) == solved(text, name, False), seed
        assert solved_rowcode(text, name, True) == solved_rowcode(text, name, False), seed
        done += 1
    assert done >= 30
