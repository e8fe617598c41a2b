"""Every example under examples/ solves to independently derived answers.

The expected numbers never come from the program's output: the seeds are checked
against the table "Numbers every solution must reproduce" in ../shared/DESIGN.md
(rounded there, so rel 1e-3) and against closed forms; the other examples against
closed forms derived here from the problem's own inputs (rel 1e-9). `answers()`
gives SI values, whatever unit a find line displays.
"""
from __future__ import annotations

import math
from pathlib import Path

import pytest
from helpers import answers

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"

# US customary units in SI (exact definitions)
FT = 0.3048
LBF = 4.4482216152605
FT_LB = FT * LBF

EXACT = 1e-9
DESIGN = 1e-3  # DESIGN.md's table is rounded to 3-4 significant figures


def got(name: str) -> dict[str, float]:
    return answers((EXAMPLES / f"{name}.mom").read_text(encoding="utf-8"))


def close(value: float, want: float, rel: float = EXACT, scale: float = 1.0) -> bool:
    """Relative closeness; a zero is compared against `scale` (the problem's size)."""
    return math.isclose(value, want, rel_tol=rel, abs_tol=rel * 1e-3 * scale)


def check(a: dict[str, float], want: dict[str, float], rel: float = EXACT,
          scale: float = 1.0) -> None:
    for key, w in want.items():
        assert key in a, f"{key} is not among the answers {sorted(a)}"
        assert close(a[key], w, rel, scale), f"{key}: got {a[key]!r}, expected {w!r}"


def dot(p, q):
    return p[0] * q[0] + p[1] * q[1]


def two_body_normal(m1, v1n, m2, v2n, e):
    """The formula sheet's central-impact velocities along the line of impact."""
    v1 = (m1 * v1n + m2 * v2n + e * m2 * (v2n - v1n)) / (m1 + m2)
    v2 = (m1 * v1n + m2 * v2n + e * m1 * (v1n - v2n)) / (m1 + m2)
    return v1, v2


# ---- seeds ---------------------------------------------------------------------------------------

def seed_billiards_elastic():
    a = got("seed_billiards_elastic")
    v = 5.0  # v_C1
    # DESIGN: v_C2 = v_C1/5 (rebounds), v_A2 = v_B2 = 2*sqrt(3)/5 * v_C1
    check(a, {"C.vx@2": -v / 5, "A.speed@2": 2 * math.sqrt(3) / 5 * v,
              "B.speed@2": 2 * math.sqrt(3) / 5 * v}, scale=v)
    # A leaves along its line of impact, 30 deg above C's path
    s = 2 * math.sqrt(3) / 5 * v
    check(a, {"A.vx@2": s * math.cos(math.radians(30)),
              "A.vy@2": s * math.sin(math.radians(30)), "T_lost@1->2": 0.0},
          scale=0.5 * 0.17 * v * v)


def seed_billiards_find_e():
    a = got("seed_billiards_find_e")
    check(a, {"e": 2 / 3}, DESIGN)
    check(a, {"e": 2 / 3})
    # C stops: its momentum m v goes to A and B along +-30 deg: 2 m v_A cos 30 = m v
    v = 2.0
    vA = v / (2 * math.cos(math.radians(30)))
    check(a, {"A.speed@2": vA, "B.speed@2": vA})


def seed_disk_wall():
    a = got("seed_disk_wall")
    check(a, {"t@1->2": 3.048, "disk.dtheta@1->2": -91.44, "alpha": 19.68}, DESIGN)
    # closed form: the strut (at 30 deg to the wall) pushes along itself; the wall's
    # normal force N and friction mu N (upwards: the rim slips down) balance it:
    #   x: S sin 30 = N;  y: S cos 30 + mu N = m g  =>  N = m g / (mu + cot 30)
    m, r, g, mu, w0 = 20.0, 0.150, 10.0, 0.3, 60.0
    I = m * r * r / 2
    N = m * g / (mu + 1 / math.tan(math.radians(30)))
    alpha = mu * N * r / I
    t = w0 / alpha
    check(a, {"t@1->2": t, "alpha": alpha, "disk.dtheta@1->2": -w0 * t / 2,
              "J_n[disk]@1->2": N * t})


