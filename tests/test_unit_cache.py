"""parse_unit's remembered answers are its computed ones, and a bad unit is refused
every time it is read."""
import pytest

from momentum_cli.units import UnitError, _parse_unit, parse_unit

UNITS = ["m/s^2", "kg*m**2", "lb*ft", "lb", "N*s", "rad/s", "ft/s", "slug*ft^2", "kJ", "mph"]


@pytest.mark.parametrize("text", UNITS)
def test_cached_readings_are_the_computed_ones(text):
    first, second = parse_unit(text), parse_unit(text)
    assert repr(first) == repr(second) == repr(_parse_unit(text))
    first.append("changed")  # a caller's list is its own
    assert repr(parse_unit(text)) == repr(_parse_unit(text))


@pytest.mark.parametrize("text", ["furlong", "m/", "m^99"])
def test_bad_units_are_refused_each_time(text):
    for _ in range(2):
        with pytest.raises(UnitError):
            parse_unit(text)
