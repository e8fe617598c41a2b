"""Stage 2, build: SI conversion, inertias, weights to masses, points."""
from __future__ import annotations

import math

import pytest

from momentum_cli.diagnostics import ProblemError
from momentum_cli.scene import build
from momentum_cli.source import Source
from momentum_cli.syntax import parse

LBF, FT = 4.4482216152605, 0.3048


def scene(text: str):
    return build(parse(Source("t.mom", text + "\nfind g\n" if "find" not in text else text)))


@pytest.mark.parametrize("shape, args, inertia", [
    ("rod", "mass = 3 kg, length = 2 m", 3 * 4 / 12),
    ("disk", "mass = 2 kg, radius = 0.5 m", 2 * 0.25 / 2),
    ("ring", "mass = 2 kg, radius = 0.5 m", 2 * 0.25),
    ("sphere", "mass = 5 kg, radius = 0.2 m", 0.4 * 5 * 0.04),
    ("plate", "mass = 6 kg, width = 1 m, height = 2 m", 6 * (1 + 4) / 12),
    ("rigid", "mass = 6 kg, gyration = 0.5 m", 6 * 0.25),
    ("rigid", "mass = 6 kg, inertia = 2 kg*m^2", 2.0),
    ("particle", "mass = 6 kg", 0.0),
])
def test_inertia_formulas(shape, args, inertia):
    sc = scene(f"gravity 9.81 m/s^2 down\nbody b: {shape}({args})")
    assert math.isclose(sc.bodies["b"].inertia, inertia, rel_tol=1e-15)


def test_weight_becomes_mass_with_the_files_own_g():
    sc = scene("gravity 32.2 ft/s^2 down\nbody b: disk(weight = 5 lb, radius = 6 in)")
    b = sc.bodies["b"]
    assert math.isclose(b.mass, 5 * LBF / (32.2 * FT), rel_tol=1e-14)
    assert math.isclose(b.inertia, 0.5 * b.mass * 0.1524**2, rel_tol=1e-14)


def test_lb_is_a_mass_where_a_mass_is_expected():
    sc = scene("body b: particle(mass = 2 lb)")
    assert math.isclose(sc.bodies["b"].mass, 2 * 0.45359237, rel_tol=1e-15)


def test_composite_body_uses_the_parallel_axis_theorem():
    sc = scene("body p: composite\n"
               "    rod(mass = 4 kg, length = 2 m) at (1 m, 0)\n"
               "    particle(mass = 10 kg) at (2 m, 0)\n"
               "point O = p at (0, 0)\n")
    p = sc.bodies["p"]
    xg = (4 * 1 + 10 * 2) / 14
    want = 4 * 4 / 12 + 4 * (1 - xg) ** 2 + 10 * (2 - xg) ** 2
    assert math.isclose(p.mass, 14) and math.isclose(p.inertia, want, rel_tol=1e-14)
    # the pivot O is -xg from G along the body x axis
    assert sc.points["O"].offset == pytest.approx((-xg, 0.0))


def test_rod_ends_are_half_a_length_from_the_centre():
    sc = scene("body r: rod(mass = 1 kg, length = 3 m)\npoint A = r.end(-)\npoint B = r.end(+)")
    assert sc.points["A"].offset == (-1.5, 0.0) and sc.points["B"].offset == (1.5, 0.0)


def test_gravity_into_the_plane_defines_g_without_a_planar_force():
    sc = scene("gravity 32.2 ft/s^2 into plane\nbody b: particle(weight = 1 lbf)")
    assert sc.gravity is None and math.isclose(sc.g, 32.2 * FT)


def test_state_values_are_converted_to_si():
    sc = scene("body b: disk(mass = 1 kg, radius = 1 m)\n"
               "state 1: b.omega = 60 rpm, b.v = (36 km/h, 0), b.angle = 90 deg")
    g = sc.states["1"].givens
    assert math.isclose(g[("b", "omega")][0], 2 * math.pi)
    assert math.isclose(g[("b", "vx")][0], 10.0) and g[("b", "vy")][0] == 0.0
    assert math.isclose(g[("b", "angle")][0], math.pi / 2)


def test_a_normal_is_normalised():
    sc = scene("body b: particle(mass = 1 kg)\nstate 1\nstate 2\n"
               "impact 1 -> 2:\n    contact b with ground normal (3, 4): restitution 0.5\n")
    assert sc.transitions[0].contacts[0].normal == pytest.approx((0.6, 0.8))


@pytest.mark.parametrize("text, words", [
    ("body b: rod(mass = 1 m, length = 1 m)", "needs a mass"),
    ("body b: rod(mass = -1 kg, length = 1 m)", "must be positive"),
    ("body b: particle(weight = 1 lbf)", "needs the file's g"),
    ("body b: particle(mass = 1 kg)\nstate 1: b.omega = 1 rad/s", "particle"),
    ("body b: disk(mass = 1 kg, radius = 1 m)\npoint A = b.end(+)", "not a rod"),
    ("body b: blob(mass = 1 kg)", "unknown shape"),
])
def test_build_errors_name_the_problem(text, words):
    with pytest.raises(ProblemError) as exc:
        scene(text)
    assert words in exc.value.diagnostics[0].message
