"""Problems as a student states them (issue 10): unknown effects, normals from geometry,
particles that turn together; each against a closed form derived here."""
from __future__ import annotations

import math

from conftest import EXAMPLES
from helpers import answers, error_of



def _file(name: str) -> str:
    return (EXAMPLES / name).read_text(encoding="utf-8")


# ---- item 5: unknown forces, moments, durations and points --------------------------------
def test_an_unknown_force_from_the_speed_it_gives():
    m, v, t = 2000e3, 0.6, 40.0
    assert math.isclose(answers(_file("unknown_tug_force.mom"))["P"], m * v / t, rel_tol=1e-12)


def test_a_duration_that_is_what_is_left_of_a_total():
    # F1 t1 = m v = F2 t2 and t1 + t2 = T
    m, F1, F2, T = 1200.0, 600.0, 1200.0, 60.0
    t1 = T * F2 / (F1 + F2)
    got = answers(_file("unknown_split_duration.mom"))
    assert math.isclose(got["t@1->2"], t1, rel_tol=1e-12)
    assert math.isclose(got["t@2->3"], T - t1, rel_tol=1e-12)
    assert math.isclose(got["car.vx@2"], F1 * t1 / m, rel_tol=1e-12)


def test_the_centre_of_percussion_is_two_thirds_down_the_bar():
    L = 0.9
    got = answers(_file("centre_of_percussion.mom"))
    assert math.isclose(got["d"], -L / 6, rel_tol=1e-9)
    assert math.isclose(got["below_pivot"], 2 * L / 3, rel_tol=1e-9)


def test_an_unknown_moment_and_its_dimension():
    text = """
unknown M in N*m
body wheel: disk(mass = 20 kg, radius = 0.3 m)
pin wheel to ground
state 1: wheel at rest
state 2: wheel.omega = 10 rad/s
interval 1 -> 2:
    moment M on wheel
    duration 5 s
find M
"""
    assert math.isclose(answers(text)["M"], 0.5 * 20 * 0.09 * 10 / 5, rel_tol=1e-12)
    d = error_of(text.replace("unknown M in N*m", "unknown M in s"))
    assert "a moment needs" in d.message and d.span.line == 8


def test_a_point_an_unknown_locates_takes_only_a_force():
    d = error_of("""
unknown d in m
body bar: rod(mass = 1 kg, length = 1 m)
point Q = bar at (d, 0)
pin Q to ground
state 1: bar at rest
find d
""")
    assert "located by an unknown" in d.message and d.span.line == 5


# each example of these items, by the test that checks it against its closed form
EXAMPLE_CHECKS = {
    "unknown_tug_force": test_an_unknown_force_from_the_speed_it_gives,
    "unknown_split_duration": test_a_duration_that_is_what_is_left_of_a_total,
    "centre_of_percussion": test_the_centre_of_percussion_is_two_thirds_down_the_bar,
}
