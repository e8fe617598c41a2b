"""Every entry of our unit table checked against pint (a test-only dependency).

momentum keeps its own small table (momentum_cli.units) so that the CLI never imports
pint (~0.7 s with its registry). These tests are the reason we can trust that table:
each name is mapped to pint's spelling, and both the factor to SI and the dimension
(exponents of mass, length, time) must agree.
"""
from __future__ import annotations

import math
import re

import pytest

pint = pytest.importorskip("pint")

from momentum_cli.units import AMBIGUOUS, UNITS, UnitError, parse_unit  # noqa: E402

ureg = pint.UnitRegistry()

# our name -> pint's name, where they differ (the rest are spelled the same in pint).
PINT_NAME = {
    "kg": "kilogram",
    "gram": "gram",
    "t": "metric_ton",
    "tonne": "metric_ton",
    "slug": "slug",
    "lbm": "pound",
    "m": "meter", "mm": "millimeter", "cm": "centimeter", "km": "kilometer",
    "ft": "foot", "in": "inch", "inch": "inch", "yd": "yard", "mi": "mile",
    "s": "second", "ms": "millisecond", "min": "minute", "h": "hour", "hr": "hour",
    "N": "newton", "kN": "kilonewton", "lbf": "force_pound", "kip": "kip",
    "J": "joule", "kJ": "kilojoule", "W": "watt",
    "rad": "radian", "deg": "degree", "degree": "degree", "rev": "revolution",
    "rpm": "revolution / minute",
    "Hz": "hertz",
    "mph": "mile / hour",
    "kph": "kilometer / hour",
    "kW": "kilowatt", "MW": "megawatt", "hp": "horsepower", "sec": "second",
    "°": "degree", "kmh": "kilometer / hour", "fps": "foot / second",
}
# `lb` (and `lbs`) is read as a force first, then as a mass.
PINT_AMBIGUOUS = {
    "lb": ["force_pound", "pound"],
    "lbs": ["force_pound", "pound"],
    "oz": ["force_ounce", "ounce"],
}

REL = 1e-14  # pint and we write the same exact definitions; allow a few ulps


def pint_reading(expr: str) -> tuple[float, tuple[int, int, int]]:
    """(factor to SI, (mass, length, time) exponents) of a pint unit expression."""
    q = ureg.Quantity(1.0, expr)
    dims = q.dimensionality
    extra = set(dims) - {"[mass]", "[length]", "[time]"}
    assert not extra, f"{expr}: unexpected pint dimensions {extra}"
    dim = tuple(int(dims.get(k, 0)) for k in ("[mass]", "[length]", "[time]"))
    # radians are dimensionless in SI (and in our table); pint keeps them as a base
    # unit of magnitude 1, so the base-unit magnitude is the SI factor.
    return float(q.to_base_units().magnitude), dim


def close(a: float, b: float) -> bool:
    return math.isclose(a, b, rel_tol=REL, abs_tol=0.0)


# ---- the table, entry by entry -------------------------------------------------------------

def test_every_entry_has_a_pint_name():
    """A new entry in UNITS or AMBIGUOUS must be added here, so that it gets checked."""
    assert set(UNITS) == set(PINT_NAME), (set(UNITS) ^ set(PINT_NAME))
    assert set(AMBIGUOUS) == set(PINT_AMBIGUOUS), (set(AMBIGUOUS) ^ set(PINT_AMBIGUOUS))


@pytest.mark.parametrize("name", sorted(UNITS))
def test_unit_factor_and_dimension_match_pint(name):
    factor, dim = UNITS[name]
    want_factor, want_dim = pint_reading(PINT_NAME[name])
    assert dim == want_dim, f"{name}: dimension {dim}, pint says {want_dim}"
    assert close(factor, want_factor), f"{name}: factor {factor!r}, pint says {want_factor!r}"


@pytest.mark.parametrize("name", sorted(AMBIGUOUS))
def test_ambiguous_readings_match_pint(name):
    readings = AMBIGUOUS[name]
    pint_names = PINT_AMBIGUOUS[name]
    assert len(readings) == len(pint_names)
    for (factor, dim), pname in zip(readings, pint_names):
        want_factor, want_dim = pint_reading(pname)
        assert dim == want_dim, f"{name} as {pname}: dimension {dim}, pint says {want_dim}"
        assert close(factor, want_factor), f"{name} as {pname}: {factor!r} vs {want_factor!r}"


def test_lb_reads_as_force_first_then_mass():
    (_f1, d1), (_f2, d2) = AMBIGUOUS["lb"]
    assert d1 == (1, 1, -2) and d2 == (1, 0, 0)
    assert parse_unit("lb") == AMBIGUOUS["lb"]


def test_hz_and_rpm_are_rates():
    assert UNITS["Hz"][1] == (0, 0, -1)
    assert UNITS["rpm"][1] == (0, 0, -1)
    # 60 rpm is one revolution per second: 2 pi rad/s
    assert close(60 * UNITS["rpm"][0], 2 * math.pi)


def test_single_names_parse_to_their_table_entry():
    for name, entry in UNITS.items():
        assert parse_unit(name) == [entry], name
    for name, entries in AMBIGUOUS.items():
        assert parse_unit(name) == list(entries), name


# ---- compound expressions ------------------------------------------------------------------

_NAME = re.compile(r"[A-Za-z_][A-Za-z_0-9]*|°")


