"""`momentum bench accuracy`: what each extra digit costs, measured.

For each problem (files given, plus generated chains of colliding balls) every
precision mode is timed, in process, and its answers compared with the `exact`
mode's, which are the correctly rounded solution of the stated data. The chains
are one simultaneous impact of N balls with masses spread over many decades, the
hardest shape for float64 and the one whose cost must grow linearly with N.
"""
from __future__ import annotations

import math
import time

from .records import record

PRECISIONS = ("float", "refine", "exact")
LIBRARIES = ("numpy", "scipy", "lark")


def versions() -> str:
    """Python and the numeric libraries' versions (from their metadata: importing them
    here would be timed), and the machine, for the line under a measured table."""
    import os
    import platform
    import sys
    from importlib import metadata

    libs = []
    for name in LIBRARIES:
        try:
            libs.append(f"{name} {metadata.version(name)}")
        except metadata.PackageNotFoundError:
            libs.append(f"{name} (not installed)")
    return (f"python {sys.version.split()[0]}, {', '.join(libs)}; {platform.system()} "
            f"{platform.machine()}, {os.cpu_count()} CPUs")


@record
class BenchRow:
    problem: str
    unknowns: int
    precision: str
    seconds: float
    rel_error: float | None  # against the exact mode's answers; None if it failed
    error_bound: float | None  # the report's own estimate (largest over blocks)
    note: str = ""


def _chain(title: str, masses: list[float], e: float, finds: str) -> str:
    """Balls in a row, all touching, ball 1 moving at 1 m/s: one simultaneous impact
    with restitution e at every contact."""
    n = len(masses)
    lines = [f'problem "{title}"']
    lines += [f"body b{k}: particle(mass = {m!r} kg)" for k, m in enumerate(masses, 1)]
    rest = ", ".join(f"b{k} at rest" for k in range(2, n + 1))
    lines.append(f"state 1: b1.v = (1 m/s, 0){', ' + rest if rest else ''}")
    lines += ["state 2", "impact 1 -> 2:"]
    lines += [f"    contact b{k + 1} with b{k} normal (1, 0): restitution {e}"
              for k in range(1, n)]
    lines.append(f"find {finds}")
    return "\n".join(lines) + "\n"


def chain_text(n: int, decades: float = 6.0, e: float = 0.5) -> str:
    """N balls with masses 10^(decades * sin(k)), over 2*decades decades."""
    masses = [10 ** (decades * math.sin(k)) for k in range(1, n + 1)]
    return _chain(f"chain of {n} balls, masses over {2 * decades:g} decades", masses, e,
                  f"b1.vx@2, b{n}.vx@2, T_lost@1->2")


def hard_chain_text() -> str:
    """The 49-unknown chain: 25 balls, masses log-spaced from 1e-12 to 1e12 kg."""
    masses = [float(f"1e{-12 + k}") for k in range(25)]
    return _chain("hard chain: 25 balls, masses 1e-12 .. 1e12 kg", masses, 0.9,
                  "b1.vx@2, b25.vx@2, b13.vx@2")


def _run(text: str, name: str, precision: str):
    from .run import _NoCyclicGC
    from .scene import build
    from .solve import solve_scene
    from .source import Source
    from .syntax import parse

    t0 = time.perf_counter()
    with _NoCyclicGC():
        sol = solve_scene(build(parse(Source(name, text))), precision=precision)
    dt = time.perf_counter() - t0
    bound = max((b.quality.bound for b in sol.blocks if b.quality is not None), default=0.0)
    return dt, [si for _, _, _, si in sol.answers], len(sol.system.unknowns), bound


def _rel_error(got: list[float], want: list[float]) -> float:
    scale = max((abs(w) for w in want), default=0.0) or 1.0
    worst = 0.0
    for g, w in zip(got, want):
        # relative to the answer itself, or to the problem's scale for a zero answer
        denom = abs(w) if abs(w) > 1e-300 else scale
        worst = max(worst, abs(g - w) / denom)
    return worst


EXACT_LIMIT = 300_000  # above this many characters, rationals grow too long to wait for


def accuracy(problems: list[tuple[str, str]], repeat: int = 3, progress=None) -> list[BenchRow]:
    """Time each precision on each (name, text) problem; errors against `exact`
    (against `refine` for the largest problems, where exact rationals grow too long)."""
    from .diagnostics import ProblemError

    rows: list[BenchRow] = []
    for name, text in problems:
        results = {}
        big = len(text) > EXACT_LIMIT
        for p in ("refine", "float") if big else ("exact", "float", "refine"):
            best, last, err = math.inf, None, ""
            for _ in range(repeat):
                try:
                    dt, ans, n, bound = _run(text, name, p)
                except ProblemError as exc:
                    err = exc.diagnostics[0].message
                    break
                best = min(best, dt)
                last = (ans, n, bound)
            results[p] = (best, last, err)
            if progress:
                progress(name, p)
        exact = results["refine" if big else "exact"][1]
        for p in PRECISIONS:
            if p not in results:
                rows.append(BenchRow(name, 0, p, math.nan, None, None,
                                     "skipped (rationals grow too long); errors against refine"))
                continue
            best, last, err = results[p]
            if last is None:
                rows.append(BenchRow(name, 0, p, math.nan, None, None, err))
                continue
            ans, n, bound = last
            rel = _rel_error(ans, exact[0]) if exact is not None else None
            rows.append(BenchRow(name, n, p, best, rel, bound if p != "exact" else 0.0))
    return rows


def default_files(root: str = ".") -> list[str]:
    """The seed examples and the hard cases that have answers (not the `bad_*` ones)."""
    import glob
    import os

    seeds = sorted(glob.glob(os.path.join(root, "examples", "seed_*.mom")))
    hard = sorted(f for f in glob.glob(os.path.join(root, "examples", "hard", "*.mom"))
                  if not os.path.basename(f).startswith("bad_"))  # error cases: no answer
    return [os.path.normpath(f) for f in seeds + hard]


def default_problems(files: list[str], sizes: list[int]) -> list[tuple[str, str]]:
    out = []
    for f in files:
        with open(f, encoding="utf-8") as fh:
            out.append((f, fh.read()))
    out.append(("hard chain (25 balls, 1e-12..1e12 kg)", hard_chain_text()))
    for n in sizes:
        out.append((f"chain of {n} balls", chain_text(n)))
    return out
