#!/usr/bin/env python3
"""Large systems, measured as whole processes: time, CPU time and peak RSS against N.

A benchmark, not a test. Each problem is generated, written to a scratch folder and
solved by `python -m momentum_cli solve --plain FILE` (or `--json` for the many-file
rows) in a child process; wall time, CPU time (user + system: robust against a busy
machine) and the child's peak resident set size come from `os.wait4`. The ratio
column is CPU(N) / CPU(N / 10) for the same family (the issue asks for <= 11: linear
with a log factor at most).

  chain N       N balls in a row, one simultaneous impact (masses over 12 decades;
                the `bench accuracy` chains)
  cradle-seq N  Newton's cradle as N - 1 two-ball impacts, one state per impact
                (tests/test_hard.py's cradle_text)
  cradle-sim N  the same cradle as one simultaneous impact
  json F        `solve --json` and `solve --plain` of F generated seed variants in one call
                (bench/startup.py's files): peak RSS must not grow with F

    python bench/large.py                      # the default sizes
    python bench/large.py --quick              # small sizes only
    python bench/large.py --chain 1000,10000,100000 --cradle-seq 1000,10000 --json-files 0
    python bench/large.py --markdown           # the README's table, with versions
"""
from __future__ import annotations

import argparse
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "tests"))
sys.path.insert(0, str(ROOT / "bench"))


PYCACHE = tempfile.mkdtemp(prefix="momentum-large-pycache-")


def run(cmd: list[str], timeout: float) -> dict:
    """One child process: wall and CPU seconds, peak RSS in MB, exit status. Bytecode is
    cached in a private folder (as for an installed package), even if
    PYTHONDONTWRITEBYTECODE is set here."""
    env = dict(os.environ, PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""),
               PYTHONPYCACHEPREFIX=PYCACHE)
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    t0 = time.perf_counter()
    p = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=env,
                         cwd=ROOT)
    deadline = t0 + timeout
    while True:
        pid, status, ru = os.wait4(p.pid, os.WNOHANG)
        if pid:
            break
        if time.perf_counter() > deadline:
            p.kill()
            _, status, ru = os.wait4(p.pid, 0)
            return dict(wall=None, cpu=None, rss=ru.ru_maxrss / 1024, code="timeout")
        time.sleep(0.01)
    wall = time.perf_counter() - t0
    return dict(wall=wall, cpu=ru.ru_utime + ru.ru_stime, rss=ru.ru_maxrss / 1024,
                code=os.waitstatus_to_exitcode(status))


def chain(n: int) -> str:
    from momentum_cli.bench import chain_text

    return chain_text(n)


def cradle(n: int, kind: str) -> str:
    from test_hard import cradle_text

    return cradle_text(n, kind)


def measure(args) -> list[dict]:
    scratch = Path(tempfile.mkdtemp(prefix="momentum-large-"))
    py = sys.executable
    rows = []
    warm = scratch / "warm-up.mom"
    warm.write_text(chain(3), encoding="utf-8")
    run([py, "-m", "momentum_cli", "solve", "--plain", str(warm)], args.timeout)  # bytecode
    try:
        families = [("chain", args.chain, chain),
                    ("cradle-seq", args.cradle_seq, lambda n: cradle(n, "sequence")),
                    ("cradle-sim", args.cradle_sim, lambda n: cradle(n, "simultaneous"))]
        for family, sizes, make in families:
            prev = {}
            for n in sizes:
                path = scratch / f"{family}-{n}.mom"
                path.write_text(make(n), encoding="utf-8")
                r = run([py, "-m", "momentum_cli", "solve", "--plain", str(path)], args.timeout)
                r.update(family=family, n=n, what="solve --plain")
                small = prev.get(n // 10)
                r["ratio"] = (r["cpu"] / small["cpu"] if small and small["cpu"] and r["cpu"]
                              else None)
                prev[n] = r
                rows.append(r)
                _progress(r)
        for f in args.json_files:
            import startup

            folder = scratch / f"files-{f}"
            folder.mkdir()
            seeds = [(p, True) for p in sorted((ROOT / "examples").glob("seed_*.mom"))]
            files = [str(p) for p in startup.make_files(folder, seeds, f)]
            for flag in ("--json", "--plain"):
                r = run([py, "-m", "momentum_cli", "solve", flag, *files], args.timeout)
                r.update(family="files", n=f, what=f"solve {flag}", ratio=None)
                rows.append(r)
                _progress(r)
    finally:
        shutil.rmtree(scratch, ignore_errors=True)
        shutil.rmtree(PYCACHE, ignore_errors=True)
    return rows


def _progress(r: dict) -> None:
    print(f"  {r['family']} {r['n']} {r['what']}: {_s(r['wall'])} wall, {_s(r['cpu'])} CPU, "
          f"{r['rss']:.0f} MB", file=sys.stderr, flush=True)


def _s(x) -> str:
    return "-" if x is None else f"{x:.2f} s"


HEAD = ("problem", "N", "command", "wall", "CPU", "peak RSS", "CPU(N)/CPU(N/10)")


def table(rows: list[dict]) -> list[tuple]:
    return [(r["family"], f"{r['n']:,}", r["what"],
             _s(r["wall"]) if r["code"] != "timeout" else "timeout",
             _s(r["cpu"]), f"{r['rss']:.0f} MB",
             "-" if r["ratio"] is None else f"{r['ratio']:.1f}") for r in rows]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    sizes = lambda s: [int(x) for x in s.split(",") if x]  # noqa: E731
    ap.add_argument("--chain", type=sizes, default=[1000, 10000])
    ap.add_argument("--cradle-seq", type=sizes, default=[300, 1000, 3000])
    ap.add_argument("--cradle-sim", type=sizes, default=[1000, 10000])
    ap.add_argument("--json-files", type=sizes, default=[3000])
    ap.add_argument("--quick", action="store_true", help="small sizes only")
    ap.add_argument("--timeout", type=float, default=600.0, help="seconds per process")
    ap.add_argument("--markdown", action="store_true")
    args = ap.parse_args(argv)
    if args.quick:
        args.chain, args.cradle_seq, args.cradle_sim, args.json_files = \
            [100, 1000], [100, 1000], [100, 1000], [300]
    rows = table(measure(args))
    if args.markdown:
        from momentum_cli.bench import versions

        print("| " + " | ".join(HEAD) + " |")
        print("|" + "---|" * len(HEAD))
        for row in rows:
            print("| " + " | ".join(row) + " |")
        print(f"\nProduced by `python bench/large.py {' '.join(argv or sys.argv[1:])}`"
              f"; {versions()}; load average {os.getloadavg()[0]:.1f} at the end.")
    else:
        widths = [max(len(str(x)) for x in col) for col in zip(HEAD, *rows)]
        for row in [HEAD, *rows]:
            print("  ".join(str(x).rjust(w) for x, w in zip(row, widths)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
