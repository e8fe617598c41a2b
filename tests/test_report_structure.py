"""The report's shortcuts that read a structure once instead of walking it per item,
against the general code they stand for: `statements._variables` (a law's names, a
sum's products read in its loop) is `expr.variables`, the same set in the same order,
on every example, chains, cradles (sequence and simultaneous) and scenegen scenes."""
from __future__ import annotations

import sys
from pathlib import Path

from momentum_cli.bench import chain_text
from momentum_cli.expr import Add, Const, Known, Mul, Var, variables
from momentum_cli.report import statements
from momentum_cli.scene import build
from momentum_cli.solve import ProblemError, solve_scene
from momentum_cli.source import Source
from momentum_cli.syntax import parse

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tests"))
from test_hard import cradle_text  # noqa: E402


def _texts():
    for p in sorted((ROOT / "examples").glob("*.mom")):
        yield p.read_text(encoding="utf-8")
    yield chain_text(30)
    for kind in ("sequence", "simultaneous"):
        yield cradle_text(12, kind)
    import scenegen

    for cat in scenegen.categories():
        for seed in range(3):
            sc = scenegen.generate(seed, cat)
            if sc is not None:
                yield scenegen.render(sc)


def _solutions():
    for t in _texts():
        try:
            yield solve_scene(build(parse(Source("x.mom", t))))
        except ProblemError:
            continue


def test_law_names_by_the_loop_equal_variables():
    n = 0
    for sol in _solutions():
        for t in sol.system.transitions:
            for law in getattr(t, "laws", ()) or ():
                for e in (law.lhs, law.rhs, law.locked):
                    if e is None:
                        continue
                    got, want = statements._variables(e), variables(e)
                    assert got == want and list(got) == list(want)
                    n += 1
    assert n > 50


def test_law_names_drop_a_product_with_a_zero_known_factor():
    a, b, c = Var("a"), Var("b"), Var("c")
    e = Add((Mul((Known("m", 0.0), a)), Mul((Const(2.0), b)), c, Const(1.0),
             Mul((Known("k", 3.0), Add((a, Mul((Const(0.0), c))))))))
    assert statements._variables(e) == variables(e) == {"b", "c", "a"}
    assert list(statements._variables(e)) == list(variables(e))


def test_terms_of_long_sums_by_the_last_terms_matcher_equal_their_walks(monkeypatch):
    """`printer._term_printers(x, last)` (the term before's matcher tried first) gives
    the leaves and printers the walk finds, term by term: the laws of chains and
    cradles, and sums whose terms change shape (a matcher that must refuse)."""
    from momentum_cli.report import printer

    monkeypatch.setattr(printer, "COMPILE_AFTER", 0)
    a, b, c = Var("a"), Var("b"), Var("c")
    odd = Add((Mul((Known("m", 2.0), a)), Mul((Known("n", 3.0), b)), c,
               Mul((Const(-1.0), a, b)), Mul((Known("p", 4.0), c)), Const(5.0),
               Mul((Known("q", 1.5), Add((a, b))))))
    sums = [odd]
    for text in (chain_text(40), cradle_text(6, "simultaneous")):
        sol = solve_scene(build(parse(Source("x.mom", text))))
        for t in sol.system.transitions:
            for law in getattr(t, "laws", ()) or ():
                sums += [e for e in (law.lhs, law.rhs) if type(e) is Add]
    n = 0
    for e in sums:
        last: list = [None, None]
        for x in e.terms:
            got = printer._term_printers(x, last)
            want = printer._term_printers(x)
            assert bool(got) == bool(want)
            if got:
                assert got[0] == want[0] and [type(y) for y in got[0]] == \
                    [type(y) for y in want[0]]
                assert got[1] is want[1]
                n += 1
    assert n > 100
