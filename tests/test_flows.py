"""Open systems (issue 4): steady control volumes and burning bodies, against closed
forms derived here: F = mdot (v - u)(1 - cos theta), mdot v for a conveyor, the rocket
equation dv = c ln(m0/m1) and its height at burn-out."""
from __future__ import annotations

import math

import pytest
from conftest import EXAMPLES
from helpers import answers, error_of


def ex(name: str) -> dict[str, float]:
    return answers((EXAMPLES / f"{name}.mom").read_text(encoding="utf-8"))


def close(a, b, rel=1e-12):
    return math.isclose(a, b, rel_tol=rel, abs_tol=1e-12 * max(1.0, abs(b)))


def test_jet_on_a_fixed_vane():
    mdot, v, th = 2.0, 20.0, math.radians(60)
    got = ex("flow_jet_fixed_vane")
    assert close(got["Fx[mount]"], -mdot * v * (1 - math.cos(th)))
    assert close(got["Fy[mount]"], mdot * v * math.sin(th))
    # moment about the inlet: the outflow leaves at r = (0.1, 0.05) m
    assert close(got["M[mount]"], mdot * v * (0.1 * math.sin(th) - 0.05 * math.cos(th)))


def test_jet_on_a_moving_vane():
    rho, A, v, u, th = 1000.0, 0.002, 25.0, 10.0, math.radians(120)
    mdot = rho * A * (v - u)
    got = ex("flow_jet_moving_vane")
    assert close(got["mdot_on_vane"], mdot)
    assert close(got["Fx[cart]"], -mdot * (v - u) * (1 - math.cos(th)))
    assert close(got["Fy[cart]"], mdot * (v - u) * math.sin(th))


def test_jet_engine_thrust():
    got = ex("flow_jet_engine_thrust")
    assert close(got["thrust"], (60 + 1.2) * 600 - 60 * 250)
    assert got["Fy[pylon]"] == 0.0


def test_conveyor_being_loaded():
    got = ex("flow_conveyor_sand")
    assert close(got["Fx[drive]"], 20 * 1.5) and close(got["Fy[drive]"], 20 * 3)


def test_sprinkler_held_still():
    got = ex("flow_sprinkler_torque")
    # each nozzle's flux r x (mdot v) leaves the volume; the hub balances both
    assert close(got["M[hub]"], -2 * 0.3 * 0.2 * 8)
    assert got["Fx[hub]"] == 0.0 and got["Fy[hub]"] == 0.0


def test_rocket_in_free_space():
    m0, dm, mdot, c, v0 = 1000.0, 300.0, 5.0, 3000.0, 7500.0
    m1, t = m0 - dm, dm / mdot
    got = ex("flow_rocket_free_space")
    assert close(got["dv"], c * math.log(m0 / m1))
    assert close(got["t@1->2"], t) and close(got["probe.mass@2"], m1)
    assert close(got["probe.x@2"], v0 * t + c * (t - m1 / mdot * math.log(m0 / m1)))


def test_rocket_rising_against_gravity():
    m0, dm, mdot, c, g = 1000.0, 600.0, 8.0, 2500.0, 9.81
    m1, t = m0 - dm, dm / mdot
    got = ex("flow_rocket_gravity")
    assert close(got["t@1->2"], t)
    assert close(got["rocket.vy@2"], c * math.log(m0 / m1) - g * t)
    assert close(got["rocket.y@2"], c * (t - m1 / mdot * math.log(m0 / m1)) - g * t * t / 2)


def test_rocket_velocity_satisfies_the_variable_mass_balance():
    """m dv/dt = mdot c - m g at every instant: check it by differencing v(t) from the
    program at two burn durations around t (an independent route to the same law)."""
    base = (EXAMPLES / "flow_rocket_gravity.mom").read_text(encoding="utf-8")
    t, h = 40.0, 1e-3

    def v_at(tt):
        text = base.replace("burns 600 kg", f"duration {tt} s")
        return answers(text)["rocket.vy@2"]

    m = 1000.0 - 8.0 * t
    dvdt = (v_at(t + h) - v_at(t - h)) / (2 * h)
    assert math.isclose(m * dvdt, 8.0 * 2500.0 - m * 9.81, rel_tol=1e-6)


