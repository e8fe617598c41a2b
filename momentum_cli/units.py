"""Units: a small table of our own, SI factors and dimensions, plain floats afterwards.

Quantities are converted to SI once, in `build`. Angles are dimensionless (rad = 1),
as in SI. `lb` is a force (lbf) where a force is expected, as in US textbooks, and
a mass (lbm) where a mass is. `g` is never gram here: it is the file's gravity.
Every factor is checked against pint in the tests (pint is a test-only dependency).
"""
from __future__ import annotations

import math
import re

# A dimension is a tuple of exponents of (mass, length, time).
Dim = tuple[int, int, int]
NONE: Dim = (0, 0, 0)
MASS: Dim = (1, 0, 0)
LENGTH: Dim = (0, 1, 0)
TIME: Dim = (0, 0, 1)
VELOCITY: Dim = (0, 1, -1)
ACCELERATION: Dim = (0, 1, -2)
RATE: Dim = (0, 0, -1)  # angular velocity (rad/s), 1/s
FORCE: Dim = (1, 1, -2)
MOMENT: Dim = (1, 2, -2)  # N*m, also energy
IMPULSE: Dim = (1, 1, -1)
ANGULAR_IMPULSE: Dim = (1, 2, -1)
INERTIA: Dim = (1, 2, 0)
STIFFNESS: Dim = (1, 0, -2)

_LBF = 4.4482216152605
_LBM = 0.45359237
_FT = 0.3048

# name -> (factor to SI, dimension). Aliases share entries.
UNITS: dict[str, tuple[float, Dim]] = {
    # mass
    "kg": (1.0, MASS), "gram": (1e-3, MASS), "t": (1000.0, MASS), "tonne": (1000.0, MASS),
    "slug": (_LBF / _FT, MASS), "lbm": (_LBM, MASS),
    # length
    "m": (1.0, LENGTH), "mm": (1e-3, LENGTH), "cm": (1e-2, LENGTH), "km": (1e3, LENGTH),
    "ft": (_FT, LENGTH), "in": (0.0254, LENGTH), "inch": (0.0254, LENGTH),
    "yd": (0.9144, LENGTH), "mi": (1609.344, LENGTH),
    # time
    "s": (1.0, TIME), "ms": (1e-3, TIME), "min": (60.0, TIME), "h": (3600.0, TIME),
    "hr": (3600.0, TIME), "sec": (1.0, TIME),
    # force, energy, power
    "N": (1.0, FORCE), "kN": (1e3, FORCE), "lbf": (_LBF, FORCE), "kip": (1e3 * _LBF, FORCE),
    "J": (1.0, MOMENT), "kJ": (1e3, MOMENT), "W": (1.0, (1, 2, -3)), "kW": (1e3, (1, 2, -3)),
    "MW": (1e6, (1, 2, -3)), "hp": (550 * _FT * _LBF, (1, 2, -3)),  # mechanical horsepower
    # angles (dimensionless) and rates
    "rad": (1.0, NONE), "deg": (math.pi / 180, NONE), "degree": (math.pi / 180, NONE),
    "°": (math.pi / 180, NONE),
    "rev": (2 * math.pi, NONE), "rpm": (2 * math.pi / 60, RATE), "Hz": (1.0, RATE),
    # speeds
    "mph": (1609.344 / 3600, VELOCITY), "kph": (1000 / 3600, VELOCITY),
    "kmh": (1000 / 3600, VELOCITY), "fps": (_FT, VELOCITY),  # km/h (not km), ft/s
}
# Spellings offered in "did you mean" besides the names above (what a student means).
COMPOUNDS = ("m/s", "km/h", "km/hr", "mi/h", "ft/s", "ft/sec", "in/s", "m/s^2", "ft/s^2",
             "rad/s", "deg/s", "N*s", "lb*s", "N*m", "lb*ft", "N*m*s", "kg*m^2", "slug*ft^2",
             "kg*m/s", "N/m", "lb/ft", "lb/in", "kg/s", "slug/s")
# `lb` is ambiguous on purpose: force first (textbook weights, lb*ft), then mass.
# `oz` likewise: an ounce-force (a weight) first, then an ounce of mass.
AMBIGUOUS = {"lb": [(_LBF, FORCE), (_LBM, MASS)], "lbs": [(_LBF, FORCE), (_LBM, MASS)],
             "oz": [(_LBF / 16, FORCE), (_LBM / 16, MASS)]}

_TOKEN = re.compile(r"([*/])?([A-Za-z_][A-Za-z_0-9]*|°)(?:(?:\*\*|\^)(-?\d+))?")


class UnitError(ValueError):
    """An unknown unit name in a unit expression; `offset` is where in the text."""

    def __init__(self, message: str, offset: int = 0, name: str | None = None):
        super().__init__(message)
        self.offset = offset
        self.name = name  # the unknown unit name, when that is the trouble


def dim_mul(a: Dim, b: Dim) -> Dim:
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


