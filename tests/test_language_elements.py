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



# ---- item 8: normals from geometry ---------------------------------------------------------
def test_two_pucks_take_the_line_of_centres():
    m, v, e, phi = 0.17, 5.0, 0.9, math.radians(30)
    n = (math.cos(phi), math.sin(phi))  # from A's centre to B's
    vn = v * n[0]  # equal masses, B at rest: the normal parts exchange with restitution
    vb, va_n = (1 + e) / 2 * vn, (1 - e) / 2 * vn
    got = answers(_file("pucks_line_of_centres.mom"))
    va = (v - vn * n[0] + va_n * n[0], -vn * n[1] + va_n * n[1])
    for k, want in {"B.vx@2": vb * n[0], "B.vy@2": vb * n[1], "A.vx@2": va[0],
                    "A.vy@2": va[1]}.items():
        assert math.isclose(got[k], want, rel_tol=1e-12), k
    assert m > 0


ROD_ON_DISK = """
body rod: rod(mass = 2 kg, length = 1 m)
body ball: disk(mass = 0.5 kg, radius = 0.1 m)
state 1:
    rod.pos = (0, 0), rod.angle = 0, rod.v = (0, -3 m/s), rod.omega = 0
    ball.pos = (0.5 m, -0.1 m), ball at rest
state 2
impact 1 -> 2:
    contact rod.end(+) with ball: restitution 0.5, smooth
find ball.vy@2, rod.omega@2
"""


def test_a_rod_end_on_a_round_body_takes_the_normal_through_its_centre():
    m, L, M, v, e = 2.0, 1.0, 0.5, 3.0, 0.5
    w_eff = 1 / m + (L / 2) ** 2 / (m * L * L / 12) + 1 / M  # the end's and ball's compliance
    J = (1 + e) * v / w_eff  # along the vertical line through the ball's centre
    got = answers(ROD_ON_DISK)
    assert math.isclose(got["ball.vy@2"], -J / M, rel_tol=1e-12)
    assert math.isclose(got["rod.omega@2"], J * (L / 2) / (m * L * L / 12), rel_tol=1e-12)


def test_where_the_geometry_fixes_no_normal_the_error_says_so():
    d = error_of(ROD_ON_DISK.replace("ball: disk(mass = 0.5 kg, radius = 0.1 m)",
                                     "ball: rod(mass = 0.5 kg, length = 0.2 m)")
                 .replace("with ball:", "with ball.end(-):"))
    assert "geometry fixes none" in d.message and d.span.line == 9
    d = error_of(ROD_ON_DISK.replace("rod.angle = 0, ", ""))
    assert "needs rod.angle in state 1" in d.message and d.span.line == 9



# ---- item 9: particles that turn together -----------------------------------------------------
def test_two_skaters_grabbing_a_pole_spin_about_their_centre():
    mA, mB, L, vAx, vAy = 60.0, 80.0, 2.0, 4.0, -1.0
    vy = mA * vAy / (mA + mB)  # along the pole: a plastic impact of the two masses
    mu = mA * mB / (mA + mB)
    got = answers(_file("skaters_grab_pole.mom"))
    for k, want in {"pole.omega@2": -vAx / L,  # across the pole: untouched, so they turn
                    "A.vx@2": vAx, "A.vy@2": vy, "B.vy@2": vy,
                    "J[pole]@1->2": mA * (vy - vAy),
                    "T_lost@1->2": 0.5 * mu * vAy ** 2}.items():
        assert math.isclose(got[k], want, rel_tol=1e-12), k


PARTICLES_JOIN = """
body a: particle(mass = 2 kg)
body b: particle(mass = 3 kg)
weld j: a to b from 2
state 1: a.v = (5 m/s, -1 m/s), b.v = (-2 m/s, 4 m/s){where}
state 2
impact 1 -> 2
find a.vx@2, a.vy@2, b.vx@2, b.vy@2, Jx[j]@1->2, Jy[j]@1->2
"""