def seed_oblique_particles():
    a = got("seed_oblique_particles")
    m1, m2, e = 2.0, 3.0, 0.8
    n = (math.cos(math.radians(20)), math.sin(math.radians(20)))
    tg = (-n[1], n[0])
    u1, u2 = (4.0, 1.0), (-2.0, 0.5)
    v1n, v2n = two_body_normal(m1, dot(u1, n), m2, dot(u2, n), e)
    v1t, v2t = dot(u1, tg), dot(u2, tg)  # tangential components unchanged
    v1 = (v1n * n[0] + v1t * tg[0], v1n * n[1] + v1t * tg[1])
    v2 = (v2n * n[0] + v2t * tg[0], v2n * n[1] + v2t * tg[1])
    lost = 0.5 * m1 * m2 / (m1 + m2) * (1 - e * e) * (dot(u1, n) - dot(u2, n)) ** 2
    check(a, {"p1.vx@2": v1[0], "p1.vy@2": v1[1], "p2.vx@2": v2[0], "p2.vy@2": v2[1],
              "v1n": v1n, "v2n": v2n, "T_lost@1->2": lost})


def seed_pendulum_wall():
    a = got("seed_pendulum_wall")
    e = 0.6
    # DESIGN: rebounds to 39.79 deg (below) the horizontal, sin(theta) = 1 - e^2
    check(a, {"pendulum.angle@4": -math.radians(39.79)}, DESIGN)
    check(a, {"pendulum.angle@4": -math.asin(1 - e * e)})
    # energy from horizontal to hanging, about the fixed pivot O; the wall reverses
    # the ball's centre (2 m from O) with e, so omega3 = -e omega2
    g, mr, L, mb, rb = 9.81, 4.0, 2.0, 10.0, 0.3
    I_O = mr * L * L / 3 + mb * (0.4 * rb * rb + L * L)
    w2 = -math.sqrt(2 * g * (mr * L / 2 + mb * L) / I_O)
    check(a, {"pendulum.omega@2": w2, "pendulum.omega@3": -e * w2,
              "T_lost@2->3": 0.5 * I_O * w2 * w2 * (1 - e * e)})


def seed_plastic_collision():
    a = got("seed_plastic_collision")
    mA, mB = 2.0, 3.0
    uA, uB = (3.0, 0.0), (0.0, 2.0)
    # common velocity = total momentum / total mass
    vc = ((mA * uA[0] + mB * uB[0]) / (mA + mB), (mA * uA[1] + mB * uB[1]) / (mA + mB))
    T1 = 0.5 * mA * (uA[0] ** 2 + uA[1] ** 2) + 0.5 * mB * (uB[0] ** 2 + uB[1] ** 2)
    T2 = 0.5 * (mA + mB) * (vc[0] ** 2 + vc[1] ** 2)
    check(a, {"A.vx@2": vc[0], "A.vy@2": vc[1], "B.vx@2": vc[0], "B.vy@2": vc[1],
              "T_lost@1->2": T1 - T2})


def seed_rod_disk_bearing():
    a = got("seed_rod_disk_bearing")
    check(a, {"rod.omega@2": 0.0708}, DESIGN)
    # angular momentum of rod + disk about the fixed pin B is conserved; at the end the
    # disk turns with the rod. US units (slug, ft): I's scale out of omega.
    g = 32.2
    mr, L, md, r, wd = 5 / g, 3.0, 3 / g, 0.5, 8.0
    Id = md * r * r / 2
    w = Id * wd / (mr * L * L / 3 + md * L * L + Id)
    check(a, {"rod.omega@2": w})


def _rod_drop():
    m, L, g, h = 10.0, 1.0, 9.81, 1.0
    c, s = math.cos(math.radians(30)), math.sin(math.radians(30))
    v0 = math.sqrt(2 * g * h)
    I = m * L * L / 12
    return m, L, c, s, v0, I


