"""`momentum bench sweep`: variants per second, the batched sweep against its limits.

For each problem, every number it gives (its `let`s, its states' given scalars, its
impacts' coefficients) is drawn within +-5 %, and four ways solve the same N variants: the batched sweep
(`solve_batch`: compiled once, solved as arrays); numpy's own batched solve of the same
linear systems (the stacked matrices and right-hand sides of the file's linear blocks,
built beforehand, only `np.linalg.solve` timed: the limit); a loop of scalar solves in
this process (one `--set` variant after another); and one process per variant (the cost
of `momentum solve --set ...` run once per variant, as a shell loop would). The two
per-variant baselines are timed on a few variants and given as variants per second.
"""
from __future__ import annotations

import math
import os
import subprocess
import sys
import time

import numpy as np

from ..records import record

SPREAD = 0.05  # default design: every `let` drawn uniform within +-5 % of its value
SEED = 1


@record
class SweepRow:
    problem: str
    unknowns: int
    variants: int
    parameters: str  # what was varied
    batched: float | None  # variants per second of `solve_batch`
    numpy_limit: float | None  # of np.linalg.solve on the stacked linear blocks
    scalar_loop: float | None  # of scalar solves in one process
    process_per_file: float | None  # of one `momentum solve` process per variant
    failed: int = 0  # variants the sweep did not solve
    note: str = ""


def default_files(root: str = ".") -> list[str]:
    """The seed examples and the sweep examples."""
    import glob

    files = sorted(glob.glob(os.path.join(root, "examples", "seed_*.mom")))
    files += sorted(glob.glob(os.path.join(root, "examples", "sweep", "*.mom")))
    return [os.path.normpath(f) for f in files]


def inputs(text: str, name: str) -> dict:
    """{parameter: (SI value, dimension)} of every number a sweep can vary in the file:
    its scalar `let`s, its states' given scalars (`BODY.QTY@STATE`, those written as a
    number) and its impacts' restitution and friction coefficients (`e[C]`, `mu[C]`);
    zeros left out (varying a zero changes the structure)."""
    from .. import syntax as S
    from ..diagnostics import ProblemError
    from ..scene import build
    from ..source import Source
    from .params import ParamError, bind

    doc = S.parse(Source(name, text))
    names = [s.name for s in doc.statements if isinstance(s, S.Let)]
    for s in doc.statements:
        if isinstance(s, S.StateDecl):
            for it in s.items:
                if isinstance(it, S.Given) and it.relation == "=" and \
                        isinstance(it.value, (S.Num, S.Neg)):
                    names.append(f"{it.body}.{it.qty}@{s.id}")
        elif isinstance(s, S.Transition):
            for c in s.clauses:
                if isinstance(c, S.Contact):
                    label = c.label or c.a.text
                    names += [f"e[{label}]", f"mu[{label}]"]
    out = {}
    for k in dict.fromkeys(names):
        try:
            consts = build(bind(doc, [k], name)).constants
        except (ParamError, ProblemError):  # e.g. a bare number as an angular velocity
            continue
        q = consts.get(k)
        if q is None or q.is_vector:
            continue
        v = float(q.value.value) if hasattr(q.value, "value") else float(q.value)
        if v != 0.0 and math.isfinite(v):
            out[k] = (v, q.dim)
    return out


def let_design(text: str, name: str, n: int, seed: int = SEED) -> dict:
    """Columns for every input `inputs` finds: uniform within +-SPREAD of its value (a
    restitution between 1 - SPREAD of it and at most 1), in SI, drawn from `seed`
    (numpy's PCG64). Empty for a file with nothing to vary."""
    rng = np.random.Generator(np.random.PCG64(seed))
    cols = {}
    for k, (v, _dim) in inputs(text, name).items():
        lo, hi = sorted((v * (1 - SPREAD), v * (1 + SPREAD)))
        if k.startswith("e[") and hi > 1.0:
            hi = max(lo, 1.0)
        cols[k] = rng.uniform(lo, hi, n)
    return cols


def _sets(cols: dict, units: dict, i: int) -> list[tuple[str, str]]:
    return [(k, f"{float(c[i])!r} {units[k]}".strip()) for k, c in cols.items()]


def _units(text: str, name: str, cols: dict) -> dict:
    from ..units import si_label

    found = inputs(text, name)
    return {k: si_label(found[k][1]) if k in found else "" for k in cols}


def numpy_limit(text: str, name: str, n: int, repeat: int = 3) -> tuple[float | None, int, str]:
    """(variants per second of np.linalg.solve on the file's linear blocks stacked n
    times, unknowns, note). The stacked arrays are built before the clock starts."""
    from ..run import solve_source
    from ..scene import build
    from ..solve import solve_scene
    from ..source import Source
    from ..syntax import parse

    del solve_source
    sol = solve_scene(build(parse(Source(name, text))))
    blocks = [b for b in sol.blocks if b.method == "linear" and b.matrix is not None]
    others = [b for b in sol.blocks if b.method != "linear"]
    unknowns = len(sol.system.unknowns)
    note = ""
    if others:
        note = (f"{len(others)} nonlinear/explicit block(s) of "
                f"{sum(len(b.unknowns) for b in others)} unknown(s) not in the numpy limit")
    if not blocks:
        return None, unknowns, note or "no linear block"
    stacks = []
    for b in blocks:
        A = np.asarray(b.matrix, dtype=float)
        rhs = np.asarray(b.rhs, dtype=float)
        stacks.append((np.ascontiguousarray(np.broadcast_to(A, (n,) + A.shape)),
                       np.ascontiguousarray(np.broadcast_to(rhs[:, None], (n, len(rhs), 1)))))
    best = math.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        for A, rhs in stacks:
            np.linalg.solve(A, rhs)
        best = min(best, time.perf_counter() - t0)
    return n / best, unknowns, note


