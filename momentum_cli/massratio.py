"""Closed-form factors of a mass that changes by a fraction x = mdot t / m0 (part of
`compile`, for flows.py and accretion.py), free of cancellation for every x > -1.

The rocket and accretion laws hold ln(m1/m0) = ln(1 + x) divided by mdot; written as
ln(1 + x)/x and (x - ln(1 + x))/x^2, evaluated with log1p and, for small x, the series,
they keep full precision down to mdot = 0 (where they tend to 1 and 1/2).
"""
from __future__ import annotations

import math

SERIES_BELOW = 0.5  # |x| under which (x - ln(1+x))/x^2 is summed as a series


def ln1p_over_x(x: float) -> float:
    """ln(1 + x)/x, 1 at x = 0 (log1p is exact to an ulp, so no series is needed)."""
    return math.log1p(x) / x if x != 0.0 else 1.0


def x_minus_ln1p_over_x2(x: float) -> float:
    """(x - ln(1 + x))/x^2 = 1/2 - x/3 + x^2/4 - ..., 1/2 at x = 0."""
    if abs(x) < SERIES_BELOW:
        total, term, k = 0.0, 1.0, 0
        while True:
            part = term / (k + 2)
            total += part
            if abs(part) <= 1e-17 * abs(total):
                return total
            term *= -x
            k += 1
    return (x - math.log1p(x)) / (x * x)


def burn_drift(x: float) -> float:
    """(1 - (1 - x) ln(1/(1 - x))/x)/x = 1/2 + x/6 + x^2/12 + ... for a fraction x burnt:
    the rocket's drift behind v0 t + g t^2/2 is e c t^2 (mdot/m0) burn_drift(x)."""
    return ln1p_over_x(-x) - x_minus_ln1p_over_x2(-x)