def test_a_cart_leaking_sand_keeps_its_speed():
    got = ex("flow_cart_leaking_sand")
    assert got["cart.vx@2"] == 2.0 and close(got["cart.x@2"], 20.0)
    assert close(got["cart.mass@2"], 160.0)


STEADY = """
steady box:
    inflow rate {a}, velocity (1 m/s, 0)
    outflow rate {b}, velocity (2 m/s, 0)
    support s
find Fx[s]
"""


@pytest.mark.parametrize("a, b, line, words", [
    ("2 kg/s", "1.5 kg/s", 2, "mass balance"),
    ("-2 kg/s", "-2 kg/s", 3, "cannot be negative"),
    ("2 m/s", "2 kg/s", 3, "mass rate"),
])
def test_inconsistent_or_negative_flows_name_the_line(a, b, line, words):
    d = error_of(STEADY.format(a=a, b=b))
    assert d.span.line == line and words in d.message


BURN = """
body r: particle(mass = 100 kg)
state 1: r at rest
state 2
burn r 1 -> 2:
    exhaust 1000 m/s along (0, -1)
    rate {rate}
    {amount}
find r.vy@2
"""


def test_burning_more_than_the_body_has_is_an_error():
    d = error_of(BURN.format(rate="1 kg/s", amount="burns 150 kg"))
    assert d.span.line == 5 and "no mass would be left" in d.message


def test_a_burn_then_an_impact_uses_the_mass_the_burn_left():
    m0, m1, c, e = 60.0, 50.0, 100.0, 0.5
    v = c * math.log(m0 / m1)
    got = ex("flow_rocket_cart_hits_wall")
    assert close(got["cart.vx@2"], v) and close(got["cart.vx@3"], -e * v)
    assert close(got["J_n[cart]@2->3"], m1 * (1 + e) * v)
    assert close(got["cart.mass@3"], m1)
    assert close(got["T_lost@2->3"], 0.5 * m1 * v * v * (1 - e * e))


def test_stage_separation_after_a_burn_conserves_the_pairs_momentum():
    V = 2800.0 * math.log(900.0 / 600.0)
    m_lo, m_up, s = 200.0, 400.0, 4.0
    got = ex("flow_rocket_stage_separation")
    assert close(got["stack.vx@2"], V)
    # momentum: m_lo v_lo + m_up v_up = (m_lo + m_up) V; separation: v_up - v_lo = s
    assert close(got["upper.vx@3"], V + s * m_lo / (m_lo + m_up))
    assert close(got["lower.vx@3"], V - s * m_up / (m_lo + m_up))
    assert close(got["J_n[springs]@2->3"], m_up * s * m_lo / (m_lo + m_up))


def test_a_contact_takes_a_restitution_or_a_separation_speed_not_both():
    text = """
body a: particle(mass = 1 kg)
body b: particle(mass = 1 kg)
state 1: a at rest, b at rest
state 2
impact 1 -> 2:
    contact a with b normal (1, 0): restitution 0.5, separation 1 m/s
find a.vx@2
"""
    d = error_of(text)
    assert d.span.line == 7 and "not both" in d.message


def test_a_weight_rate_in_lb_per_s_becomes_a_mass_rate_with_the_files_g():
    text = """
gravity 32.2 ft/s^2 down
steady nozzle:
    inflow rate 6 lb/s, velocity (0, 0)
    outflow rate 6 lb/s, velocity (80 ft/s, 0)
    support hold
find Fx[hold] in lbf
"""
    # mdot = W/g = 6/32.2 slug/s; the hold pushes back on the jet: F = mdot v
    want_lbf = 6 / 32.2 * 80
    got = answers(text)
    assert math.isclose(got["Fx[hold]"], want_lbf * 4.4482216152605, rel_tol=1e-12)


def test_chain_lifted_from_a_pile():
    lam, v, y, g = 2.0, 1.5, 1.2, 9.81
    assert close(ex("flow_chain_lifted")["F"], lam * g * y + lam * v * v)


def test_chain_falling_onto_a_scale_reads_three_times_its_weight_on_the_pan():
    lam, x, g = 0.5, 0.8, 9.81
    got = ex("flow_chain_on_scale")
    assert close(got["N"], 3 * lam * g * x) and close(got["ratio"], 3.0)