def to_pint(expr: str, readings: dict[str, str] | None = None) -> str:
    """Our unit expression in pint's spelling (`^` -> `**`, names mapped)."""
    readings = readings or {}

    def name(m):
        n = m.group(0)
        if n in readings:
            return f"({readings[n]})"
        return f"({PINT_NAME[n]})"

    return _NAME.sub(name, expr.replace("^", "**"))


COMPOUND = [
    "m/s^2", "m/s**2", "kg*m^2", "kg*m**2", "N*m", "ft/s^2", "ft/s**2", "km/h", "m/s",
    "ft/s", "N*s", "N*m*s", "kN*m", "slug*ft^2", "lbm*in^2", "kip*ft", "J/s", "rad/s",
    "rad/s^2", "rev/min", "deg/s", "N/m", "lbf/in", "mm/ms", "kg*m/s", "lbf*s", "in/s^2",
    "km/h/s", "m^-1", "s^-2", "kg*m**2/s", "mi/h", "ft/sec", "km/hr", "kW*h", "hp*s",
]


@pytest.mark.parametrize("expr", COMPOUND)
def test_compound_expressions_match_pint(expr):
    got = parse_unit(expr)
    assert len(got) == 1, expr
    factor, dim = got[0]
    want_factor, want_dim = pint_reading(to_pint(expr))
    assert dim == want_dim, f"{expr}: dimension {dim}, pint says {want_dim}"
    assert close(factor, want_factor), f"{expr}: factor {factor!r}, pint says {want_factor!r}"


@pytest.mark.parametrize("expr", ["lb*ft", "lb*in", "lb*s", "lb/ft", "lb*ft^2", "lb/s^2",
                                  "lbs*ft"])
def test_lb_compounds_give_force_then_mass_readings(expr):
    got = parse_unit(expr)
    name = "lbs" if "lbs" in expr else "lb"
    want = [pint_reading(to_pint(expr, {name: reading})) for reading in ("force_pound", "pound")]
    assert len(got) == 2, expr
    for (f, d), (wf, wd) in zip(got, want):
        assert d == wd, f"{expr}: dimension {d}, pint says {wd}"
        assert close(f, wf), f"{expr}: factor {f!r}, pint says {wf!r}"


def test_lb_ft_is_a_moment_first():
    (f, d), _ = parse_unit("lb*ft")
    assert d == (1, 2, -2)
    assert close(f, ureg.Quantity(1, "force_pound * foot").to("newton * meter").magnitude)


def test_left_to_right_like_pint():
    # km/h/s is (km/h)/s, an acceleration, as pint reads it
    (f, d), = parse_unit("km/h/s")
    assert d == (0, 1, -2)
    assert close(f, 1000 / 3600)


# ---- names that are not units --------------------------------------------------------------

@pytest.mark.parametrize("expr", ["g", "kg*g", "m/g"])
def test_g_is_gravity_not_gram(expr):
    with pytest.raises(UnitError) as exc:
        parse_unit(expr)
    msg = str(exc.value)
    assert "gravity" in msg and "gram" in msg, msg
    # the error points at the `g`
    assert expr[exc.value.offset] == "g"


def test_g_in_a_problem_file_is_reported_with_the_gravity_message():
    from helpers import error_of

    text = ("body A: particle(mass = 500 g)\n"
            "state 1: A.v = (1 m/s, 0)\n"
            "find A.vx@1\n")
    d = error_of(text)
    assert "gravity" in d.message and "gram" in d.message, d.message


@pytest.mark.parametrize("expr", ["furlong", "m/parsec", "kgs"])
def test_unknown_names_are_errors(expr):
    with pytest.raises(UnitError) as exc:
        parse_unit(expr)
    assert "unknown unit" in str(exc.value)


@pytest.mark.parametrize("expr", ["/s", "m s", "m//s", "m*", "m^"])
def test_malformed_expressions_are_errors(expr):
    with pytest.raises(UnitError):
        parse_unit(expr)


# ---- what a student types: issue 10 item 11 ------------------------------------------------

def test_kmh_is_kilometres_per_hour_not_kilometres():
    (f, d), = parse_unit("kmh")
    assert d == (0, 1, -1) and close(f, 1000 / 3600)


def test_degree_sign_is_a_degree():
    (f, d), = parse_unit("°")
    assert d == (0, 0, 0) and close(f, math.pi / 180)


def test_oz_reads_as_weight_first_then_mass():
    (f1, d1), (f2, d2) = parse_unit("oz")
    assert d1 == (1, 1, -2) and d2 == (1, 0, 0)
    assert close(16 * f1, AMBIGUOUS["lb"][0][0]) and close(16 * f2, AMBIGUOUS["lb"][1][0])


@pytest.mark.parametrize("name,want,expect", [
    ("km", (0, 1, -1), "km/h"),        # a length where a speed is wanted
    ("kgg", None, "kg"),
    ("ftsec", (0, 1, -1), "ft/sec"),
])
def test_unit_suggestions_have_the_right_dimension(name, want, expect):
    from momentum_cli.units import suggest_unit

    assert f"'{expect}'" in suggest_unit(name, want)


def test_a_unit_of_another_dimension_is_not_suggested_as_itself():
    from momentum_cli.units import suggest_unit

    assert suggest_unit("kmh", (1, 1, -2)) == "" or "kmh'" not in suggest_unit("kmh", (1, 1, -2))