def seed_rod_drop_rough():
    a = got("seed_rod_drop_rough")
    check(a, {"rod.omega@3": -5.754}, DESIGN)
    m, L, c, s, v0, I = _rod_drop()
    # plastic and no slip: A stops; angular momentum about A is conserved:
    #   m (r_G/A x v) = I_A w, r_G/A = (L/2)(cos 30, sin 30), v = (0, -v0)
    w = -m * (L / 2) * c * v0 / (m * L * L / 3)
    vx, vy = -w * (L / 2) * s, w * (L / 2) * c  # v_G = w k x r_G/A
    T2 = 0.5 * m * (vx * vx + vy * vy) + 0.5 * I * w * w
    check(a, {"rod.omega@3": w, "rod.vx@3": vx, "rod.vy@3": vy,
              "J_n[A]@2->3": m * (vy + v0), "J_t[A]@2->3": -m * vx,  # tangent is (-1, 0)
              "T_lost@2->3": 0.5 * m * v0 * v0 - T2})


def seed_rod_drop_smooth():
    a = got("seed_rod_drop_smooth")
    check(a, {"rod.omega@3": -14.16}, DESIGN)
    m, L, c, _s, v0, I = _rod_drop()
    e = 1.0
    # vertical impulse J at A, arm (L/2) cos 30 clockwise; Newton at A:
    #   J = (1 + e) v0 / (1/m + (L/2 cos 30)^2 / I)
    d = (L / 2) * c
    J = (1 + e) * v0 / (1 / m + d * d / I)
    check(a, {"rod.omega@3": -d * J / I, "rod.vx@3": 0.0, "rod.vy@3": -v0 + J / m,
              "J_n[A]@2->3": J, "T_lost@2->3": 0.0}, scale=0.5 * m * v0 * v0)


# ---- new examples ----------------------------------------------------------------------------------

def rod_struck_by_particle():
    a = got("rod_struck_by_particle")
    M, L, m, v0, d, e = 4.0, 1.2, 0.5, 10.0, 0.4, 0.5
    I = M * L * L / 12
    # impulse J on the rod (+y) at d from G, -J on the puck; Newton at the contact:
    #   (v_G + w d) - v_p = e v0  =>  J = (1 + e) v0 / (1/m + 1/M + d^2/I)
    J = (1 + e) * v0 / (1 / m + 1 / M + d * d / I)
    vG, w, vp = J / M, J * d / I, v0 - J / m
    T2 = 0.5 * M * vG * vG + 0.5 * I * w * w + 0.5 * m * vp * vp
    check(a, {"rod.vy@2": vG, "rod.omega@2": w, "puck.vy@2": vp, "J_n[hit]@1->2": J,
              "vA": vG - w * L / 2, "vB": vG + w * L / 2, "T_lost@1->2": 0.5 * m * v0 * v0 - T2})


def ballistic_pendulum():
    a = got("ballistic_pendulum")
    g, L, mr, mb, w, h, m, v0 = 9.81, 1.5, 2.0, 6.0, 0.2, 0.2, 0.030, 500.0
    # moments of inertia about the pin O: rod m L^2/3, block (plate) by parallel axes
    I_O = mr * L * L / 3 + mb * (w * w + h * h) / 12 + mb * L * L
    # angular momentum about O is conserved (the pin's impulse has no moment about O)
    w2 = m * v0 * L / (I_O + m * L * L)
    # energy: (1/2)(I_O + m L^2) w^2 = (mr L/2 + mb L + m L) g (1 - cos theta)
    T2 = 0.5 * (I_O + m * L * L) * w2 * w2
    theta = math.acos(1 - T2 / ((mr * L / 2 + mb * L + m * L) * g))
    # the pin's horizontal impulse: linear momentum of pendulum + bullet in x
    p_after = (mr * L / 2 + mb * L + m * L) * w2
    check(a, {"pendulum.omega@2": w2, "bullet.vx@2": w2 * L,
              "T_lost@1->2": 0.5 * m * v0 * v0 - T2, "swing": theta,
              "Jx[O]@1->2": p_after - m * v0})


def _pendulum_joined_in_impact(name: str):
    a = got(name)
    g, m, M, v0 = 9.81, 0.010, 2.0, 400.0
    v = m * v0 / (m + M)  # momentum in x: the wires give no horizontal impulse
    check(a, {"block.vx@2": v, "bullet.vx@2": v, "rise": v * v / (2 * g),  # energy
              "T_lost@1->2": 0.5 * m * v0 * v0 - 0.5 * (m + M) * v * v})


