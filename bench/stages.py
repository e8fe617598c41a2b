#!/usr/bin/env python3
"""CPU time per stage of one solve, in-process: where a large file's time goes.

A benchmark, not a test. Stages: parse, build (the scene), compile, analyse, solve
(`solve._solve`: the blocks, bounds and answers), rest (the rest of `solve_scene`:
regimes, checks), report (`build_report` as `solve --plain` makes it: streamed, its
transitions, blocks, unknowns and, since the twelfth session, checks as they are
read: the checks are in render), render (plain text,
`text.render_parts`, with what of the report it reads). CPU seconds
(process time: robust against a busy machine), the minimum over --reps runs of
build and solve (the parse and report run once); cyclic GC off, as `solve` runs.

    python bench/stages.py --cradle-seq 1000 --cradle-seq 10000
    python bench/stages.py --chain 10000 examples/seed_rod_drop_smooth.mom --reps 5
"""
from __future__ import annotations

import argparse
import gc
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "tests"))

STAGES = ("parse", "build", "compile", "analyse", "solve", "rest", "report", "render")


def stages(name: str, text: str, reps: int = 1) -> dict[str, float]:
    """CPU seconds per stage of solving `text` (minimum over `reps` for build..rest)."""
    import momentum_cli.solve as S
    from momentum_cli.report.model import build_report
    from momentum_cli.report.text import render_parts
    from momentum_cli.scene import build
    from momentum_cli.source import Source
    from momentum_cli.syntax import parse

    best: dict[str, float] = {}
    spent: dict[str, float] = {}

    def timed(key, f):
        def g(*a, **k):
            t0 = time.process_time()
            try:
                return f(*a, **k)
            finally:
                spent[key] = spent.get(key, 0.0) + time.process_time() - t0
        return g

    def keep(key, t):
        best[key] = min(best.get(key, t), t)

    saved = {k: getattr(S, k) for k in ("compile_scene", "analyse", "_solve")}
    was = gc.isenabled()
    gc.disable()
    try:
        t0 = time.process_time()
        doc = parse(Source(name, text))
        keep("parse", time.process_time() - t0)
        for k, key in (("compile_scene", "compile"), ("analyse", "analyse"), ("_solve", "solve")):
            setattr(S, k, timed(key, saved[k]))
        for _ in range(max(1, reps)):
            spent.clear()
            t0 = time.process_time()
            scene = build(doc)
            t1 = time.process_time()
            sol = S.solve_scene(scene)
            t2 = time.process_time()
            keep("build", t1 - t0)
            for key in ("compile", "analyse", "solve"):
                keep(key, spent.get(key, 0.0))
            keep("rest", t2 - t1 - sum(spent.values()))
        for k, f in saved.items():
            setattr(S, k, f)
        t0 = time.process_time()
        rep = build_report(name, sol, 6, "file", lazy=True)
        t1 = time.process_time()
        render_parts(rep, 6)
        keep("report", t1 - t0)
        keep("render", time.process_time() - t1)
    finally:
        for k, f in saved.items():
            setattr(S, k, f)
        if was:
            gc.enable()
    return best


def add_problem_arguments(ap: argparse.ArgumentParser) -> None:
    """The problems a bench script runs on: files, generated cradles and chains."""
    ap.add_argument("files", nargs="*", help="problem files")
    ap.add_argument("--cradle-seq", type=int, action="append", default=[],
                    help="the sequential Newton's cradle of N balls (tests/test_hard.py)")
    ap.add_argument("--chain", type=int, action="append", default=[],
                    help="the N-ball chain of `momentum bench accuracy`")


def problem_jobs(args) -> list[tuple[str, str]]:
    """(name, text) of each problem `add_problem_arguments` read from the command line."""
    jobs = [(f, Path(f).read_text(encoding="utf-8")) for f in args.files]
    if args.cradle_seq:
        from test_hard import cradle_text

        jobs += [(f"cradle-seq {n}", cradle_text(n, "sequence")) for n in args.cradle_seq]
    if args.chain:
        from momentum_cli.bench import chain_text

        jobs += [(f"chain {n}", chain_text(n)) for n in args.chain]
    return jobs


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    add_problem_arguments(ap)
    ap.add_argument("--reps", type=int, default=1)
    args = ap.parse_args(argv)
    jobs = problem_jobs(args)
    print("  ".join(["problem".rjust(16), *(s.rjust(8) for s in STAGES), "total".rjust(8)]))
    for name, text in jobs:
        t = stages(name, text, args.reps)
        print("  ".join([name.rjust(16), *(f"{t[s]:8.3f}" for s in STAGES),
                         f"{sum(t.values()):8.3f}"]), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
