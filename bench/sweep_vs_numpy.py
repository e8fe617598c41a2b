"""Issue 13's sweep target, measured as a ratio in one run (not a test).

Whole-process time of `momentum sweep examples/seed_rod_drop_smooth.mom` with 10^6
Monte Carlo variants (e[A] and the drop height rod.y@1 sampled) against the limit:
the start-up of `python -c "import numpy"` plus numpy's batched solve of the same
10^6 systems (the energy block's root and the 3x3 impact block, built as arrays).
Target: ratio <= 3. Usage: python bench/sweep_vs_numpy.py [COUNT] [REPEATS]
"""
from __future__ import annotations

import os
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
FILE = os.path.join(ROOT, "examples", "seed_rod_drop_smooth.mom")

NUMPY_SOLVE = r"""
import sys, numpy as np
n = int(sys.argv[1])
rng = np.random.Generator(np.random.PCG64(1))
e = rng.uniform(0.5, 0.9, n); h = rng.uniform(0.5, 1.5, n)
m, L, g, th = 10.0, 1.0, 9.81, np.pi / 6
I = m * L * L / 12
vy2 = -np.sqrt(2 * g * h)                        # the energy block's root
c = 0.5 * L * np.cos(th)
A = np.zeros((n, 3, 3)); b = np.zeros((n, 3))   # unknowns vy3, J_n, omega3
A[:, 0, 0] = 1; A[:, 0, 2] = -c; b[:, 0] = -e * vy2
A[:, 1, 0] = m; A[:, 1, 1] = -1; b[:, 1] = m * vy2
A[:, 2, 1] = c; A[:, 2, 2] = I
x = np.linalg.solve(A, b[:, :, None])[:, :, 0]
print(x[:, 2].mean())
"""


# an installed package has its bytecode cached; a worktree run with
# PYTHONDONTWRITEBYTECODE would compile every module in every process: cache it aside
ENV = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
ENV.setdefault("PYTHONPYCACHEPREFIX", os.path.join("/tmp", f"momentum-pycache-{os.getuid()}"))
ENV["OPENBLAS_NUM_THREADS"] = "1"


def run(cmd) -> float:
    t = time.perf_counter()
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, env=ENV)
    return time.perf_counter() - t


def main() -> None:
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 1_000_000
    reps = int(sys.argv[2]) if len(sys.argv) > 2 else 3
    env_py = sys.executable
    sweep = [env_py, "-m", "momentum_cli", "sweep", FILE,
             "--sample", "e[A]~uniform(0.5, 0.9)", "--sample", "rod.y@1~uniform(0.5 m, 1.5 m)",
             "--count", str(n), "--seed", "1"]
    start = [env_py, "-c", "import numpy"]
    limit = [env_py, "-c", NUMPY_SOLVE, str(n)]
    run(sweep[:-4] + ["--count", "10", "--seed", "1"])  # warm the bytecode cache
    run(limit[:-1] + ["10"])
    ts, tn, tl = [], [], []
    for _ in range(reps):  # interleaved: the machine's load hits all three alike
        ts.append(run(sweep))
        tn.append(run(start))
        tl.append(run(limit))
    s, st, lim = min(ts), min(tn), min(tl)
    print(f"variants: {n}")
    print(f"momentum sweep, whole process:          {s:.3f} s")
    print(f"python -c 'import numpy':               {st:.3f} s")
    print(f"numpy batched solve, whole process:     {lim:.3f} s (start-up included)")
    print(f"ratio sweep / numpy solve process:      {s / lim:.2f}  (target <= 3)")


if __name__ == "__main__":
    main()
