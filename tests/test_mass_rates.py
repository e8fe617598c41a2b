"""Bodies whose mass changes: closed forms free of cancellation at any rate, and phases
integrated numerically as blocks that solve runs once their start is known.

Expected values are closed forms derived here (Taylor series of ln(1 + x) for the tiny
rates, where ln(m1/m0)/mdot would cancel; momentum integrals otherwise).
"""
from __future__ import annotations

import math

import pytest
from helpers import answers, error_of

from momentum_cli.massratio import burn_drift, ln1p_over_x, x_minus_ln1p_over_x2

M0, V0, T = 1e4, 3.0, 10.0  # a 10 t body at 3 m/s, for 10 s

GAIN = """
{gravity}
body c: particle(mass = {m0} kg)
state 1: c.v = ({vx} m/s, {vy} m/s), c.pos = (0, 0)
state 2
{kind} c 1 -> 2:
    rate {rate} kg/s
    duration {t} s
find c.vx@2, c.vy@2, c.x@2, c.y@2, c.mass@2
"""


def series_ln1p(x: float, terms: int = 8) -> float:
    """ln(1 + x) by its Taylor series (|x| small): the independent reference."""
    return sum((-1) ** (k + 1) * x ** k / k for k in range(1, terms + 1))


@pytest.mark.parametrize("rate", [1e-9, 1e-15, 1e-170, 0.0])
def test_a_gain_at_a_tiny_rate_moves_v0_t(rate):
    """The issue's case: 1e-9 kg/s gave 30.0027 m, 1e-15 kg/s '0 m', 1e-170 kg/s a
    ZeroDivisionError. Momentum m v = m0 v0 (the mass joins at rest), so
    x = v0 m0 ln(1 + x_)/mdot = v0 t (1 - x_/2 + x_^2/3 - ...), x_ = mdot t/m0."""
    got = answers(GAIN.format(gravity="", m0=M0, vx=V0, vy=0, kind="gain", rate=rate, t=T))
    x_ = rate * T / M0
    want_x = V0 * T * (1 - x_ / 2 + x_ * x_ / 3)
    assert math.isclose(got["c.x@2"], want_x, rel_tol=1e-15)
    assert math.isclose(got["c.vx@2"], M0 * V0 / (M0 + rate * T), rel_tol=1e-15)
    assert got["c.mass@2"] == M0 + rate * T


@pytest.mark.parametrize("rate", [1e-9, 1e-15, 1e-170, 0.0])
def test_a_tiny_gain_under_gravity_falls_as_a_constant_mass(rate):
    """m v = m0 v0 + g t (m0 + m1)/2: at a vanishing rate, y = v0 t - g t^2/2."""
    got = answers(GAIN.format(gravity="gravity 9.81 m/s^2 down", m0=M0, vx=0, vy=V0,
                              kind="gain", rate=rate, t=T))
    x_ = rate * T / M0
    # y = v0 t phi + g t^2 (psi + 1/2)/2 with phi ~ 1 - x/2, psi ~ 1/2 - x/3
    want = V0 * T * (1 - x_ / 2) - 9.81 * T * T / 2 * (1 - x_ / 3)
    assert math.isclose(got["c.y@2"], want, rel_tol=1e-14)
    assert math.isclose(got["c.vy@2"], (M0 * V0 - 9.81 * T * (2 * M0 + rate * T) / 2) /
                        (M0 + rate * T), rel_tol=1e-14)


@pytest.mark.parametrize("rate", [5.0, 400.0])
def test_a_gain_at_a_normal_rate_matches_the_log_form(rate):
    """Away from mdot = 0 the textbook form has no cancellation: x = v0 m0 ln(m1/m0)/mdot
    for mass joining at rest, and m v = m0 v0."""
    m0 = 200.0
    got = answers(GAIN.format(gravity="", m0=m0, vx=V0, vy=0, kind="gain", rate=rate, t=T))
    m1 = m0 + rate * T
    assert math.isclose(got["c.x@2"], V0 * m0 * math.log(m1 / m0) / rate, rel_tol=1e-13)
    assert math.isclose(got["c.vx@2"], m0 * V0 / m1, rel_tol=1e-14)


def test_a_loss_at_a_tiny_rate_keeps_full_precision():
    """`lose` with the mass leaving at rest (absolute): m v = m0 v0 still, m1 = m0 - mdot t."""
    rate = 1e-12
    got = answers(GAIN.format(gravity="", m0=M0, vx=V0, vy=0, kind="lose", rate=rate, t=T)
                  .replace("rate", "velocity (0, 0)\n    rate"))
    x_ = -rate * T / M0
    assert math.isclose(got["c.x@2"], V0 * T * (1 - x_ / 2 + x_ * x_ / 3), rel_tol=1e-15)
    assert math.isclose(got["c.vx@2"], V0 / (1 + x_), rel_tol=1e-15)


