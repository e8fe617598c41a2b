"""Stage 5, solve: linear blocks, Newton with hints, friction regimes, checks.

Expected values are closed forms derived here, or the seeds' worked answers.
"""
from __future__ import annotations

import math

import pytest
from helpers import answers, error_of, solve_text

from momentum_cli.linalg import SingularError, solve


def rows_of(A):
    return [{j: float(v) for j, v in enumerate(row) if v} for row in A]


@pytest.mark.parametrize("precision", ["float", "refine", "exact"])
def test_python_lapack_sparse_and_exact_solves_agree(precision):
    import numpy as np

    rng = np.random.default_rng(1)
    for n in (2, 5, 12, 20, 80):
        A = rng.normal(size=(n, n)) * np.logspace(-6, 6, n)
        if n == 80:  # sparse: a banded chain goes to the sparse LU
            A = np.triu(np.tril(A, 1), -1) + np.eye(n)
        b = rng.normal(size=n)
        x, q = solve(rows_of(A), b.tolist(), n, precision)
        assert np.allclose(A @ np.array(x), b, rtol=1e-9, atol=1e-9 * np.abs(b).max())
        assert q.cond >= 1.0 and q.precision == precision


def test_a_singular_block_is_refused():
    with pytest.raises(SingularError):
        solve(rows_of([[1.0, 2.0], [2.0, 4.0]]), [1.0, 2.0], 2)


def test_exact_elimination_is_the_correctly_rounded_answer():
    from fractions import Fraction

    A = [[1.0, 1e-17], [1e-17, 1.0]]
    b = [1.0, 0.1]
    x, q = solve(rows_of(A), b, 2, "exact")
    # Cramer's rule in rationals on the same data
    a, bb, c, d = (Fraction(v) for v in (1.0, 1e-17, 1e-17, 1.0))
    det = a * d - bb * c
    want = [(Fraction(1.0) * d - bb * Fraction(0.1)) / det,
            (a * Fraction(0.1) - c * Fraction(1.0)) / det]
    assert x == [float(w) for w in want] and q.bound == 0.0


ROD = """
gravity 9.81 m/s^2 down
body rod: rod(mass = {m} kg, length = {L} m)
point A = rod.end(-)
state 2: rod.angle = {deg} deg, rod.v = (0, -{v} m/s), rod.omega = 0
state 3
impact 2 -> 3:
    contact A with ground normal (0, 1): restitution {e}, smooth
find rod.omega@3, rod.vy@3
"""


@pytest.mark.parametrize("m, L, deg, v, e", [(10, 1, 30, math.sqrt(2 * 9.81), 1),
                                             (2, 0.5, 60, 3, 0.4), (7, 2, 10, 1, 0)])
def test_rod_on_smooth_floor_matches_the_closed_form(m, L, deg, v, e):
    # A at r = -(L/2)(c, s) from G; vy_A' = -e vy_A; J along y only.
    I, d = m * L * L / 12, L / 2 * math.cos(math.radians(deg))
    # unknowns vy', w', J:  m(vy' + v) = J;  I w' = -d J;  vy' - d w' = e v
    J = (1 + e) * v / (1 / m + d * d / I)
    want_w = -d * J / I
    got = answers(ROD.format(m=m, L=L, deg=deg, v=v, e=e))
    assert math.isclose(got["rod.omega@3"], want_w, rel_tol=1e-12)
    assert math.isclose(got["rod.vy@3"], -v + J / m, rel_tol=1e-12, abs_tol=1e-12)


def test_energy_phase_needs_a_hint_when_two_roots_exist():
    text = """
gravity 9.81 m/s^2 down
body b: particle(mass = 1 kg)
state 1: b.y = 2 m, b at rest
state 2: b.y = 0, b.vx = 0
energy 1 -> 2
find b.vy@2
"""
    d = error_of(text)
    assert d.code == "ambiguous" and "b.vy < 0" in " ".join(d.notes)
    got = answers(text.replace("b.vx = 0", "b.vx = 0, b.vy < 0"))
    assert math.isclose(got["b.vy@2"], -math.sqrt(2 * 9.81 * 2), rel_tol=1e-12)