def dim_div(a: Dim, b: Dim) -> Dim:
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def dim_pow(a: Dim, p: float) -> Dim | None:
    """The dimension of a**p, or None if p does not give whole exponents."""
    out = []
    for x in a:
        y = x * p
        if not math.isfinite(y) or abs(y) > 1e6 or abs(y - round(y)) > 1e-12:
            return None
        out.append(int(round(y)))
    return (out[0], out[1], out[2])


_READINGS: dict[str, tuple] = {}  # parse_unit's answers: a file repeats a few units


def parse_unit(text: str) -> list[tuple[float, Dim]]:
    """All readings of a pint-style unit expression (`m/s^2`, `kg*m**2`, `lb*ft`).

    Evaluated left to right as pint does. Returns one (factor, dim) pair, or two
    when `lb` makes it ambiguous (force reading first).
    """
    hit = _READINGS.get(text)
    if hit is None:
        hit = tuple(_parse_unit(text))
        if len(_READINGS) < 4096:
            _READINGS[text] = hit
    return list(hit)


def _parse_unit(text: str) -> list[tuple[float, Dim]]:
    pos = 0
    readings: list[tuple[float, Dim]] = [(1.0, NONE)]
    first = True
    while pos < len(text):
        m = _TOKEN.match(text, pos)
        if not m or (first and m.group(1)) or (not first and not m.group(1)):
            raise UnitError(f"cannot read unit '{text}'", pos)
        op, name, power = m.group(1), m.group(2), m.group(3)
        if name in UNITS:
            options = [UNITS[name]]
        elif name in AMBIGUOUS:
            options = AMBIGUOUS[name]
        else:
            raise UnitError(unknown_unit_message(name), m.start(2), name)
        p = int(power) if power else 1
        if abs(p) > 12:
            raise UnitError(f"unit power {p} is out of range", m.start(3))
        new = []
        for factor, dim in readings:
            for f, d in options:
                fp, dp = f**p, (d[0] * p, d[1] * p, d[2] * p)
                if op == "/":
                    new.append((factor / fp, dim_div(dim, dp)))
                else:
                    new.append((factor * fp, dim_mul(dim, dp)))
        readings = new
        pos = m.end()
        first = False
    return readings


def unknown_unit_message(name: str, want: Dim | None = None) -> str:
    if name == "g":
        return "'g' is the file's gravity, not a unit (write grams as 'gram')"
    return f"unknown unit '{name}'" + suggest_unit(name, want)


def suggest_unit(name: str, want: Dim | None = None) -> str:
    """A "; did you mean X?" suffix for a unit, preferring those of dimension `want`."""
    from .diagnostics import did_you_mean

    every = [u for u in list(UNITS) + list(AMBIGUOUS) + list(COMPOUNDS)
             if u not in _TERSE and u != name]
    if want is not None:
        every = [u for u in every if any(d == want for _f, d in parse_unit(u))]
    return did_you_mean(name, every)


# read but not offered as suggestions: the spelled-out forms say more (`km` -> `km/h`)
_TERSE = {"kmh", "kph", "fps", "sec", "°"}


def reading_for(readings: list[tuple[float, Dim]], want: Dim | None) -> tuple[float, Dim]:
    """The reading of a unit with dimension `want`, or the first one."""
    if want is not None:
        for r in readings:
            if r[1] == want:
                return r
    return readings[0]


_NAMED: dict[Dim, str] = {
    NONE: "", MASS: "kg", LENGTH: "m", TIME: "s", VELOCITY: "m/s", ACCELERATION: "m/s^2",
    RATE: "1/s", FORCE: "N", MOMENT: "N*m", IMPULSE: "N*s", ANGULAR_IMPULSE: "N*m*s",
    INERTIA: "kg*m^2", STIFFNESS: "N/m", (1, 2, -3): "W", (1, 0, -1): "kg/s",
}

DIM_WORDS: dict[Dim, str] = {
    NONE: "a number", MASS: "a mass", LENGTH: "a length", TIME: "a time",
    VELOCITY: "a velocity", ACCELERATION: "an acceleration", RATE: "an angular velocity",
    FORCE: "a force", MOMENT: "a moment or energy", IMPULSE: "an impulse",
    ANGULAR_IMPULSE: "an angular impulse", INERTIA: "a moment of inertia",
    STIFFNESS: "a stiffness",
}


def si_label(dim: Dim) -> str:
    """The SI unit we print for a dimension (`N*s`, `m/s`, `kg*m^2`...)."""
    if dim in _NAMED:
        return _NAMED[dim]
    parts = []
    for sym, e in zip(("kg", "m", "s"), dim):
        if e == 1:
            parts.append(sym)
        elif e:
            parts.append(f"{sym}^{e}")
    return "*".join(parts)


def describe(dim: Dim) -> str:
    """Physics words for a dimension, for error messages."""
    return DIM_WORDS.get(dim, f"a quantity in {si_label(dim) or '1'}")
