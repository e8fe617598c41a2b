#!/usr/bin/env python3
"""Start-up and per-file cost of the momentum CLI, measured as whole processes.

A benchmark, not a test. Everything is timed as a whole process (subprocess, wall
clock), hyperfine-style: warm-up runs first, then N timed runs of every command,
interleaved round-robin so that a noisy neighbour slows every command alike; the
median is reported (with min, mean, spread).

  (i)   start-up: `python -c "import numpy, lark, rich, typer"` (the four heavy
        dependencies, which a one-shot CLI pays for if it imports them) against
        `python -m momentum_cli solve --plain examples/seed_rod_drop_smooth.mom`
        (and the `momentum` entry point, if installed) -> ratio; and
        `python -m momentum_cli simulate --plain examples/seed_pendulum_wall.mom`;
  (ii)  marginal cost per file: one call on 1000 generated problem files (variations
        of the seed examples) against one call on one file:
        (T1000 - T1) / 999, in ms;
  (iii) `python -X importtime` of the seed solve: which modules dominate start-up,
        and whether numpy (not needed for a 4-unknown block) or rich (not needed in
        --plain mode) is imported on that path.

    python bench/startup.py                 # table
    python bench/startup.py --markdown      # the README's table, with versions
    python bench/startup.py --json          # one JSON document
    python bench/startup.py --runs 30 --files 1000
"""
from __future__ import annotations

import argparse
import json
import os
import platform
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
EXAMPLES = ROOT / "examples"
SEED = EXAMPLES / "seed_rod_drop_smooth.mom"
SIM_SEED = EXAMPLES / "seed_pendulum_wall.mom"
PY = sys.executable
HEAVY = "import numpy, lark, rich, typer"


# ---- timing ----------------------------------------------------------------------------------

def _env(cache_dir: str, pycache: str | None) -> dict[str, str]:
    """The environment of every timed process. With `pycache`, bytecode is cached in that
    private directory (as for an installed package, whose .pyc files exist), even if
    PYTHONDONTWRITEBYTECODE is set in the calling environment."""
    env = dict(os.environ)
    if pycache is not None:
        env.pop("PYTHONDONTWRITEBYTECODE", None)
        env["PYTHONPYCACHEPREFIX"] = pycache
    env["PYTHONPATH"] = str(ROOT) + (os.pathsep + env["PYTHONPATH"] if env.get("PYTHONPATH")
                                     else "")
    env["MOMENTUM_CACHE_DIR"] = cache_dir  # a private, warm lark cache
    env.pop("PYTHONSTARTUP", None)
    env["NO_COLOR"] = "1"
    return env


def run_once(cmd: list[str], env: dict[str, str]) -> float:
    t0 = time.perf_counter()
    p = subprocess.run(cmd, env=env, cwd=ROOT, stdout=subprocess.DEVNULL,
                       stderr=subprocess.PIPE)
    dt = time.perf_counter() - t0
    if p.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd[:6])}... exited {p.returncode}: "
                           f"{p.stderr.decode(errors='replace')[-800:]}")
    return dt


def summary(times: list[float]) -> dict:
    med = statistics.median(times)
    return {
        "median_ms": med * 1e3,
        "min_ms": min(times) * 1e3,
        "mean_ms": statistics.fmean(times) * 1e3,
        "stdev_ms": (statistics.stdev(times) if len(times) > 1 else 0.0) * 1e3,
        "mad_ms": statistics.median(abs(t - med) for t in times) * 1e3,
        "runs": len(times),
    }


def measure(commands: dict[str, list[str]], runs: int, warmup: int, env,
            progress=None) -> dict[str, dict]:
    """Round-robin: warm-up runs of every command, then `runs` timed rounds."""
    for _ in range(warmup):
        for cmd in commands.values():
            run_once(cmd, env)
    times: dict[str, list[float]] = {k: [] for k in commands}
    for i in range(runs):
        for name, cmd in commands.items():
            times[name].append(run_once(cmd, env))
        if progress:
            progress(f"  round {i + 1}/{runs}")
    return {k: summary(v) for k, v in times.items()}