def ballistic_pendulum_pin_from_impact():
    _pendulum_joined_in_impact("ballistic_pendulum_pin_from_impact")


def ballistic_pendulum_pin_from_impact_rough():
    _pendulum_joined_in_impact("ballistic_pendulum_pin_from_impact_rough")


def disk_slide_then_roll():
    a = got("disk_slide_then_roll")
    m, r, v0, mu, g = 5.0, 0.25, 6.0, 0.2, 9.81
    vf = 2 * v0 / 3
    t = v0 / (3 * mu * g)
    T_end = 0.5 * m * vf * vf + 0.5 * (m * r * r / 2) * (vf / r) ** 2
    check(a, {"wheel.vx@2": vf, "wheel.omega@2": -vf / r, "t@1->2": t,
              "wheel.dx@1->2": (v0 + vf) / 2 * t,
              "J_t[wheel]@1->2": mu * m * g * t,  # along the tangent (-1, 0): backwards
              "T_lost@1->2": 0.5 * m * v0 * v0 - T_end})


def _particle_on_rough_wall(m, speed, beta_deg, e, mu):
    """Particle hits the wall with normal (-1, 0) (tangent (0, -1)); Coulomb friction."""
    b = math.radians(beta_deg)
    vn, vt = -speed * math.cos(b), speed * math.sin(b)  # along n = (-1, 0), t = (0, -1)
    Jn = m * (1 + e) * -vn
    Jt = -m * vt  # stick: the tangential velocity is stopped
    stick = abs(Jt) <= mu * Jn
    if not stick:
        Jt = -math.copysign(mu * Jn, vt)
    vn2, vt2 = -e * vn, vt + Jt / m
    vx, vy = -vn2, -vt2  # back to x, y
    lost = 0.5 * m * speed * speed - 0.5 * m * (vx * vx + vy * vy)
    return stick, vx, vy, Jn, Jt, lost


def wall_oblique_stick():
    a = got("wall_oblique_stick")
    stick, vx, vy, Jn, Jt, lost = _particle_on_rough_wall(0.2, 8.0, 20.0, 0.6, 0.3)
    assert stick  # the premise of this example
    check(a, {"ball.vx@2": vx, "ball.vy@2": vy, "J_n[ball]@1->2": Jn, "J_t[ball]@1->2": Jt,
              "ratio": Jt / Jn, "T_lost@1->2": lost}, scale=8.0)


def wall_oblique_slide():
    a = got("wall_oblique_slide")
    stick, vx, vy, Jn, Jt, lost = _particle_on_rough_wall(0.2, 8.0, 60.0, 0.6, 0.3)
    assert not stick  # the premise of this example
    check(a, {"ball.vx@2": vx, "ball.vy@2": vy, "J_n[ball]@1->2": Jn, "J_t[ball]@1->2": Jt,
              "ratio": -0.3, "rebound": math.atan(vy / vx), "T_lost@1->2": lost})


def us_rod_center_of_percussion():
    a = got("us_rod_center_of_percussion")
    # in US units: slugs, ft, ft/s, lb*s
    g = 32.2
    mb, L, m, v0, d, e = 6 / g, 3.0, 0.5 / g, 40.0, 2.0, 0.5
    I_O = mb * L * L / 3
    # angular momentum about O and Newton at the contact (the bar's point moves at w d):
    #   m v0 d = I_O w + m v d,  w d - v = e v0
    w = m * d * v0 * (1 + e) / (I_O + m * d * d)
    v = w * d - e * v0
    J = m * (v0 - v)
    lost = 0.5 * m * v0 * v0 - 0.5 * I_O * w * w - 0.5 * m * v * v
    assert math.isclose(w, 3.0, rel_tol=1e-12) and math.isclose(v, -14.0, rel_tol=1e-12)
    # the bar is struck at 2L/3, its centre of percussion: the pin gives no impulse
    # (horizontal: J - m_bar w L/2 = 0)
    assert math.isclose(d, 2 * L / 3)
    check(a, {"bar.omega@2": w, "ball.vx@2": v * FT, "vP": w * d * FT, "J_n[hit]@1->2": J * LBF,
              "Jx[O]@1->2": 0.0, "Jy[O]@1->2": 0.0, "T_lost@1->2": lost * FT_LB}, scale=J * LBF)