def test_two_particles_welded_at_one_point_join_plastically():
    """No distance between them (none given, or the same point): one velocity, the
    total momentum over the total mass, and a two-component impulse (no line for it)."""
    ma, mb, va, vb = 2.0, 3.0, (5.0, -1.0), (-2.0, 4.0)
    v = [(ma * va[k] + mb * vb[k]) / (ma + mb) for k in range(2)]
    for where in ("", ", a.pos = (1 m, 2 m), b.pos = (1 m, 2 m)"):
        got = answers(PARTICLES_JOIN.format(where=where))
        for k, axis in enumerate("xy"):
            assert math.isclose(got[f"a.v{axis}@2"], v[k], rel_tol=1e-12), where
            assert math.isclose(got[f"b.v{axis}@2"], v[k], rel_tol=1e-12), where
            # the impulse on a (from b) is a's change of momentum
            assert math.isclose(got[f"J{axis}[j]@1->2"], ma * (v[k] - va[k]),
                                rel_tol=1e-12), where


def test_two_particles_welded_apart_take_an_impulse_along_their_line():
    d = error_of(PARTICLES_JOIN.format(where=", a.pos = (0, 1 m), b.pos = (0, -1 m)"))
    assert "unknown quantity 'Jx[j]@1->2'" in d.message and "J[j]@1->2" in d.message


def test_a_rigid_body_with_no_inertia_is_a_point_mass():
    got = answers("""
body a: rigid(mass = 2 kg, inertia = 0)
state 1: a.v = (1 m/s, 0)
state 2
interval 1 -> 2:
    force (1 N, 0) on a
    duration 1 s
find a.vx@2
""")
    assert math.isclose(got["a.vx@2"], 1.5, rel_tol=1e-12)



# ---- item 3: a collar on a slider ----------------------------------------------------------------
def test_a_collar_sliding_out_conserves_angular_momentum_and_energy_then_strikes_the_stop():
    M, L, m, r1, w1 = 4.0, 1.2, 1.5, 0.2, 6.0
    I_O = M * L * L / 3
    w2 = (I_O + m * r1 ** 2) * w1 / (I_O + m * L ** 2)  # angular momentum about the axle
    T1 = 0.5 * (I_O + m * r1 ** 2) * w1 ** 2
    vr = math.sqrt((2 * T1 - (I_O + m * L ** 2) * w2 ** 2) / m)  # energy: the rest is radial
    got = answers(_file("collar_slides_on_spinning_rod.mom"))
    # the stop's impulse acts along the rod, through the axle: the spin is unchanged and
    # the collar's radial energy is lost
    for k, want in {"rod.omega@2": w2, "collar.vx@2": vr, "rod.omega@3": w2,
                    "T_lost@2->3": 0.5 * m * vr ** 2}.items():
        assert math.isclose(got[k], want, rel_tol=1e-12), k
    assert abs(got["collar.vx@3"]) < 1e-12


def test_a_slider_pushed_across_moves_the_rod_and_not_along():
    # a free rod (no pin) and a collar at its centre: a blow across the rod on the collar
    # moves both together; a blow along it moves the collar alone
    text = """
body rod: rod(mass = 3 kg, length = 1 m)
body collar: particle(mass = 1 kg)
slider collar on rod along (1, 0)
state 1: rod.angle = 0, rod.pos = (0, 0), rod at rest, collar.pos = (0, 0), collar at rest
state 2
interval 1 -> 2:
    force (2 N, 4 N) on collar
    duration 1 s
find collar.vx@2, collar.vy@2, rod.vx@2, rod.vy@2, rod.omega@2
"""
    got = answers(text)
    for k, want in {"collar.vx@2": 2.0, "collar.vy@2": 1.0, "rod.vx@2": 0.0, "rod.vy@2": 1.0,
                    "rod.omega@2": 0.0}.items():
        assert math.isclose(got[k], want, rel_tol=1e-12, abs_tol=1e-12), k