def test_an_instant_balance_is_the_variable_mass_particle_law():
    """sum F = m a + mdot (v - v_m), from the formula sheet: a body of 10 kg moving at
    (3, 0) m/s accelerating at (2, 0) m/s^2 while gaining 4 kg/s of mass that arrives at
    (1, 0) m/s needs F = 10*2 + 4*(3 - 1) = 28 N."""
    text = """
instant b:
    contents mass 10 kg, velocity (3 m/s, 0), acceleration (2 m/s^2, 0)
    inflow rate 4 kg/s, velocity (1 m/s, 0)
    support push
find Fx[push]
"""
    assert close(answers(text)["Fx[push]"], 10 * 2 + 4 * (3 - 1))


def test_a_burn_whose_rate_varies_is_integrated_numerically():
    """dv = c ln(m0/m1) holds for any rate profile (constant c); the distance has no
    closed form here, so the test integrates x = int c ln(m0/m(s)) ds by composite
    Simpson on 20,000 intervals (its own error ~1e-13)."""
    m0, c, T = 1000.0, 2400.0, 50.0

    def burned(s):  # mdot = 12 - 8 s/50 kg/s
        return 12 * s - 4 / 50 * s * s

    m1 = m0 - burned(T)
    n = 20000
    h = T / n
    f = [c * math.log(m0 / (m0 - burned(k * h))) for k in range(n + 1)]
    x = h / 3 * (f[0] + f[-1] + 4 * sum(f[1:-1:2]) + 2 * sum(f[2:-1:2]))
    got = ex("flow_rocket_throttled")
    assert close(got["rocket.mass@2"], m1)
    assert math.isclose(got["rocket.vx@2"], c * math.log(m0 / m1), rel_tol=1e-9)
    assert math.isclose(got["rocket.x@2"], x, rel_tol=1e-9)


def test_a_varying_burn_that_runs_out_of_mass_is_an_error():
    d = error_of(BURN.format(rate="1 kg/s + (1 kg/s^2) * t", amount="duration 20 s"))
    assert d.span.line == 5 and "runs out of mass" in d.message


# ---- gaining and losing mass over an interval (`gain`, `lose`) ---------------------------
# Closed forms derived here. The balance is d(m v)/dt = sum F + m g + mdot v_in.


def test_chain_lifted_by_a_constant_force_obeys_the_energy_like_integral():
    """p = lambda y v, dp/dt = P - lambda g y; multiplying by p = lambda y dy/dt and
    integrating: (lambda y v)^2/2 = lambda (P y^2/2 - lambda g y^3/3) + C', i.e.
    v^2 = P/lambda - 2 g y/3 + C/y^2 with C fixed by v = 0 at y0."""
    lam, P, g, y0, y1 = 2.0, 40.0, 9.81, 0.05, 1.5
    C = -y0 ** 2 * (P / lam - 2 * g * y0 / 3)
    v1 = math.sqrt(P / lam - 2 * g * y1 / 3 + C / y1 ** 2)
    got = ex("flow_chain_lifted_by_force")
    assert math.isclose(got["chain.vy@2"], v1, rel_tol=1e-8)
    # every link picked up stays: m = lambda y
    assert math.isclose(got["chain.mass@2"], lam * y1, rel_tol=1e-8)
    # the time: t = int dy / v(y), by Simpson in y on the smooth part, and near y0
    # (where v ~ sqrt(y - y0)) by the substitution y = y0 + s^2
    n = 20000

    def dt_ds(s):  # dt = dy/v = 2 s ds/v; at s = 0, v^2 ~ s^2 d(v^2)/dy
        if s == 0:
            return 2 / math.sqrt(-2 * g / 3 - 2 * C / y0 ** 3)
        y = y0 + s * s
        return 2 * s / math.sqrt(P / lam - 2 * g * y / 3 + C / (y * y))

    S = math.sqrt(y1 - y0)
    h = S / n
    f = [dt_ds(k * h) for k in range(n + 1)]
    t = h / 3 * (f[0] + f[-1] + 4 * sum(f[1:-1:2]) + 2 * sum(f[2:-1:2]))
    assert math.isclose(got["t@1->2"], t, rel_tol=1e-8)