def us_railcars_couple():
    a = got("us_railcars_couple")
    # US units: two cars couple, momentum along the track conserved
    g, WA, WB, vA = 32.2, 30000.0, 20000.0, 4.0
    v = WA * vA / (WA + WB)
    J = WB / g * v
    lost = WA * vA**2 / (2 * g) - (WA + WB) * v**2 / (2 * g)
    check(a, {"A.vx@2": v * FT, "B.vx@2": v * FT, "J_n[A-B]@1->2": J * LBF,
              "T_lost@1->2": lost * FT_LB}, scale=J * LBF)


def newtons_cradle_sequence():
    a = got("newtons_cradle_sequence")
    m, v0, e = 0.1, 2.0, 1.0
    v = [v0, 0.0, 0.0, 0.0, 0.0]
    for k in range(4):  # A on B, B on C, C on D, D on E
        v[k], v[k + 1] = two_body_normal(m, v[k], m, v[k + 1], e)
    assert v == [0.0, 0.0, 0.0, 0.0, v0]  # e = 1: the last ball leaves with the first's speed
    check(a, {f"{n}.vx@5": x for n, x in zip("ABCDE", v)}, scale=v0)
    T = 0.5 * m * v0 * v0
    check(a, {"T@1": T, "T@5": T, "T_lost@1->2": 0.0}, scale=T)


def newtons_cradle_simultaneous():
    a = got("newtons_cradle_simultaneous")
    mA = mB = mC = 0.1
    v, e = 2.0, 1.0
    # one impact, Newton's law at both contacts: B-C were touching (no approach), so
    # they separate at e*0 = 0 and leave together; at A-B, vB' - vA' = e v; momentum:
    #   mA vA' + (mB + mC) vB' = mA v  =>  vB' = mA v (1 + e) / (mA + mB + mC)
    vB = mA * v * (1 + e) / (mA + mB + mC)
    vA = vB - e * v
    assert math.isclose(vA, -v / 3) and math.isclose(vB, 2 * v / 3)  # equal balls, e = 1
    lost = 0.5 * mA * v * v - 0.5 * mA * vA * vA - 0.5 * (mB + mC) * vB * vB
    check(a, {"A.vx@2": vA, "B.vx@2": vB, "C.vx@2": vB, "J_n[AB]@1->2": mA * (v - vA),
              "J_n[BC]@1->2": mC * vB, "T_lost@1->2": lost}, scale=0.5 * mA * v * v)


def ball_bounce_rebound():
    a = got("ball_bounce_rebound")
    m, g, h, e = 0.06, 9.81, 2.0, 0.8
    v = math.sqrt(2 * g * h)
    check(a, {"ball.vy@2": -v, "ball.vy@3": e * v, "J_n[ball]@2->3": m * (1 + e) * v,
              "T_lost@2->3": 0.5 * m * v * v * (1 - e * e), "rebound": e * e * h})


def bounce_find_e():
    a = got("bounce_find_e")
    m, g, h1, h2 = 0.057, 9.81, 2.5, 1.4
    v2, v3 = math.sqrt(2 * g * h1), math.sqrt(2 * g * h2)
    check(a, {"e[floor]": math.sqrt(h2 / h1), "ball.vy@2": -v2, "ball.vy@3": v3,
              "T_lost@2->3": 0.5 * m * (v2 * v2 - v3 * v3)})


def sphere_backspin_returns():
    a = got("sphere_backspin_returns")
    m, r, v0, w0, mu, g = 1.5, 0.1, 2.0, 60.0, 0.25, 9.81
    I = 0.4 * m * r * r
    # angular momentum about the contact point: I w - m r v is conserved; w = -v/r at the end
    v = (m * r * v0 - I * w0) / (I / r + m * r)
    w = -v / r
    t = (v0 - v) / (mu * g)  # the centre decelerates at mu g throughout
    T1 = 0.5 * m * v0 * v0 + 0.5 * I * w0 * w0
    T2 = 0.5 * m * v * v + 0.5 * I * w * w
    assert v < 0  # it comes back
    check(a, {"ball.vx@2": v, "ball.omega@2": w, "t@1->2": t, "ball.dx@1->2": (v0 + v) / 2 * t,
              "ball.dtheta@1->2": (w0 + w) / 2 * t, "T_lost@1->2": T1 - T2})


