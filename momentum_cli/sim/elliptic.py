"""Jacobi elliptic functions, the incomplete elliptic integral and a bracketed root.

The standard algorithms, in plain Python so that a pendulum between impacts costs no
scipy import (scipy.special and scipy.optimize together take ~0.3 s to import, most of
a one-shot run): the arithmetic-geometric mean for sn, cn, dn and am (Abramowitz and
Stegun 16.4), Carlson's duplication algorithm for R_F (F(phi|m) = sin(phi)
R_F(cos^2 phi, 1 - m sin^2 phi, 1)), and the Illinois variant of false position.
tests/test_simulate.py checks them against scipy.
"""
from __future__ import annotations

import math

EPS = 2.220446049250313e-16


def ellipj(u: float, m: float) -> tuple[float, float, float, float]:
    """(sn, cn, dn, am) of u with parameter m, 0 <= m < 1."""
    if m < 1e-300:
        return math.sin(u), math.cos(u), 1.0, u
    # sn, cn and dn have the period 4K: reduce u first (am grows by 2 pi a period)
    period = 4 * ellipk(m)
    turns = round(u / period)
    u -= turns * period
    a, b, c = 1.0, math.sqrt(1.0 - m), math.sqrt(m)
    cs = [c]
    As = [a]
    n = 0
    while abs(c) > EPS * a and n < 40:
        a, b, c = (a + b) / 2, math.sqrt(a * b), (a - b) / 2
        n += 1
        As.append(a)
        cs.append(c)
    phi = (2 ** n) * a * u
    prev = phi
    for k in range(n, 0, -1):
        prev = phi
        phi = (phi + math.asin(max(-1.0, min(1.0, cs[k] / As[k] * math.sin(phi))))) / 2
    sn, cn = math.sin(phi), math.cos(phi)
    dn = cn / math.cos(prev - phi) if n else 1.0
    return sn, cn, dn, phi + 2 * math.pi * turns


def carlson_rf(x: float, y: float, z: float) -> float:
    """R_F(x, y, z) by duplication (relative error ~1e-16 with ERRTOL 0.0025)."""
    for _ in range(100):
        sx, sy, sz = math.sqrt(x), math.sqrt(y), math.sqrt(z)
        lam = sx * (sy + sz) + sy * sz
        x, y, z = (x + lam) / 4, (y + lam) / 4, (z + lam) / 4
        mean = (x + y + z) / 3
        dx, dy, dz = (mean - x) / mean, (mean - y) / mean, (mean - z) / mean
        if max(abs(dx), abs(dy), abs(dz)) < 0.0025:
            break
    e2 = dx * dy - dz * dz
    e3 = dx * dy * dz
    return (1 + (e2 / 24 - 0.1 - 3 * e3 / 44) * e2 + e3 / 14) / math.sqrt(mean)


def ellipkinc(phi: float, m: float) -> float:
    """F(phi | m) for |phi| <= pi/2, 0 <= m < 1."""
    s, c = math.sin(phi), math.cos(phi)
    return s * carlson_rf(c * c, c * c + (1.0 - m) * s * s, 1.0)  # 1 - m s^2, no cancelling


def ellipk(m: float) -> float:
    """K(m) = F(pi/2 | m)."""
    return carlson_rf(0.0, 1.0 - m, 1.0)


def root(f, a: float, b: float, fa: float | None = None, fb: float | None = None) -> float:
    """A root of f in [a, b], where f(a) and f(b) differ in sign (Illinois false
    position, bisecting when it stalls), to the last bit of the bracket."""
    fa = f(a) if fa is None else fa
    fb = f(b) if fb is None else fb
    if fa == 0:
        return a
    if fb == 0:
        return b
    side = 0
    for _ in range(200):
        if abs(b - a) <= 4 * EPS * max(abs(a), abs(b)) + 1e-300:
            break
        x = (a * fb - b * fa) / (fb - fa)
        if not (min(a, b) < x < max(a, b)) or side in (-3, 3):
            x, side = (a + b) / 2, 0  # false position stalls: halve the bracket
        fx = f(x)
        if fx == 0:
            return x
        if (fx > 0) == (fb > 0):
            b, fb = x, fx
            if side < 0:
                fa /= 2  # Illinois: the end that stays is halved
            side = side - 1 if side < 0 else -1
        else:
            a, fa = x, fx
            if side > 0:
                fb /= 2
            side = side + 1 if side > 0 else 1
    return b if abs(fb) < abs(fa) else a
