"""Number formatting for every renderer: N significant figures, by our function.

Never `repr`: the last digits of a float depend on BLAS and platform; golden files
must not.
"""
from __future__ import annotations

import math

DEFAULT_SIG = 6


def fmt_num(x: float, sig: int = DEFAULT_SIG) -> str:
    """`x` to `sig` significant figures, without a trailing '.0' or a '-0'."""
    if type(x) is float:  # the common case, in one format call: nan, inf and 0 print
        s = f"{x:.{sig}g}"  # as below ('nan', 'inf', '-inf', '0'; '-0' for -0.0)
        if "e" in s:
            mant, exp = s.split("e")
            return f"{mant}e{int(exp)}"
        return "0" if s == "-0" else s
    if x is None:
        return "-"
    if isinstance(x, float) and (math.isnan(x) or math.isinf(x)):
        return "nan" if math.isnan(x) else ("inf" if x > 0 else "-inf")
    if x == 0:
        return "0"
    s = f"{x:.{sig}g}"
    if "e" in s:
        mant, exp = s.split("e")
        exp_i = int(exp)
        return f"{mant}e{exp_i}"
    if s in ("-0",):
        return "0"
    return s


def fmt_tiny(x: float, sig: int = 2, floor: float = 1e-14) -> str:
    """A round-off-sized figure (residual, error bound): below `floor` it prints as
    `< 1e-14`, so that golden files do not depend on the last bits of a float."""
    if x is None:
        return "-"
    if abs(x) < floor:
        return f"< {fmt_num(floor, 1)}"
    return fmt_num(x, sig)