# ---- (ii) problem files ----------------------------------------------------------------------

_MASS = re.compile(r"\b(mass|weight)(\s*=\s*)(\d+\.?\d*)")
_TITLE = re.compile(r'^problem "([^"]*)"', re.M)


def factor(i: int) -> float:
    return 0.5 + (i % 61) / 40  # 0.5 .. 2.0


def variant(text: str, i: int, scale_masses: bool) -> str:
    """The same problem with a new title and, where that leaves it solvable (impacts:
    answers do not depend on a common mass scale; given forces do), its masses and
    weights scaled."""
    if scale_masses:
        f = factor(i)
        text = _MASS.sub(lambda m: f"{m.group(1)}{m.group(2)}{float(m.group(3)) * f:.6g}",
                         text)
    return _TITLE.sub(lambda m: f'problem "{m.group(1)} (variant {i})"', text, count=1)


def _solves(paths: list[Path], env) -> bool:
    r = subprocess.run([PY, "-m", "momentum_cli", "solve", "--plain", *map(str, paths)],
                       env=env, cwd=ROOT, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return r.returncode == 0


def usable_seeds(env, scratch: Path) -> tuple[list[tuple[Path, bool]], list[str]]:
    """Seeds that solve, each with whether its masses can be scaled (checked at the
    smallest, middle and largest factor); seeds that do not solve are left out."""
    ok, bad = [], []
    for p in sorted(EXAMPLES.glob("*.mom")):
        if not _solves([p], env):
            bad.append(p.name)
            continue
        text = p.read_text(encoding="utf-8")
        probes = []
        for i in (0, 30, 60):  # factors 0.5, 1.25, 2.0
            q = scratch / f"probe_{i}_{p.name}"
            q.write_text(variant(text, i, True), encoding="utf-8")
            probes.append(q)
        ok.append((p, _solves(probes, env)))
        for q in probes:
            q.unlink()
    return ok, bad


def make_files(dest: Path, seeds: list[tuple[Path, bool]], n: int) -> list[Path]:
    texts = [s.read_text(encoding="utf-8") for s, _ in seeds]
    out = []
    for i in range(n):
        k = i % len(seeds)
        p = dest / f"{i:04d}_{seeds[k][0].stem}.mom"
        p.write_text(variant(texts[k], i, seeds[k][1]), encoding="utf-8")
        out.append(p)
    return out


# ---- (iii) -X importtime ---------------------------------------------------------------------

_IT = re.compile(r"^import time:\s+(\d+)\s+\|\s+(\d+)\s+\|(\s*)(\S+)\s*$")


def importtime(cmd: list[str], env, repeats: int = 5) -> dict:
    """Per top-level package, the median over `repeats` runs of: its cumulative import
    time (summed over the imports of it that are not nested in an import of the same
    package, so lazily imported submodules count too; nested packages are included,
    as in -X importtime's own cumulative column), and its modules' own (self) time."""
    per_run = []
    modules_seen: set[str] = set()
    for _ in range(repeats):
        p = subprocess.run([PY, "-X", "importtime", *cmd], env=env, cwd=ROOT,
                           stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
        rows = []
        for line in p.stderr.decode(errors="replace").splitlines():
            m = _IT.match(line)
            if m:
                rows.append((len(m.group(3)), m.group(4), int(m.group(1)), int(m.group(2))))
        cum: dict[str, int] = {}
        self_: dict[str, int] = {}
        stack: list[tuple[int, str]] = []  # enclosing imports; -X importtime is post-order
        for indent, name, s, c in reversed(rows):
            while stack and stack[-1][0] >= indent:
                stack.pop()
            top = name.split(".")[0]
            parent_top = stack[-1][1].split(".")[0] if stack else None
            if parent_top != top:
                cum[top] = cum.get(top, 0) + c
            self_[top] = self_.get(top, 0) + s
            modules_seen.add(name)
            stack.append((indent, name))
        total = sum(self_.values())
        per_run.append((cum, self_, total))
    tops = sorted({k for cum, _, _ in per_run for k in cum})
    rows = []
    for t in tops:
        rows.append({
            "package": t,
            "cumulative_ms": statistics.median(r[0].get(t, 0) for r in per_run) / 1e3,
            "self_ms": statistics.median(r[1].get(t, 0) for r in per_run) / 1e3,
        })
    rows.sort(key=lambda r: -r["cumulative_ms"])
    return {
        "total_self_ms": statistics.median(r[2] for r in per_run) / 1e3,
        "top": rows,
        "numpy_imported": any(m == "numpy" or m.startswith("numpy.") for m in modules_seen),
        "rich_imported": any(m == "rich" or m.startswith("rich.") for m in modules_seen),
        "rich_modules": sorted(m for m in modules_seen
                               if m == "rich" or m.startswith("rich."))[:12],
        "modules": len(modules_seen),
    }


# ---- main ------------------------------------------------------------------------------------

def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--runs", type=int, default=15, help="timed runs per command (>= 15)")
    ap.add_argument("--warmup", type=int, default=2, help="untimed warm-up runs per command")
    ap.add_argument("--files", type=int, default=1000, help="files in the batch call")
    ap.add_argument("--batch-runs", type=int, default=None,
                    help="timed runs of the batch measurement (default: --runs)")
    ap.add_argument("--json", action="store_true", help="print one JSON document")
    ap.add_argument("--markdown", action="store_true", help="print the README's table")
    ap.add_argument("--skip-batch", action="store_true", help="only start-up and importtime")
    ap.add_argument("--no-pyc-cache", action="store_true",
                    help="keep the environment's bytecode setting (by default bytecode is "
                         "cached in a private directory, as for an installed package)")
    args = ap.parse_args(argv)
    if args.runs < 15:
        print("note: fewer than 15 runs; medians will be noisy", file=sys.stderr)
    log = (lambda s: None) if args.json else (lambda s: print(s, file=sys.stderr, flush=True))

    cache = tempfile.mkdtemp(prefix="momentum-bench-cache-")
    work = Path(tempfile.mkdtemp(prefix="momentum-bench-files-"))
    pycache = None if args.no_pyc_cache else tempfile.mkdtemp(prefix="momentum-bench-pyc-")
    env = _env(cache, pycache)
    result: dict = {
        "bytecode_cached": pycache is not None,
        "PYTHONDONTWRITEBYTECODE_in_caller": os.environ.get("PYTHONDONTWRITEBYTECODE"),
        "python": sys.version.split()[0],
        "platform": platform.platform(),
        "cpus": os.cpu_count(),
        "loadavg_start": list(os.getloadavg()) if hasattr(os, "getloadavg") else None,
        "runs": args.runs,
        "warmup": args.warmup,
        "OPENBLAS_NUM_THREADS": os.environ.get("OPENBLAS_NUM_THREADS"),
    }
    try:
        # (i) start-up ---------------------------------------------------------------
        seed = str(SEED.relative_to(ROOT))
        cmds = {
            "python -c pass": [PY, "-c", "pass"],
            f'python -c "{HEAVY}"': [PY, "-c", HEAVY],
            f"python -m momentum_cli solve --plain {seed}":
                [PY, "-m", "momentum_cli", "solve", "--plain", seed],
            f"python -m momentum_cli simulate --plain {SIM_SEED.relative_to(ROOT)}":
                [PY, "-m", "momentum_cli", "simulate", "--plain", str(SIM_SEED.relative_to(ROOT))],
        }
        entry = shutil.which("momentum")
        if entry:
            cmds[f"momentum solve --plain {seed}"] = [entry, "solve", "--plain", seed]
        result["entry_point"] = entry
        log(f"(i) start-up: {len(cmds)} commands x {args.runs} runs")
        startup = measure(cmds, args.runs, args.warmup, env, log)
        result["startup"] = startup
        heavy = startup[f'python -c "{HEAVY}"']["median_ms"]
        solve = startup[f"python -m momentum_cli solve --plain {seed}"]["median_ms"]
        result["ratio_solve_over_heavy_imports"] = solve / heavy
        if entry:
            result["ratio_entry_point_over_heavy_imports"] = \
                startup[f"momentum solve --plain {seed}"]["median_ms"] / heavy

        # (iii) importtime -------------------------------------------------------------
        log("(iii) -X importtime of the seed solve")
        result["importtime"] = importtime(["-m", "momentum_cli", "solve", "--plain", seed], env)
        result["importtime_simulate"] = importtime(
            ["-m", "momentum_cli", "simulate", "--plain", str(SIM_SEED.relative_to(ROOT))], env)

        # (ii) marginal cost per file -------------------------------------------------
        if not args.skip_batch:
            seeds, bad = usable_seeds(env, work)
            result["batch_seeds"] = [p.name for p, _ in seeds]
            result["batch_seeds_copied_unscaled"] = [p.name for p, sc in seeds if not sc]
            result["batch_seeds_excluded"] = bad
            files = make_files(work, seeds, args.files)
            one = next((f for f in files if "seed_rod_drop_smooth" in f.name), files[0])
            rel = [str(f) for f in files]
            batch = {
                "T1": [PY, "-m", "momentum_cli", "solve", "--plain", str(one)],
                f"T{args.files}": [PY, "-m", "momentum_cli", "solve", "--plain", *rel],
            }
            runs = args.batch_runs or args.runs
            log(f"(ii) batch: 1 file vs {args.files} files ({len(seeds)} seeds) x {runs} runs")
            res = measure(batch, runs, 1, env, log)
            result["batch_runs"] = runs
            t1, tn = res["T1"]["median_ms"], res[f"T{args.files}"]["median_ms"]
            result["batch"] = res
            result["batch_files"] = args.files
            result["marginal_ms_per_file"] = (tn - t1) / (args.files - 1)
            result["files_per_second_in_batch"] = 1e3 / result["marginal_ms_per_file"]
            result["ratio_T1_over_marginal"] = t1 / result["marginal_ms_per_file"]
    finally:
        shutil.rmtree(cache, ignore_errors=True)
        if pycache:
            shutil.rmtree(pycache, ignore_errors=True)
        shutil.rmtree(work, ignore_errors=True)
    result["loadavg_end"] = list(os.getloadavg()) if hasattr(os, "getloadavg") else None

    if args.json:
        print(json.dumps(result, indent=2))
    elif args.markdown:
        print_markdown(result, " ".join(["python bench/startup.py"] + list(
            sys.argv[1:] if argv is None else argv)))
    else:
        print_table(result)
    return 0


def print_markdown(r: dict, command: str) -> None:
    """The README's table "What it costs (measured)", from one run's results."""
    sys.path.insert(0, str(ROOT))
    from momentum_cli.bench import versions

    seed = str(SEED.relative_to(ROOT))
    sim = str(SIM_SEED.relative_to(ROOT))
    st = r["startup"]
    solve = st[f"python -m momentum_cli solve --plain {seed}"]["median_ms"]
    heavy = st[f'python -c "{HEAVY}"']["median_ms"]
    print("| measure | result | aim |")
    print("|---|---|---|")
    print(f"| `python -m momentum_cli solve --plain {seed}`, whole process | {solve:.0f} ms, "
          f"**{solve / heavy:.2f}×** `python -c \"{HEAVY}\"` ({heavy:.0f} ms) | ≤ 0.6× |")
    if "batch" in r:
        n, m = r["batch_files"], r["marginal_ms_per_file"]
        print(f"| {n:,} files in one call, marginal cost per file | {m:.1f} ms "
              f"({1e3 / m:.0f} files/s): files are solved by worker processes on every core "
              f"({r['cpus']} here) and reported in order | ≤ 2 ms |")
    it = r["importtime"]
    heavy_mods = [name for name, key in (("numpy", "numpy_imported"), ("rich", "rich_imported"))
                  if it[key]]
    print("| what a one-shot plain solve imports | " + (
        "numpy and rich are never imported" if not heavy_mods else
        f"**{', '.join(heavy_mods)} imported**") + f" ({it['modules']} modules, "
          f"{it['total_self_ms']:.0f} ms of import time) | no numpy, no rich |")
    sim_ms = st[f"python -m momentum_cli simulate --plain {sim}"]["median_ms"]
    its = r["importtime_simulate"]
    scipy = any(row["package"] == "scipy" for row in its["top"])
    print(f"| `python -m momentum_cli simulate --plain {sim}`, whole process | "
          f"{sim_ms / 1e3:.2f} s: numpy for the dynamics, "
          f"{'scipy imported' if scipy else 'no scipy (the swing is an elliptic closed form)'}"
          " | |")
    print()
    batch = f" (batch: {r['batch_runs']} runs)" if "batch" in r else ""
    print(f"Produced by `{command}`: medians of {r['runs']} whole-process runs per command"
          f"{batch}, load average "
          f"{r['loadavg_start'][0]:.2f} -> {r['loadavg_end'][0]:.2f}; {versions()}.")


def print_table(r: dict) -> None:
    print(f"python {r['python']} on {r['platform']}, {r['cpus']} CPUs, load average "
          f"{r['loadavg_start'][0]:.2f} -> {r['loadavg_end'][0]:.2f}; "
          f"{r['runs']} runs per command (median, hyperfine-style); bytecode "
          f"{'cached (private dir)' if r['bytecode_cached'] else 'as in the environment'}")
    print()
    print("(i) start-up, whole process")
    w = max(len(k) for k in r["startup"]) + 2
    print(f"  {'command':<{w}}{'median':>10}{'min':>10}{'mean':>10}{'MAD':>9}")
    for k, s in r["startup"].items():
        print(f"  {k:<{w}}{s['median_ms']:>8.1f}ms{s['min_ms']:>8.1f}ms{s['mean_ms']:>8.1f}ms"
              f"{s['mad_ms']:>7.1f}ms")
    print(f"  ratio  solve / import of numpy+lark+rich+typer = "
          f"{r['ratio_solve_over_heavy_imports']:.2f}")
    if "ratio_entry_point_over_heavy_imports" in r:
        print(f"  ratio  `momentum` entry point / imports       = "
              f"{r['ratio_entry_point_over_heavy_imports']:.2f}")
    else:
        print("  (the `momentum` entry point is not installed: not measured)")
    if "batch" in r:
        n = r["batch_files"]
        print()
        print(f"(ii) marginal cost per file (one call, {n} files from "
              f"{len(r['batch_seeds'])} seeds)")
        for k, s in r["batch"].items():
            print(f"  {k:<8}{s['median_ms']:>10.1f}ms  (min {s['min_ms']:.1f}, MAD "
                  f"{s['mad_ms']:.1f})")
        print(f"  (T{n} - T1) / {n - 1} = {r['marginal_ms_per_file']:.2f} ms per file "
              f"({r['files_per_second_in_batch']:.0f} files/s); "
              f"T1 / marginal = {r['ratio_T1_over_marginal']:.0f}")
        if r["batch_seeds_copied_unscaled"]:
            print(f"  copied without scaling masses: "
                  f"{', '.join(r['batch_seeds_copied_unscaled'])}")
        if r["batch_seeds_excluded"]:
            print(f"  seeds excluded (did not solve): {', '.join(r['batch_seeds_excluded'])}")
    it = r["importtime"]
    print()
    print(f"(iii) python -X importtime, seed solve: {it['modules']} modules, "
          f"{it['total_self_ms']:.0f} ms of import time (median of 5)")
    print(f"  {'package':<22}{'cumulative':>12}{'self':>10}")
    for row in it["top"][:14]:
        print(f"  {row['package']:<22}{row['cumulative_ms']:>10.1f}ms{row['self_ms']:>8.1f}ms")
    print(f"  numpy imported on the seed solve path: {'YES' if it['numpy_imported'] else 'no'}")
    print(f"  rich imported in --plain mode: {'YES' if it['rich_imported'] else 'no'}"
          + (f" ({', '.join(it['rich_modules'])})" if it["rich_imported"] else ""))


if __name__ == "__main__":
    sys.exit(main())
