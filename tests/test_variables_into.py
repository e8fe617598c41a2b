"""rowcode.variables_into (the unknowns of a sum of many terms from the terms' shapes)
against expr.variables: the same names on every example and on generated scenes."""
from __future__ import annotations

import glob
import os

from momentum_cli import rowcode
from momentum_cli.bench import chain_text
from momentum_cli.diagnostics import ProblemError
from momentum_cli.scene import build
from momentum_cli.solve import solve_scene
from momentum_cli.source import Source
from momentum_cli.syntax import parse

EXAMPLES = sorted(p for p in glob.glob("examples/*.mom") + glob.glob("examples/hard/*.mom")
                  if os.path.getsize(p) < 40_000)  # not the generated 1000-ball files


def test_variables_by_shapes_is_variables():
    """rowcode.variables_into names what expr.variables names, on every example's
    equations and energies summed, zero products and all."""
    from momentum_cli.expr import add_all, variables

    for path in EXAMPLES + ["chain"]:
        text = chain_text(40) if path == "chain" else open(path, encoding="utf-8").read()
        try:
            sol = solve_scene(build(parse(Source(path, text))))
        except ProblemError:
            continue
        exprs = [e.residual for e in sol.system.equations]
        exprs += [T for t in sol.system.transitions if t.energy is not None for T in t.energy]
        for e in exprs + [add_all(exprs)]:
            got: set = set()
            with rowcode.remembered():
                rowcode.variables_into(e, got, variables)
            assert got == variables(e), path


def test_variables_by_shapes_of_a_difference_of_sums():
    from momentum_cli.expr import Const, Known, Var, add_all, mul, neg, variables

    a = add_all([mul(Known("m", 2.0), mul(Var(f"v{i}"), Var(f"v{i}"))) for i in range(40)])
    b = add_all([mul(Known("m", 0.0), Var(f"w{i}")) for i in range(20)] +
                [mul(Const(3.0), Var(f"u{i}")) for i in range(30)])
    for e in (add_all([a, neg(b)]), add_all([neg(a), b, mul(Const(0.0), a)])):
        got: set = set()
        with rowcode.remembered():
            rowcode.variables_into(e, got, variables)
        assert got == variables(e)