BURN = """
body r: particle(mass = {m0} kg)
state 1: r.v = ({v0} m/s, 0), r.pos = (0, 0)
state 2
burn r 1 -> 2:
    exhaust 3000 m/s along (-1, 0)
    rate {rate} kg/s
    duration {t} s
find r.vx@2, r.x@2
"""


@pytest.mark.parametrize("rate", [1e-9, 1e-15, 1e-170, 0.0])
def test_a_burn_at_a_tiny_rate_keeps_full_precision(rate):
    """v1 = v0 + c ln(m0/m1) = v0 + c (x + x^2/2 + ...), x = mdot t/m0; the drift
    r1 - r0 - v0 t = c (t - (m1/mdot) ln(m0/m1)) = c t (x/2 + x^2/6 + ...)."""
    c, v0 = 3000.0, 0.0
    got = answers(BURN.format(m0=M0, v0=v0, rate=rate, t=T))
    x = rate * T / M0
    dv = -c * series_ln1p(-x)
    drift = c * T * (x / 2 + x * x / 6)
    if rate == 0.0:
        assert got["r.vx@2"] == 0.0 and got["r.x@2"] == 0.0
    else:
        assert math.isclose(got["r.vx@2"], dv, rel_tol=1e-14)
        assert math.isclose(got["r.x@2"], drift, rel_tol=1e-14)


def test_a_burn_at_a_normal_rate_matches_the_rocket_equation():
    """Burning 60 % of the mass: the textbook log forms, no cancellation at this rate."""
    m0, rate, t, c, v0 = 1000.0, 12.0, 50.0, 3000.0, 7.0
    got = answers(BURN.format(m0=m0, v0=v0, rate=rate, t=t))
    m1 = m0 - rate * t
    assert math.isclose(got["r.vx@2"], v0 + c * math.log(m0 / m1), rel_tol=1e-14)
    assert math.isclose(got["r.x@2"], v0 * t + c * (t - m1 / rate * math.log(m0 / m1)),
                        rel_tol=1e-13)


def _series(coef, x: float, terms: int = 40) -> float:
    return math.fsum(coef(k) * x ** k for k in range(terms))


@pytest.mark.parametrize("x", [-0.9, -0.5, -0.49, -1e-3, -1e-300, 0.0, 1e-300, 1e-8, 0.3,
                               0.5, 2.0, 1e6])
def test_the_mass_ratio_factors_agree_with_their_definitions(x):
    """Against the definitions where they do not cancel, and their series where they do:
    ln(1+x)/x = sum (-x)^k/(k+1), (x - ln(1+x))/x^2 = sum (-x)^k/(k+2)."""
    if abs(x) > 0.1:
        assert math.isclose(ln1p_over_x(x), math.log(1 + x) / x, rel_tol=1e-14)
        assert math.isclose(x_minus_ln1p_over_x2(x), (x - math.log(1 + x)) / x ** 2,
                            rel_tol=1e-12)
    else:
        assert math.isclose(ln1p_over_x(x), _series(lambda k: 1 / (k + 1), -x),
                            rel_tol=1e-15)
        assert math.isclose(x_minus_ln1p_over_x2(x), _series(lambda k: 1 / (k + 2), -x),
                            rel_tol=1e-15)


@pytest.mark.parametrize("b", [0.0, 1e-300, 1e-12, 1e-4, 0.05, 0.3, 0.6, 0.99])
def test_the_burn_drift_factor(b):
    """(1 - (1 - b) ln(1/(1 - b))/b)/b = sum b^k/((k+1)(k+2)): the series where it
    cancels, the definition where it does not."""
    if b > 0.1:
        L = -math.log(1 - b)
        assert math.isclose(burn_drift(b), (1 - (1 - b) * L / b) / b, rel_tol=1e-12)
    else:
        assert math.isclose(burn_drift(b), _series(lambda k: 1 / ((k + 1) * (k + 2)), b),
                            rel_tol=1e-15)


# ---- integration blocks: the start of a numerically integrated phase is solved first

IMPACT_THEN_GAIN = """
body a: particle(mass = 1 kg)
body b: particle(mass = 3 kg)
state 1: a.v = (4 m/s, 0), b at rest, b.pos = (0, 0)
state 2 "just after the impact"
state 3 "{end}"{given}
impact 1 -> 2:
    contact b with a normal (1, 0): restitution 1, smooth
gain b 2 -> 3:
    rate 1 kg/s * t / (1 s)     # m = m0 + t^2/2 (in kg, t in s)
{duration}
find b.vx@3, b.mass@3, t@2->3{more}
"""


