"""analyse's shortcuts give the structure of the string-keyed walk
(tests/reference_analyse.py): rows held as the shapes' tuples of names (`Incidence`),
the matching and the blocks made without the passes a fully matched system does not
need, and Tarjan's walk emitting a node whose successors are all finished at once."""
from __future__ import annotations

import random

import pytest

import reference_analyse as R
from momentum_cli import rowcode
from momentum_cli.analyse import Incidence, _blt, analyse
from momentum_cli.bench import chain_text
from test_compile_equal import _structure_order
from test_hard import cradle_text


def _system(text):
    from momentum_cli.compile import compile_scene
    from momentum_cli.scene import build
    from momentum_cli.source import Source
    from momentum_cli.syntax import parse

    return compile_scene(build(parse(Source("t.mom", text))))


TEXTS = [chain_text(n) for n in (2, 7, 120)] + \
    [cradle_text(n, kind) for n in (3, 50) for kind in ("sequence", "simultaneous")]


@pytest.mark.parametrize("text", TEXTS)
def test_analyse_within_a_solve_equals_the_string_keyed_one(text):
    """With the shapes remembered (the incidence read from them, as in a solve), also
    with unknowns known and equations excluded."""
    system = _system(text)
    names = list(system.unknowns)
    n_eqs = len(system.equations)
    with rowcode.remembered(n_eqs):
        for excluded, known in ((frozenset(), None),
                                (frozenset(range(0, n_eqs, 4)), None),
                                (frozenset(), {v: 1.0 for v in names[::3]}),
                                (frozenset({n_eqs - 1}), {v: 1.0 for v in names[1::5]})):
            got = analyse(system, excluded, known)
            assert isinstance(got.incidence, Incidence)
            assert _structure_order(got) == \
                _structure_order(R.analyse(system, excluded, known))


def test_incidence_reads_as_the_list_of_sets():
    rows = [("a", "b", "a"), {"c"}, ()]
    inc = Incidence(rows)
    assert len(inc) == 3 and inc[0] == {"a", "b"} and inc[1] is rows[1] and inc[2] == set()
    assert list(inc) == [{"a", "b"}, {"c"}, set()]
    assert inc == [{"a", "b"}, {"c"}, set()] and [{"a", "b"}, {"c"}, set()] == inc
    assert inc != [{"a"}, {"c"}, set()]


def _graph(seed: int):
    """A random graph: sparse and dense, with cycles, self-free, nodes in any order."""
    rng = random.Random(seed)
    n = rng.randint(1, 60)
    p = rng.choice((0.02, 0.05, 0.1, 0.3))
    back = rng.random() < 0.5  # mostly edges to earlier nodes: the common, acyclic case
    succ = []
    for v in range(n):
        ws = [w for w in range(n) if w != v and rng.random() < (p if not back or w < v
                                                                  else p / 10)]
        succ.append(sorted(ws))
    nodes = list(range(n))
    if rng.random() < 0.5:
        rng.shuffle(nodes)
    return n, succ, nodes


@pytest.mark.parametrize("seed", range(80))
def test_blocks_made_as_the_walk_emits_them_are_the_plain_walks(seed):
    """`_blt` (successors listed as the walk reaches them, blocks made as components are
    emitted) against the walk before the shortcut (tests/reference_analyse.py) and the
    blocks made afterwards from its components: the same components in the same order,
    the same unknowns and dependencies. Equation k is matched to column 2k+1 (its
    columns: its own and its successors'); the even columns are unmatched."""
    n, succ, nodes = _graph(seed)
    cols = [sorted([2 * k + 1] + [2 * d + 1 for d in succ[k]] + [2 * k]) for k in range(n)]
    mvar = [k // 2 if k % 2 else -1 for k in range(2 * n)]
    meq = [2 * k + 1 for k in range(n)]
    col_name = [f"x{c}" for c in range(2 * n)]
    blocks, block_of_eq = _blt(nodes, cols, mvar, meq, col_name, n)
    comps = R._tarjan(nodes, dict(enumerate(succ)))
    assert [b.equations for b in blocks] == [sorted(c) for c in comps]
    assert [b.index for b in blocks] == list(range(len(comps)))
    ref_of = {k: i for i, c in enumerate(comps) for k in c}
    assert block_of_eq == [ref_of.get(k, -1) for k in range(n)]
    for b in blocks:
        assert b.unknowns == [f"x{2 * k + 1}" for k in b.equations]
        assert b.depends == {ref_of[d] for k in b.equations for d in succ[k]} - {b.index}


def test_the_matching_dicts_are_made_when_asked_and_forgotten_when_replaced():
    """A solve never reads the matching's dicts (only an inconsistency's message does),
    nor the unknowns' blocks as a dict: they are made from the integer walk on first
    use, equal to the reference's, and replacing all three (run._shed) drops the walk."""
    system = _system(cradle_text(5, "sequence"))
    got = analyse(system)
    assert got._match_eq is None and got._match_var is None and got._block_of_var is None
    ref = R.analyse(system)
    assert list(got.match_var.items()) == list(ref.match_var.items())
    assert got._match_eq is None  # one asked, the others still not made
    assert list(got.match_eq.items()) == list(ref.match_eq.items())
    assert got._block_of_var is None
    assert list(got.block_of_var.items()) == list(ref.block_of_var.items())
    got = analyse(system)
    got.match_eq, got.match_var = {}, {}
    assert got._walk is not None  # the blocks' dict may still be asked for
    got.block_of_var = {}
    assert got._walk is None and got.match_eq == {} and got.block_of_var == {}
    assert got.needed_blocks(list(system.unknowns)) == []  # as with the dict emptied


@pytest.mark.parametrize("text", TEXTS)
def test_needed_blocks_from_the_walk_equal_those_from_the_dict(text):
    """needed_blocks reads an unknown's block through the walk's lists (no dict): the
    same blocks as through the reference's dict, for every unknown alone, random sets,
    names that are no unknown, and with unknowns known and equations excluded."""
    system = _system(text)
    names = list(system.unknowns) + ["nobody.vx@1"]
    rng = random.Random(len(text))
    n_eqs = len(system.equations)
    for excluded, known in ((frozenset(), None), (frozenset(range(0, n_eqs, 3)), None),
                            (frozenset(), {v: 1.0 for v in names[::4]})):
        got = analyse(system, excluded, known)
        ref = R.analyse(system, excluded, known)
        assert got._block_of_var is None
        asks = [[n] for n in names] + [rng.sample(names, min(len(names), k))
                                       for k in (2, 5, 40) for _ in range(10)] + [names]
        for ask in asks:
            assert got.needed_blocks(ask) == ref.needed_blocks(ask), ask
        assert got._block_of_var is None  # never made to answer them