def test_not_enough_energy_is_named():
    text = """
gravity 9.81 m/s^2 down
body b: particle(mass = 1 kg)
state 1: b.y = 0, b.v = (0, 1 m/s)
state 2: b.y = 5 m, b.vx = 0, b.vy > 0
energy 1 -> 2
find b.vy@2
"""
    assert error_of(text).code in ("no-solution",)


FRICTION_WALL = """
body p: particle(mass = 1 kg)
state 1: p.v = ({vt} m/s, -{vn} m/s)
state 2
impact 1 -> 2:
    contact p with ground normal (0, 1): restitution {e}, friction {mu}
find p.v@2
"""


@pytest.mark.parametrize("vt, vn, e, mu", [(3, 4, 0.5, 0.2), (0.5, 4, 0.5, 0.6),
                                           (-3, 2, 0.8, 0.1)])
def test_coulomb_friction_sticks_or_slides_as_the_closed_form_says(vt, vn, e, mu):
    jn = (1 + e) * vn  # per unit mass
    if abs(vt) <= mu * jn:
        want_vt, regime = 0.0, "stick"
    else:
        want_vt, regime = vt - math.copysign(mu * jn, vt), "slide"
    sol = solve_text(FRICTION_WALL.format(vt=vt, vn=vn, e=e, mu=mu))
    got = {n: si for n, _, _, si in sol.answers}
    assert math.isclose(got["p.vx@2"], want_vt, rel_tol=1e-12, abs_tol=1e-12)
    assert math.isclose(got["p.vy@2"], e * vn, rel_tol=1e-12)
    site = sol.system.friction[0]
    assert ("stick" if site.regime == "stick" else "slide") == regime


def test_inconsistent_givens_name_the_conflicting_line():
    text = """
body a: particle(mass = 1 kg)
body b: particle(mass = 1 kg)
state 1: a.v = (1 m/s, 0), b at rest
state 2: a.v = (1 m/s, 0), b.v = (1 m/s, 0)
impact 1 -> 2:
    contact b with a normal (1, 0): restitution 0.5
find b.vx@2
"""
    d = error_of(text)
    assert d.code == "inconsistent" and d.span is not None


def test_under_determined_names_the_unknowns_and_suggests_a_fix():
    text = """
body a: particle(mass = 1 kg)
body b: particle(mass = 1 kg)
state 1: a.v = (1 m/s, 0), b at rest
state 2
impact 1 -> 2:
    contact b with a normal (1, 0): restitution ?
find b.vx@2
"""
    d = error_of(text)
    assert d.code == "under-determined"
    assert "b.vx@2" in d.message and "e[b-a]" in d.message
    assert "restitution" in " ".join(d.notes)


def test_only_the_blocks_the_find_needs_are_solved():
    """Two independent impacts: asking for one solves what it needs plus what the
    report's checks need (each impact's velocities and impulses: its energy check, and
    rows that depend on each other are only found inconsistent by solving them);
    `--all` solves everything."""
    text = """
body a: particle(mass = 1 kg)
body b: particle(mass = 2 kg)
state 1: a.v = (0, -3 m/s), b.v = (0, -1 m/s)
state 2
impact 1 -> 2:
    contact a with ground normal (0, 1): restitution 0.5
state 3: b.v = (0, -1 m/s)
state 4
impact 3 -> 4:
    contact b with ground normal (0, 1): restitution 0.5
find a.vy@2
"""
    sol = solve_text(text)
    assert sol.values["a.vy@2"] == 1.5  # -e * (-3 m/s)
    assert sol.values["J_n[b]@3->4"] == 2 * (0.5 + 1)  # m (v' - v), for the checks
    full = solve_text(text, solve_all=True)
    assert full.values["J_n[b]@3->4"] == 2 * (0.5 + 1)  # m (v' - v)
    assert full.values["b.vy@4"] == 0.5 and full.values["a.vy@2"] == 1.5