def sphere_rough_bounce():
    a = got("sphere_rough_bounce")
    m, r, speed, e, mu = 0.2, 0.05, 10.0, 0.7, 0.5
    I = 0.4 * m * r * r
    vx, vy, w = speed * math.cos(math.radians(45)), -speed * math.sin(math.radians(45)), 0.0
    Jn = m * (1 + e) * -vy
    # horizontal friction impulse F at the rim (arm (0, -r)): stick stops the rim's slip
    slip = vx + w * r
    F = -slip / (1 / m + r * r / I)
    assert abs(F) <= mu * Jn  # the premise: it sticks
    vx2, w2 = vx + F / m, w + r * F / I
    assert math.isclose(vx2, 5 / 7 * vx)
    T2 = 0.5 * m * (vx2 * vx2 + e * e * vy * vy) + 0.5 * I * w2 * w2
    check(a, {"ball.vx@2": vx2, "ball.vy@2": -e * vy, "ball.omega@2": w2,
              "J_n[ball]@1->2": Jn, "J_t[ball]@1->2": -F,  # the tangent is (-1, 0)
              "T_lost@1->2": 0.5 * m * speed * speed - T2})


def crate_pushed_force():
    a = got("crate_pushed_force")
    m, g, P, th, mu, t1 = 40.0, 9.81, 250.0, math.radians(20), 0.3, 3.0
    N = m * g + P * math.sin(th)
    v2 = (P * math.cos(th) - mu * N) * t1 / m
    t2 = v2 / (mu * g)
    check(a, {"crate.vx@2": v2, "J_n[crate]@1->2": N * t1, "J_t[crate]@1->2": mu * N * t1,
              "t@2->3": t2, "crate.dx@1->2": v2 / 2 * t1, "crate.dx@2->3": v2 / 2 * t2})


def flywheel_torque():
    a = got("flywheel_torque")
    m, r, M, t = 20.0, 0.3, 12.0, 5.0
    I = m * r * r / 2
    w = M * t / I
    check(a, {"wheel.omega@2": w, "turns": w * t / 2, "alpha": M / I})


def spring_launch_collision():
    a = got("spring_launch_collision")
    mA, mB, k, e = 0.5, 1.5, 800.0, 0.4
    v = math.sqrt(k / mA) * (0.3 - 0.2)  # (1/2) k x^2 = (1/2) m v^2
    vA, vB = two_body_normal(mA, v, mB, 0.0, e)
    lost = 0.5 * mA * v * v - 0.5 * mA * vA * vA - 0.5 * mB * vB * vB
    check(a, {"A.vx@2": v, "A.vx@3": vA, "B.vx@3": vB, "T_lost@2->3": lost})


def disk_rolls_down_ramp():
    a = got("disk_rolls_down_ramp")
    g, h, r, slope = 9.81, 1.0, 0.1, math.radians(30)
    v = math.sqrt(4 * g * h / 3)  # m g h = (1/2) m v^2 + (1/2)(m r^2/2)(v/r)^2
    check(a, {"wheel.vx@2": v * math.cos(slope), "wheel.vy@2": -v * math.sin(slope),
              "wheel.speed@2": v, "wheel.omega@2": -v / r})


def disk_climbs_curb():
    a = got("disk_climbs_curb")
    m, r, h, g = 4.0, 0.25, 0.1, 9.81
    I_G = m * r * r / 2
    I_C = I_G + m * r * r
    # after the plastic rough impact the disk pivots about C; it just reaches the top:
    #   (1/2) I_C w2^2 = m g h
    w2 = -math.sqrt(2 * m * g * h / I_C)
    # angular momentum about C, rolling before (w1 = -v/r), r_G/C = (-0.2, r - h):
    #   I_G (-v/r) - m (r - h) v = I_C w2
    v = -I_C * w2 / (I_G / r + m * (r - h))
    T1 = 0.5 * m * v * v + 0.5 * I_G * (v / r) ** 2
    check(a, {"v_min": v, "wheel.omega@2": w2, "lost": 1 - m * g * h / T1})