def test_a_gain_starts_from_the_velocity_an_impact_solves():
    """The elastic impact gives b v0 = 2 m1 u/(m1 + m2) = 2 m/s; the mass joins at rest,
    so m v = m0 v0: with m = 3 + t^2/2 kg, b reaches 1 m/s when m = 6 kg, at t = sqrt(6) s.
    The rate varies with t, so the gain is an integration block after the impact's."""
    got = answers(IMPACT_THEN_GAIN.format(end="slowed to 1 m/s", given=": b.vx = 1 m/s",
                                          duration="", more=""))
    assert math.isclose(got["t@2->3"], math.sqrt(6.0), rel_tol=1e-8)
    assert math.isclose(got["b.mass@3"], 6.0, rel_tol=1e-8)
    assert got["b.vx@3"] == 1.0


def test_a_timed_gain_after_an_impact_has_the_atan_closed_form():
    """Over a given 2 s: v = m0 v0/m(t) and x = m0 v0 sqrt(2/m0) atan(t/sqrt(2 m0))."""
    got = answers(IMPACT_THEN_GAIN.format(end="2 s later", given="",
                                          duration="    duration 2 s", more=", b.x@3"))
    m0, v0, t = 3.0, 2.0, 2.0
    assert math.isclose(got["b.vx@3"], m0 * v0 / (m0 + t * t / 2), rel_tol=1e-9)
    assert math.isclose(got["b.mass@3"], m0 + t * t / 2, rel_tol=1e-9)
    want_x = m0 * v0 * math.sqrt(2 / m0) * math.atan(t / math.sqrt(2 * m0))
    assert math.isclose(got["b.x@3"], want_x, rel_tol=1e-9)


def test_an_integration_whose_start_depends_on_its_end_is_refused():
    """The end velocity is given and the start is only found through the phase: the
    integration runs forward, so the file is refused with a located error."""
    text = """
body b: particle(mass = 3 kg)
state 1: b.pos = (0, 0)
state 2: b.vx = 1 m/s, b.vy = 0 m/s
gain b 1 -> 2:
    rate 1 kg/s * t / (1 s)
    duration 2 s
find b.vx@1
"""
    d = error_of(text)
    assert d.span.line == 5 and "integrated" in d.message, d.message


LOADED_UNTIL = """
body c: particle(mass = 200 kg)
state 1: c.v = (3 m/s, 0 m/s), c.pos = (0, 0)
state 2: c.vx = 2.4 m/s
gain c 1 -> 2:
    rate 5 kg/s
equation t@1->2 = {t} s
find t@1->2, c.x@2
"""


def test_a_redundant_statement_of_an_integrated_answer_is_judged_at_its_tolerance():
    """m v = m0 v0: the cart slows to 2.4 m/s at m = 250 kg, t = 10 s. Stating t = 10 s
    holds within the integrator's tolerance; 1e-3 of it off is an inconsistency."""
    got = answers(LOADED_UNTIL.format(t=10))
    assert math.isclose(got["t@1->2"], 10.0, rel_tol=1e-9)
    d = error_of(LOADED_UNTIL.format(t=10.01))
    assert d.code == "inconsistent" and d.span.line == 7, d.message


def test_a_gain_starts_with_the_mass_an_integrated_burn_leaves():
    """A throttled burn (12 -> 4 kg/s over 50 s: 400 kg of 1000 kg) gives v1 = c ln(m0/m1)
    whatever the rate's profile; then 100 kg joins at rest: m v = const. The gain's start
    mass exists only once the burn's block is solved, so it is an integration block too."""
    text = """
body r: particle(mass = 1000 kg)
state 1: r at rest, r.pos = (0, 0)
state 2
state 3
burn r 1 -> 2:
    exhaust 2400 m/s along (-1, 0)
    rate 12 kg/s - (8 kg/s) * t / (50 s)
    duration 50 s
gain r 2 -> 3:
    rate 10 kg/s
    duration 10 s
find r.vx@2, r.vx@3, r.mass@3
"""
    got = answers(text)
    v1 = 2400 * math.log(1000 / 600)
    assert math.isclose(got["r.vx@2"], v1, rel_tol=1e-9)
    assert math.isclose(got["r.vx@3"], v1 * 600 / 700, rel_tol=1e-9)
    assert math.isclose(got["r.mass@3"], 700.0, rel_tol=1e-9)
