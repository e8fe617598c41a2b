"""Exact products for residuals: p + e == a * b in float64 (Dekker's algorithm).

Used by linalg (one float at a time) and banded (elementwise on numpy arrays): the same
IEEE operations either way, so both paths' residuals agree bit for bit.
"""
from __future__ import annotations

_SPLIT = 134217729.0  # 2^27 + 1, Veltkamp's splitter for float64


def two_product(a, b):
    """p + e == a * b exactly (Dekker); assumes no overflow. Elementwise on numpy arrays
    too (banded.py's residuals)."""
    p = a * b
    t = _SPLIT * a
    ah = t - (t - a)
    al = a - ah
    t = _SPLIT * b
    bh = t - (t - b)
    bl = b - bh
    e = ((ah * bh - p) + ah * bl + al * bh) + al * bl
    return p, e