def joint_forms_in_impact():
    a = got("joint_forms_in_impact")
    m1, m2, v1 = 1.0, 3.0, 4.0
    v = m1 * v1 / (m1 + m2)  # momentum conserved: the latched pair moves together
    check(a, {"a.vx@2": v, "b.vx@2": v, "Jx[latch]@1->2": m1 * (v - v1),
              "T_lost@1->2": 0.5 * m1 * v1 * v1 - 0.5 * (m1 + m2) * v * v})


def weld_forms_in_impact():
    a = got("weld_forms_in_impact")
    M, L, m, r, v0 = 3.0, 1.0, 1.0, 0.1, 4.0
    xc = m * (L / 2) / (M + m)  # the welded pair's centre of mass, on the rod's axis
    vc = m * v0 / (M + m)  # linear momentum conserved
    I = M * L * L / 12 + M * xc ** 2 + m * r * r / 2 + m * (L / 2 - xc) ** 2
    w = m * (L / 2 - xc) * v0 / I  # angular momentum about the pair's centre conserved
    T2 = 0.5 * (M + m) * vc * vc + 0.5 * I * w * w
    check(a, {"rod.omega@2": w, "disk.omega@2": w, "rod.vy@2": vc - w * xc,
              "disk.vy@2": vc + w * (L / 2 - xc),
              "M[glue]@1->2": m * r * r / 2 * w,  # the weld's moment alone turns the disk
              "T_lost@1->2": 0.5 * m * v0 * v0 - T2})


def _rod_rough_floor(law: str) -> None:
    """The slender rod striking a rough floor under each impact law: the closed forms
    are derived in test_impact_laws.py (Stronge's impulse path, by hand)."""
    from test_impact_laws import rod_floor_expected

    check(got(f"rod_rough_floor_{law}"), rod_floor_expected(law))


def rod_rough_floor_newton():
    _rod_rough_floor("newton")


def rod_rough_floor_poisson():
    _rod_rough_floor("poisson")


def rod_rough_floor_energetic():
    _rod_rough_floor("energetic")


def _crash(a, vA_kmh, vB_kmh, mA=1500.0, mB=1000.0, mu=0.7, g=9.81):
    """Two cars lock (momentum), the wreck skids to rest: t = V/(mu g), v^2 = 2 mu g d."""
    vA, vB = vA_kmh / 3.6, vB_kmh / 3.6
    Vx, Vy = mA * vA / (mA + mB), mB * vB / (mA + mB)
    V = math.hypot(Vx, Vy)
    check(a, {"A.vx@2": Vx, "A.vy@2": Vy, "wreck_speed": V, "t@2->3": V / (mu * g),
              "d": V * V / (2 * mu * g)})


def crash_cars_lock_skid():
    _crash(got("crash_cars_lock_skid"), 50, 30)


def rod_pinned_struck_energy():
    """e = 1 on a pinned rod: effective mass I_O/d^2 at the struck point."""
    a = got("rod_pinned_struck_energy")
    m, M, L, d, u = 0.5, 4.0, 1.2, 0.9, 6.0
    mP = M * L * L / 3 / d**2
    check(a, {"ball.vx@2": (m - mP) / (m + mP) * u, "rod.omega@2": 2 * m * u / ((m + mP) * d),
              "J_n[hit]@1->2": 2 * m * mP / (m + mP) * u})


def find_e_no_energy_lost():
    a = got("find_e_no_energy_lost")
    ma, mb, u = 2.0, 3.0, 5.0
    check(a, {"e[hit]": 1.0, "a.vx@2": (ma - mb) / (ma + mb) * u, "b.vx@2": 2 * ma * u / (ma + mb),
              "J_n[hit]@1->2": 2 * ma * mb / (ma + mb) * u})


