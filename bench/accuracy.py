"""Accuracy against time, for the README: every precision mode on the seed and hard
examples and on ball chains of growing length.

    python bench/accuracy.py [FILE ...] [--sizes 10,100,1000,10000] [--repeat 3]
                             [--plot bench/results/accuracy.png]

Prints a Markdown table (the one in the README), with the command, the number of runs
and the library versions under it, and, if matplotlib is installed, draws error
against time. Times are the best of --repeat runs, in process (start-up excluded).
Files default to the seed examples and the hard cases. A benchmark, not a test.
"""
from __future__ import annotations

import argparse
import math
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(__file__), ".."))

from momentum_cli.bench import accuracy, default_files, default_problems, versions  # noqa: E402


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("files", nargs="*", help="problem files (default: seeds and hard cases)")
    ap.add_argument("--sizes", default="10,100,1000,10000")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--plot", default=None)
    args = ap.parse_args()
    root = os.path.join(os.path.dirname(__file__), "..")
    files = args.files or default_files(root)
    sizes = [int(s) for s in args.sizes.split(",") if s.strip()]
    problems = default_problems(files, sizes)
    accuracy(problems[:1], 1)  # warm-up, untimed: imports and the parser's cache
    rows = accuracy(problems, args.repeat,
                    progress=lambda n, p: print(f"  {n}: {p}", file=sys.stderr))
    print("| problem | unknowns | float: ms, error | refine: ms, error | exact: ms |")
    print("|---|---:|---:|---:|---:|")
    by = {}
    for r in rows:
        by.setdefault(r.problem, {})[r.precision] = r
    for name, d in by.items():
        def cell(p):
            r = d.get(p)
            if r is None:
                return "failed"
            if r.rel_error is None:
                return "—" if r.note.startswith("skipped") else "refused"
            e = "0" if r.rel_error == 0 else f"{r.rel_error:.1e}"
            t = f"{r.seconds:.3g} s" if r.seconds >= 1 else f"{r.seconds * 1e3:.3g} ms"
            return f"{t}, {e}" if p != "exact" else t
        short = os.path.relpath(name, root) if os.path.exists(name) else name
        n = max(r.unknowns for r in d.values())
        print(f"| {short} | {n} | {cell('float')} | {cell('refine')} | {cell('exact')} |")
    cmd = " ".join(["python bench/accuracy.py"] + sys.argv[1:])
    print(f"\nProduced by `{cmd}`: best of {args.repeat} run(s) per cell, in process; "
          f"{versions()}.")
    if args.plot:
        try:
            import matplotlib

            matplotlib.use("Agg")
            import matplotlib.pyplot as plt
        except ImportError:
            print("matplotlib is not installed: no plot", file=sys.stderr)
            return
        fig, ax = plt.subplots(figsize=(7, 4.5))
        for p, mark in (("float", "o"), ("refine", "s"), ("exact", "^")):
            pts = [(r.seconds, max(r.rel_error, 1e-17)) for r in rows
                   if r.precision == p and r.rel_error is not None and math.isfinite(r.seconds)]
            ax.scatter([t for t, _ in pts], [e for _, e in pts], marker=mark, label=p)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("wall time per solve (s)")
        ax.set_ylabel("relative error against exact (1e-17 = exact)")
        ax.legend()
        os.makedirs(os.path.dirname(args.plot) or ".", exist_ok=True)
        fig.tight_layout()
        fig.savefig(args.plot, dpi=120)
        print(f"wrote {args.plot}", file=sys.stderr)


if __name__ == "__main__":
    main()