# ---- item 4: rolling during an interval ------------------------------------------------------
def test_a_disk_rolls_down_an_incline_with_the_friction_it_needs():
    m, r, g, th, T = 3.0, 0.2, 9.81, math.radians(25), 2.0
    a = g * math.sin(th) / 1.5  # m a = m g sin - F, (m r^2/2) a / r = F r
    got = answers(_file("disk_rolls_down_incline_interval.mom"))
    for k, want in {"disk.speed@2": a * T, "disk.omega@2": -a * T / r,
                    "friction": m * g * math.sin(th) / 3,
                    "normal": m * g * math.cos(th)}.items():
        assert math.isclose(got[k], want, rel_tol=1e-12), k


ROLLS = """
gravity 9.81 m/s^2 down
body hoop: ring(mass = 2 kg, radius = 0.5 m)
surface incline normal (sin(30 deg), cos(30 deg))
state 1: hoop at rest
state 2
interval 1 -> 2:
    hoop rolls on incline
    duration 1 s
find hoop.speed@2, F = J_t[hoop]@1->2 / t@1->2
"""


def test_rolls_on_in_an_interval_means_rolling_throughout():
    g, m = 9.81, 2.0
    got = answers(ROLLS)  # a hoop: I = m r^2, so a = g sin / 2 and F = m g sin / 2
    assert math.isclose(got["hoop.speed@2"], g * 0.5 / 2, rel_tol=1e-12)
    assert math.isclose(got["F"], m * g * 0.5 / 2, rel_tol=1e-12)


def test_the_static_coefficient_that_is_too_small_is_reported():
    from helpers import solve_text

    text = _file("disk_rolls_down_incline_interval.mom").replace("static 0.2", "static 0.1")
    checks = {c.name: c for c in solve_text(text).checks}
    assert checks["friction at disk (1->2)"].status == "warning"



# ---- item 7: friction with the ground in plan view ---------------------------------------------
def test_a_wreck_skids_to_rest_against_its_velocity():
    m1, v1, m2, v2, mu, g = 1500.0, 15.0, 1100.0, 20.0, 0.6, 9.81
    vx, vy = m1 * v1 / (m1 + m2), m2 * v2 / (m1 + m2)  # they lock: momentum conserved
    speed = math.hypot(vx, vy)
    s = speed ** 2 / (2 * mu * g)  # decelerating at mu g along a straight line
    got = answers(_file("intersection_crash_skid.mom"))
    for k, want in {"car.vx@2": vx, "car.vy@2": vy, "t@2->3": speed / (mu * g),
                    "car.dx@2->3": s * vx / speed, "car.dy@2->3": s * vy / speed}.items():
        assert math.isclose(got[k], want, rel_tol=1e-12), k


def test_plan_friction_takes_only_a_coefficient():
    d = error_of("""
gravity 9.81 m/s^2 into plane
body puck: particle(mass = 1 kg)
state 1: puck.v = (3 m/s, 4 m/s)
state 2
interval 1 -> 2:
    contact puck with ground: friction 0.1, slip (1, 0)
    puck stops
""")
    assert "write only `friction MU`" in d.message and d.span.line == 7



# ---- item 6: static and kinetic friction, and what happens at a stop ----------------------------
def test_a_crate_stops_up_an_incline_and_slides_back():
    g, th, mk, v0 = 9.81, math.radians(25), 0.3, 5.0
    up = g * (math.sin(th) + mk * math.cos(th))  # friction down the slope while going up
    down = g * (math.sin(th) - mk * math.cos(th))  # and up the slope while coming down
    got = answers(_file("crate_up_incline_slides_back.mom"))
    for k, want in {"t@1->2": v0 / up, "up_slope": v0 ** 2 / (2 * up),
                    "crate.speed@3": down * 1.0}.items():
        assert math.isclose(got[k], want, rel_tol=1e-12), k


def _hold_check(text: str):
    from helpers import solve_text

    return [c for c in solve_text(text).checks if "holding it" in c.detail]


def test_static_friction_holds_a_crate_when_tan_theta_is_below_it():
    text = _file("crate_up_incline_slides_back.mom")
    [c] = _hold_check(text.replace("let slope = 25 deg", "let slope = 20 deg"))
    assert c.status == "ok" and c.detail.endswith("it holds")  # tan 20 deg = 0.364 < 0.4
    assert f"{math.tan(math.radians(20)):.6g}" in c.detail
    # the comma form, and no phase after the stop: a slip is a warning
    alone = text.replace("friction 0.3 static 0.4", "friction 0.3, static 0.4")
    alone = alone[:alone.index("interval 2 -> 3")] + "find t@1->2\n"
    [c] = _hold_check(alone)
    assert c.status == "warning" and "it slips" in c.detail