CHECKS = {f.__name__: f for f in [
    crash_cars_lock_skid, rod_pinned_struck_energy, find_e_no_energy_lost,
    seed_billiards_elastic, seed_billiards_find_e, seed_disk_wall, seed_oblique_particles,
    seed_pendulum_wall, seed_plastic_collision, seed_rod_disk_bearing, seed_rod_drop_rough,
    seed_rod_drop_smooth,
    rod_struck_by_particle, ballistic_pendulum, ballistic_pendulum_pin_from_impact,
    ballistic_pendulum_pin_from_impact_rough, disk_slide_then_roll, wall_oblique_stick,
    wall_oblique_slide, us_rod_center_of_percussion, us_railcars_couple,
    newtons_cradle_sequence,
    newtons_cradle_simultaneous, ball_bounce_rebound, bounce_find_e, sphere_backspin_returns,
    sphere_rough_bounce, crate_pushed_force, flywheel_torque, spring_launch_collision,
    disk_rolls_down_ramp, disk_climbs_curb, joint_forms_in_impact, weld_forms_in_impact,
    rod_rough_floor_newton, rod_rough_floor_poisson, rod_rough_floor_energetic,
]}

from test_language_items import CHECKS as LANGUAGE_CHECKS  # noqa: E402 (issue 10's items)

CHECKS.update(LANGUAGE_CHECKS)
# the examples of the language items (issue 10), checked in test_language_items.py
from test_language_elements import EXAMPLE_CHECKS  # noqa: E402

CHECKS.update(EXAMPLE_CHECKS)
from test_loops import EXAMPLE_CHECKS as LOOP_CHECKS  # noqa: E402 (issue 10, item 10)

CHECKS.update(LOOP_CHECKS)

# the open-system examples (flow_*) are checked against their closed forms in test_flows.py
PROBLEMS = sorted(p.stem for p in EXAMPLES.glob("*.mom") if not p.stem.startswith("flow_"))

@pytest.mark.parametrize("name", PROBLEMS)
def test_example_answers(name):
    assert name in CHECKS, f"examples/{name}.mom has no independent check in {__file__}"
    CHECKS[name]()


def test_every_check_has_its_example():
    assert sorted(CHECKS) == PROBLEMS


# ---- variants of the examples: the other friction regime, the other direction ------------------

def test_sphere_rough_bounce_slides_with_little_friction():
    text = (EXAMPLES / "sphere_rough_bounce.mom").read_text(encoding="utf-8")
    a = answers(text.replace("friction 0.5", "friction 0.1"))
    m, r, speed, e, mu = 0.2, 0.05, 10.0, 0.7, 0.1
    I = 0.4 * m * r * r
    vx, vy = speed * math.cos(math.radians(45)), -speed * math.sin(math.radians(45))
    Jn = m * (1 + e) * -vy
    assert (2 / 7) * vx * m > mu * Jn  # sticking would need more friction than mu allows
    F = -mu * Jn  # sliding: against the rim's forward slip throughout
    check(a, {"ball.vx@2": vx + F / m, "ball.vy@2": -e * vy, "ball.omega@2": r * F / I,
              "J_n[ball]@1->2": Jn, "J_t[ball]@1->2": -F})


SECOND_INTERVAL = """\
problem "second interval: the slip direction comes from an unknown velocity"
gravity 10 m/s^2 down
body b: particle(mass = 1 kg)
surface floor normal (0, 1)
state 1: b.v = ({v0}, 0)
state 2
state 3
interval 1 -> 2:
    contact b with floor: friction 0.1
    duration 1 s
interval 2 -> 3:
    contact b with floor: friction 0.1
    b stops
find b.vx@2, t@2->3
"""


def test_second_interval_slides_to_the_left():
    # v0 = -6 m/s: after 1 s at mu g = 1 m/s^2 it moves at -5 m/s and stops 5 s later
    a = answers(SECOND_INTERVAL.format(v0="-6 m/s"))
    check(a, {"b.vx@2": -5.0, "t@2->3": 5.0})


def test_second_interval_slides_to_the_right():
    a = answers(SECOND_INTERVAL.format(v0="6 m/s"))
    check(a, {"b.vx@2": 5.0, "t@2->3": 5.0})