def test_a_cart_loaded_while_moving_keeps_its_momentum():
    m0, v0, mdot, T = 200.0, 3.0, 5.0, 10.0
    got = ex("flow_cart_loaded_sand")
    assert close(got["cart.vx@2"], m0 * v0 / (m0 + mdot * T))
    assert close(got["cart.x@2"], m0 * v0 / mdot * math.log(1 + mdot * T / m0))
    assert close(got["cart.mass@2"], m0 + mdot * T)


def test_a_loaded_cart_then_hits_a_wall_with_the_mass_it_gained():
    m1 = 200.0 + 5.0 * 10.0
    v = 200.0 * 3.0 / m1
    e = 0.5
    got = ex("flow_cart_loaded_hits_wall")
    assert close(got["cart.vx@2"], v) and close(got["cart.vx@3"], -e * v)
    assert close(got["J_n[cart]@2->3"], m1 * (1 + e) * v)
    assert close(got["cart.mass@3"], m1)
    assert close(got["T_lost@2->3"], 0.5 * m1 * v * v * (1 - e * e))


def test_a_raindrop_in_mist_tends_to_a_terminal_speed():
    """mdot = k m v, mist at rest: dm/ds = k m, so m = m0 e^(k s); d(m v)/dt = m g with
    v d/ds: (m v) d(m v)/ds = m^2 g, so (m v)^2 = m0^2 g (e^(2 k s) - 1)/k."""
    k, g, s, m0 = 0.01, 9.81, 100.0, 5e-5
    got = ex("flow_raindrop_in_mist")
    assert math.isclose(got["drop.vy@2"], -math.sqrt(g / k * (1 - math.exp(-2 * k * s))),
                        rel_tol=1e-8)
    assert math.isclose(got["drop.mass@2"], m0 * math.exp(k * s), rel_tol=1e-8)


GAIN = """
{gravity}
body c: particle(mass = {m0} kg)
state 1: c.v = ({vx} m/s, {vy} m/s), c.pos = (0, 0)
state 2{end}
{kind} c 1 -> 2:
{clauses}
find {finds}
"""


def gain(clauses, finds, kind="gain", end="", gravity="", m0=200, vx=3, vy=0):
    return answers(GAIN.format(gravity=gravity, m0=m0, vx=vx, vy=vy, end=end, kind=kind,
                               clauses=clauses, finds=finds))


def test_an_end_condition_instead_of_a_duration_finds_the_time():
    """The loaded cart slows to 2.4 m/s when m = 250 kg, i.e. after t = 10 s (the end
    found by integration, not by the closed form)."""
    got = gain("    rate 5 kg/s", "t@1->2, c.x@2, c.mass@2", end=": c.vx = 2.4 m/s")
    assert math.isclose(got["t@1->2"], 10.0, rel_tol=1e-9)
    assert math.isclose(got["c.x@2"], 600 / 5 * math.log(1.25), rel_tol=1e-9)
    assert math.isclose(got["c.mass@2"], 250.0, rel_tol=1e-9)


def test_a_gain_with_gravity_a_force_and_falling_mass_has_the_closed_form():
    """Rain (2 kg/s, arriving at -5 m/s) falls into a 10 kg bucket lifted by 150 N:
    m v = m0 v0 + (F - m0 g + mdot v_in) t - mdot g t^2/2, m = m0 + mdot t; the height
    by Simpson's rule on v(t)."""
    m0, v0, md, vin, F, g, T = 10.0, 1.0, 2.0, -5.0, 150.0, 9.81, 3.0

    def v(t):
        return (m0 * v0 + (F - m0 * g + md * vin) * t - md * g * t * t / 2) / (m0 + md * t)

    n = 2000
    h = T / n
    f = [v(k * h) for k in range(n + 1)]
    y = h / 3 * (f[0] + f[-1] + 4 * sum(f[1:-1:2]) + 2 * sum(f[2:-1:2]))
    got = gain("    rate 2 kg/s\n    velocity (0, -5 m/s)\n    force (0, 150 N)\n"
               "    duration 3 s", "c.vy@2, c.y@2, c.mass@2", gravity="gravity 9.81 m/s^2 down",
               m0=10, vx=0, vy=1)
    assert close(got["c.vy@2"], v(T), rel=1e-12)
    assert math.isclose(got["c.y@2"], y, rel_tol=1e-11)
    assert close(got["c.mass@2"], m0 + md * T)