# each example of these items, by the test that checks it against its closed form
EXAMPLE_CHECKS = {
    "unknown_tug_force": test_an_unknown_force_from_the_speed_it_gives,
    "unknown_split_duration": test_a_duration_that_is_what_is_left_of_a_total,
    "centre_of_percussion": test_the_centre_of_percussion_is_two_thirds_down_the_bar,
    "pucks_line_of_centres": test_two_pucks_take_the_line_of_centres,
    "skaters_grab_pole": test_two_skaters_grabbing_a_pole_spin_about_their_centre,
    "disk_rolls_down_incline_interval":
        test_a_disk_rolls_down_an_incline_with_the_friction_it_needs,
    "intersection_crash_skid": test_a_wreck_skids_to_rest_against_its_velocity,
    "crate_up_incline_slides_back": test_a_crate_stops_up_an_incline_and_slides_back,
    "collar_slides_on_spinning_rod":
        test_a_collar_sliding_out_conserves_angular_momentum_and_energy_then_strikes_the_stop,
}


def test_simulated_skaters_on_a_pole_turn_uniformly_about_their_centre():
    from momentum_cli.scene import build
    from momentum_cli.sim.integrate import simulate
    from momentum_cli.source import Source
    from momentum_cli.syntax import parse

    text = """
body A: particle(mass = 60 kg)
body B: particle(mass = 80 kg)
weld pole: A to B
state 1:
    A.pos = (0, 1 m), A.v = (2 m/s, 0)
    B.pos = (0, -1 m), B.v = (-1.5 m/s, 0)
simulate from 1:
    until t = 1 s
"""
    res = simulate(build(parse(Source("t.mom", text))), rtol=1e-10)
    f = res.frame()
    w, t = -3.5 / 2, 1.0  # zero momentum: they turn about the fixed centre (0, -1/7 m)
    c, rA = -1 / 7, 1 - (-1 / 7)
    ax, ay = f.pose["A"][0], f.pose["A"][1]
    assert math.isclose(ax, -rA * math.sin(w * t), abs_tol=1e-7)
    assert math.isclose(ay, c + rA * math.cos(w * t), abs_tol=1e-7)


def test_a_simulated_collar_slides_out_keeping_angular_momentum_and_energy():
    from momentum_cli.scene import build
    from momentum_cli.sim.integrate import simulate
    from momentum_cli.source import Source
    from momentum_cli.syntax import parse

    text = """
body rod: rod(mass = 4 kg, length = 1.2 m)
body collar: particle(mass = 1.5 kg)
pin rod.end(-) to ground at (0, 0)
slider collar on rod along (1, 0)
state 1:
    rod.angle = 0, rod.omega = 6 rad/s
    collar.pos = (0.2 m, 0), collar.v = (0, 1.2 m/s)
simulate from 1:
    until t = 0.3 s
"""
    M, L, m, r1, w1 = 4.0, 1.2, 1.5, 0.2, 6.0
    I_O = M * L * L / 3
    f = simulate(build(parse(Source("t.mom", text))), rtol=1e-10).frame()
    (cx, cy, _), (vx, vy, _) = f.pose["collar"], f.twist["collar"]
    th, w = f.pose["rod"][2], f.twist["rod"][2]
    assert abs(-cx * math.sin(th) + cy * math.cos(th)) < 1e-8  # on the rod's line
    H = I_O * w + m * (cx * vy - cy * vx)
    T = 0.5 * I_O * w * w + 0.5 * m * (vx * vx + vy * vy)
    assert math.isclose(H, (I_O + m * r1 * r1) * w1, rel_tol=1e-8)
    assert math.isclose(T, 0.5 * (I_O + m * r1 * r1) * w1 * w1, rel_tol=1e-8)
    assert math.hypot(cx, cy) > 0.3  # it has slid out