def scalar_loop(text: str, name: str, cols: dict, count: int) -> float:
    """Variants per second of scalar solves in this process, each with its `--set`s."""
    from ..run import solve_source
    from ..source import Source

    units = _units(text, name, cols)
    count = max(1, count)
    t0 = time.perf_counter()
    for i in range(count):
        solve_source(Source(name, text), overrides=_sets(cols, units, i) if cols else ())
    return count / (time.perf_counter() - t0)


def process_per_file(path: str, text: str, cols: dict, count: int) -> float:
    """Variants per second of one `momentum solve --plain` process per variant."""
    units = _units(text, path, cols)
    count = max(1, count)
    t0 = time.perf_counter()
    for i in range(count):
        args = [sys.executable, "-m", "momentum_cli", "solve", "--plain", path]
        for k, v in (_sets(cols, units, i) if cols else []):
            args += ["--set", f"{k}={v}"]
        subprocess.run(args, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=False)
    return count / (time.perf_counter() - t0)


def batched(path: str, text: str, cols: dict, repeat: int = 1) -> tuple[float, int]:
    """(variants per second of the batched sweep, variants it did not solve)."""
    from ..scene import build
    from ..source import Source
    from ..syntax import parse
    from .batch import solve_batch

    found = inputs(text, path)
    dims = {k: found[k][1] for k in cols if k in found}
    n = len(next(iter(cols.values())))
    best, failed = math.inf, 0
    for _ in range(repeat):
        t0 = time.perf_counter()
        res = solve_batch(path, cols, dims)
        best = min(best, time.perf_counter() - t0)
        failed = int(sum(1 for s in res.status if s.startswith("error")))
    return n / best, failed


def run(files: list[str], count: int = 10000, loop: int = 100, processes: int = 5,
        seed: int = SEED, design=None, progress=None) -> list[SweepRow]:
    """One row per file. `design(text, name, n)` -> columns replaces the default (every
    input `inputs` finds, within +-5 %); a file with nothing to vary is reported, not
    swept."""
    rows = []
    for path in files:
        with open(path, encoding="utf-8") as fh:
            text = fh.read()
        cols = design(text, path, count) if design is not None else \
            let_design(text, path, count, seed)
        what = ", ".join(cols) if cols else ""
        if progress:
            progress(path, "numpy")
        limit, unknowns, note = numpy_limit(text, path, count)
        if not cols:
            rows.append(SweepRow(path, unknowns, count, "-", None, limit, None, None, 0,
                                 "nothing to vary (no `let`, no given number other than 0)"))
            continue
        if progress:
            progress(path, "batched")
        rate, failed = batched(path, text, cols)
        if progress:
            progress(path, "scalar loop")
        loop_rate = scalar_loop(text, path, cols, min(loop, count))
        if progress:
            progress(path, "processes")
        proc_rate = process_per_file(path, text, cols, min(processes, count)) \
            if processes else None
        rows.append(SweepRow(path, unknowns, count, what, rate, limit, loop_rate, proc_rate,
                             failed, note))
    return rows


HEADERS = ["problem", "unknowns", "variants", "varied", "batched sweep (variants/s)",
           "numpy limit (variants/s)", "scalar loop (variants/s)",
           "process per file (variants/s)", "batched / loop", "note"]


def _rate(x: float | None) -> str:
    if x is None or not math.isfinite(x):
        return "-"
    return f"{x:,.0f}" if x >= 100 else f"{x:.3g}"


def table(rows: list[SweepRow]) -> list[list[str]]:
    out = []
    for r in rows:
        ratio = "-" if not (r.batched and r.scalar_loop) else f"{r.batched / r.scalar_loop:,.0f}x"
        note = r.note + (f"; {r.failed} not solved" if r.failed else "")
        out.append([r.problem, str(r.unknowns), f"{r.variants:,}", r.parameters, _rate(r.batched),
                    _rate(r.numpy_limit), _rate(r.scalar_loop), _rate(r.process_per_file),
                    ratio, note.strip("; ")])
    return out


def markdown(rows: list[SweepRow]) -> str:
    body = table(rows)
    right = {1, 2, 4, 5, 6, 7, 8}
    out = ["| " + " | ".join(HEADERS) + " |",
           "|" + "|".join("---:" if i in right else "---" for i in range(len(HEADERS))) + "|"]
    for r in body:
        r = [f"`{c}`" if i == 0 else c for i, c in enumerate(r)]
        out.append("| " + " | ".join(r) + " |")
    return "\n".join(out) + "\n"


def as_json(rows: list[SweepRow]) -> list[dict]:
    return [dict(problem=r.problem, unknowns=r.unknowns, variants=r.variants,
                 varied=r.parameters, batched=r.batched, numpy_limit=r.numpy_limit,
                 scalar_loop=r.scalar_loop, process_per_file=r.process_per_file,
                 failed=r.failed, note=r.note) for r in rows]
