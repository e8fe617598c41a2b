#!/usr/bin/env python3
"""How a file's solved blocks depend on each other: what could be batched, and what not.

A benchmark's companion, not a test. A block's values and error bounds need the blocks
that solved the unknowns its equations use (`bounds.propagate` runs block after block).
A block's level is one more than the highest level among those; blocks of one level
need nothing from each other, so only they could be solved or bounded together (as
arrays). Prints, per file: the number of blocks and of levels, the commonest levels,
and for each block size how many blocks and levels it spans.

    python bench/levels.py --chain 1000 --cradle-seq 1000 examples/hard/cradle_1000_sequence.mom
"""
from __future__ import annotations

import argparse
import collections
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "tests"))
sys.path.insert(0, str(ROOT / "bench"))

from stages import add_problem_arguments, problem_jobs  # noqa: E402 (after the paths)


def levels(name: str, text: str) -> str:
    """One paragraph on the dependencies among the solved blocks of `text`."""
    import momentum_cli.solve as S
    from momentum_cli.scene import build
    from momentum_cli.source import Source
    from momentum_cli.syntax import parse

    seen: dict = {}
    solve = S._solve

    def spy(system, structure, *a, **k):
        owner = {u: b.index for b in structure.blocks for u in b.unknowns}
        incidence = [list(v) for v in structure.incidence]  # dropped after the solve
        sol = solve(system, structure, *a, **k)
        level: dict[int, int] = {}
        for rep in sol.blocks:
            own = set(rep.unknowns)
            deps = {owner[v] for e in rep.equations for v in incidence[e]
                    if v not in own and v in owner}
            level[rep.index] = 1 + max((level.get(d, 0) for d in deps), default=0)
        seen["blocks"] = [(len(r.unknowns), level[r.index]) for r in sol.blocks]
        return sol

    S._solve = spy
    try:
        S.solve_scene(build(parse(Source(name, text))))
    finally:
        S._solve = solve
    blocks = seen["blocks"]
    per_level = collections.Counter(lv for _, lv in blocks)
    by_size: dict[int, set] = collections.defaultdict(set)
    count = collections.Counter(n for n, _ in blocks)
    for n, lv in blocks:
        by_size[n].add(lv)
    top = ", ".join(f"level {lv}: {c}" for lv, c in per_level.most_common(3))
    sizes = "; ".join(f"{count[n]} of {n} unknown{'s' if n > 1 else ''} in "
                      f"{len(by_size[n])} level{'s' if len(by_size[n]) > 1 else ''}"
                      for n in sorted(count))
    many = "s" if len(per_level) > 1 else ""
    return (f"{name}: {len(blocks)} blocks, {len(per_level)} level{many} ({top}); "
            f"blocks: {sizes}")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    add_problem_arguments(ap)
    args = ap.parse_args(argv)
    jobs = problem_jobs(args)
    for name, text in jobs:
        print(levels(name, text), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
