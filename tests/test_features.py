"""Language features beyond the seeds, each against a closed form derived here."""
from __future__ import annotations

import math

from helpers import answers, solve_text

PINNED_ROD = """
body rod: rod(mass = 3 kg, length = 2 m)
body p: particle(mass = 0.5 kg)
point O = rod.end(+)
point H = rod at (-0.5 m, 0)
pin O to ground
state 1: rod.angle = -90 deg, rod at rest, p.v = (4 m/s, 0)
state 2
impact 1 -> 2:
    contact H with p normal (1, 0): restitution 0.5, smooth
{extra}
find rod.omega@2, p.vx@2
"""


def test_pinned_rod_struck_by_a_particle():
    # about the pin O: I_O = m L^2/3; the blow is d = 1.5 m from O.
    m, L, mp, v, e, d = 3.0, 2.0, 0.5, 4.0, 0.5, 1.5
    I_O = m * L * L / 3
    # restitution: -d w' - v' = e v ; angular momentum about O: -d mp v = -d mp v' + I_O w'
    w = (-e * v * d * mp - d * mp * v) / (I_O + mp * d * d)
    vp = -e * v - d * w
    got = answers(PINNED_ROD.format(extra=""))
    assert math.isclose(got["rod.omega@2"], w, rel_tol=1e-12)
    assert math.isclose(got["p.vx@2"], vp, rel_tol=1e-12)


def test_a_stated_principle_that_fails_is_named_with_its_reason():
    sol = solve_text(PINNED_ROD.format(extra="conserve momentum x of {rod, p} over 1 -> 2"))
    warn = [d for d in sol.diagnostics if d.code == "principle-does-not-hold"]
    assert warn and "pin O gives an external impulse" in warn[0].message


def test_a_stated_principle_that_holds_is_checked():
    text = PINNED_ROD.format(extra="conserve momentum y of {p} over 1 -> 2")
    sol = solve_text(text)
    assert any(c.status == "ok" and "stated" in c.name for c in sol.checks)


def test_spring_energy_launch():
    text = """
gravity 9.81 m/s^2 down
body b: particle(mass = 2 kg)
point P = ground at (0, 1 m)
spring s: b to P stiffness 800 N/m length 0.5 m
state 1: b.pos = (0, 0.8 m), b at rest
state 2: b.pos = (0, 0.5 m), b.vx = 0, b.vy < 0
energy 1 -> 2
find b.vy@2
"""
    m, k, g = 2.0, 800.0, 9.81
    T2 = 0.5 * k * 0.3**2 + m * g * 0.3  # spring returns to free length, block drops 0.3 m
    assert math.isclose(answers(text)["b.vy@2"], -math.sqrt(2 * T2 / m), rel_tol=1e-12)


def test_constant_force_and_moment_over_a_given_duration():
    text = """
body d: disk(mass = 4 kg, radius = 0.5 m)
point R = d at (0, 0.5 m)
state 1: d at rest, d.angle = 0
state 2
interval 1 -> 2:
    force (10 N, 0) on R
    moment 3 N*m on d
    duration 2 s
find d.vx@2, d.omega@2, d.dx@1->2
"""
    m, r, F, M, t = 4.0, 0.5, 10.0, 3.0, 2.0
    I = m * r * r / 2
    got = answers(text)
    assert math.isclose(got["d.vx@2"], F * t / m)
    assert math.isclose(got["d.omega@2"], (M - r * F) * t / I)  # F at the top turns it clockwise
    assert math.isclose(got["d.dx@1->2"], 0.5 * F / m * t * t)


WELDED = """
body r: rod(mass = 2 kg, length = 1 m)
body s: particle(mass = 1 kg)
body p: particle(mass = 0.2 kg)
point E = r.end(+)
point T = r.end(-)
weld s to E
state 1: r.angle = 0, r at rest, s at rest, p.v = (0, 10 m/s)
state 2
impact 1 -> 2:
    contact T with p normal (0, 1): restitution 1, smooth
find r.omega@2, p.vy@2
"""

COMPOSITE = """
body r: composite
    rod(mass = 2 kg, length = 1 m) at (0, 0)
    particle(mass = 1 kg) at (0.5 m, 0)
body p: particle(mass = 0.2 kg)
point T = r at (-0.5 m, 0)
state 1: r.angle = 0, r at rest, p.v = (0, 10 m/s)
state 2
impact 1 -> 2:
    contact T with p normal (0, 1): restitution 1, smooth
find r.omega@2, p.vy@2
"""


def test_a_weld_makes_one_rigid_body_as_a_composite_does():
    # closed form: free body M, I_G, blow at arm a (perpendicular) from G, e = 1
    M, mp, v = 3.0, 0.2, 10.0
    xg = 1.0 * 0.5 / M  # G of rod (0) + particle (0.5 m)
    I = 2.0 / 12 + 2.0 * xg**2 + 1.0 * (0.5 - xg) ** 2
    a = -0.5 - xg  # T's x from G
    k = 1 / M + a * a / I  # point mobility along y
    J = (1 + 1.0) * v / (k + 1 / mp)  # impulse on the body (up)
    want_w = a * J / I
    want_vp = v - J / mp
    for text in (WELDED, COMPOSITE):
        got = answers(text)
        assert math.isclose(got["r.omega@2"], want_w, rel_tol=1e-12), text
        assert math.isclose(got["p.vy@2"], want_vp, rel_tol=1e-12), text


def test_rolling_in_a_state_ties_speed_to_spin():
    text = """
surface floor normal (0, 1)
body d: disk(mass = 1 kg, radius = 0.2 m)
state 1: d.omega = -5 rad/s, d rolls on floor
find d.vx@1, d.vy@1
"""
    got = answers(text)
    assert math.isclose(got["d.vx@1"], 1.0) and got["d.vy@1"] == 0.0


def test_a_pin_from_a_state_joins_bodies_after_the_impact():
    text = """
gravity 9.81 m/s^2 down
body block: rigid(mass = 4 kg, inertia = 0.02 kg*m^2)
body bullet: particle(mass = 0.01 kg)
point O = block at (0, 1 m)
pin O to ground at (0, 1 m)
pin bullet to block from 2
state 1: block.angle = 0, block at rest, bullet.v = (400 m/s, 0)
state 2
state 3: block.omega = 0, block.angle > 0
impact 1 -> 2:
    contact block with bullet normal (1, 0): restitution 0, rough
energy 2 -> 3
find block.omega@2, block.angle@3
"""
    m, M, I, L, v, g = 0.01, 4.0, 0.02, 1.0, 400.0, 9.81
    I_O = I + (M + m) * L * L  # block about the pin, bullet at the block's centre
    w = m * v * L / I_O
    theta = math.acos(1 - 0.5 * I_O * w * w / ((M + m) * g * L))
    got = answers(text)
    assert math.isclose(got["block.omega@2"], w, rel_tol=1e-12)
    assert math.isclose(got["block.angle@3"], theta, rel_tol=1e-10)
