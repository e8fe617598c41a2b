"""How often each impact law gains kinetic energy, over random contacts (README numbers).

Random W (symmetric positive definite: W_tt, W_nn in [0.1, 5], correlation within
+-0.999), v0 = (v_t in [-3, 3], v_n in [-3, -0.01]), e in [0, 1], mu in [0, 2];
seed 1. Run: python bench/impact_laws_energy.py [N]
"""
from __future__ import annotations

import math
import random
import sys

from momentum_cli.laws import resolve


def main(n: int = 100_000) -> None:
    rng = random.Random(1)
    gains = {"newton": 0, "poisson": 0, "energetic": 0}
    done = 0
    for _ in range(n):
        a, c = rng.uniform(0.1, 5), rng.uniform(0.1, 5)
        b = rng.uniform(-1, 1) * math.sqrt(a * c) * 0.999
        W = ((a, b), (b, c))
        v0 = (rng.uniform(-3, 3), -rng.uniform(0.01, 3))
        e, mu = rng.random(), rng.uniform(0, 2)
        try:
            rs = {law: resolve(W, v0, e, mu, law) for law in gains}
        except ValueError:  # Newton's sliding solution is not compressive
            continue
        done += 1
        for law, r in rs.items():
            gains[law] += r.gains_energy
    print(f"{done} impacts (of {n} drawn)")
    for law, k in gains.items():
        print(f"  {law:9s} gains energy in {k} ({100 * k / done:.2f} %)")


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 100_000)