def test_losing_mass_at_an_absolute_velocity_uses_the_same_balance():
    """A 200 kg cart at 3 m/s throws 4 kg/s of sand backwards at -1 m/s (absolute) for
    10 s: m v = m0 v0 - mdot v_out t."""
    got = gain("    rate 4 kg/s\n    velocity (-1 m/s, 0)\n    duration 10 s",
               "c.vx@2, c.mass@2", kind="lose")
    assert close(got["c.vx@2"], (200 * 3 - 4 * (-1) * 10) / 160)
    assert close(got["c.mass@2"], 160.0)


def test_mass_that_leaves_with_the_body_changes_nothing_but_the_mass():
    """`lose` without a velocity: the mass leaves at the body's own velocity."""
    got = gain("    rate 4 kg/s * (1 + t / (10 s))\n    duration 10 s",
               "c.vx@2, c.x@2, c.mass@2", kind="lose")
    assert math.isclose(got["c.vx@2"], 3.0, rel_tol=1e-10)
    assert math.isclose(got["c.x@2"], 30.0, rel_tol=1e-10)
    assert math.isclose(got["c.mass@2"], 200 - 4 * (10 + 100 / 20), rel_tol=1e-10)


@pytest.mark.parametrize("kind, clauses, end, line, words", [
    ("gain", "    duration 1 s", "", 6, "needs `rate"),
    ("gain", "    rate 2 kg/m\n    duration 1 s", "", 7, "mass rate"),
    ("gain", "    rate -2 kg/s\n    duration 1 s", "", 7, "written `lose`"),
    ("lose", "    rate 30 kg/s\n    velocity (0, 0)\n    duration 10 s", "", 6,
     "no mass would be left"),
    ("lose", "    rate 30 kg/s * (1 + t / (1 s))\n    duration 10 s", "", 6,
     "no mass would be left"),
    ("gain", "    rate 2 kg/s\n    velocity (5 m/s, 0)", ": c.vx = 6 m/s", 6,
     "never reached"),
    ("gain", "    rate 1 kg/m * c.vx\n    force (-100 N, 0)", ": c.x = 100 m", 6,
     "turns back"),
    ("gain", "    rate 2 kg/s\n    velocity (0, 0) relative", "", 6, "gives nothing"),
    ("gain", "    rate 2 kg/m * d.vx\n    duration 1 s", "", 7, "c's own state"),
])
def test_gain_errors_name_the_line(kind, clauses, end, line, words):
    text = GAIN.format(gravity="body d: particle(mass = 1 kg)", m0=200, vx=3, vy=0, end=end,
                       kind=kind, clauses=clauses, finds="c.vx@2")
    d = error_of(text)
    assert d.span.line == line and words in d.message, d.message


def test_a_closed_form_gain_does_not_import_scipy():
    import subprocess
    import sys

    code = ("import sys; sys.path.insert(0, 'tests'); from helpers import answers; "
            f"answers(open({str(EXAMPLES / 'flow_cart_loaded_sand.mom')!r}).read()); "
            "print('scipy' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         cwd=EXAMPLES.parent, check=True)
    assert out.stdout.strip() == "False"


def test_chain_falling_onto_a_scale_over_time():
    """The falling part sheds links at its own velocity, so it falls freely: after x has
    landed, v = sqrt(2 g x) at t = sqrt(2 x/g), and the scale reads 3 lambda g x."""
    lam, L, x, g = 0.5, 1.0, 0.8, 9.81
    got = ex("flow_chain_falls_onto_scale")
    assert math.isclose(got["chain.vy@2"], -math.sqrt(2 * g * x), rel_tol=1e-8)
    assert math.isclose(got["t@1->2"], math.sqrt(2 * x / g), rel_tol=1e-8)
    assert math.isclose(got["chain.mass@2"], lam * (L - x), rel_tol=1e-8)
    assert math.isclose(got["N"], 3 * lam * g * x, rel_tol=1e-8)
