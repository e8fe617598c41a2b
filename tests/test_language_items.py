"""Issue 10's language items, each against a closed form derived here (not the program's
own output): the small grammar traps, the units a student types, energy of part of the
scene, quantities of a body or a set, and two cases in one file."""
from __future__ import annotations

import math
import re
from pathlib import Path

import pytest

from helpers import answers, error_of

EX = Path(__file__).resolve().parent.parent / "examples"


def ex(name: str) -> dict[str, float]:
    return answers((EX / name).read_text(), name=name)


# ---- item 12: small grammar traps -------------------------------------------------------
def test_number_before_in_unit_is_a_number():
    a = answers('problem "t"\nlet L = 1.5 m\nbody b: particle(mass = 1 kg)\n'
                'state 1: b.v = (0, 0), b.pos = (0, 0)\n'
                'find half = L/2 in mm, q = -L/2 in mm, r = 3 in + 2 in in mm\n')
    assert a["half"] == pytest.approx(0.75)
    assert a["q"] == pytest.approx(-0.75)
    assert a["r"] == pytest.approx(5 * 0.0254)  # inches elsewhere stay inches


def test_in_unit_inside_an_expression_is_a_located_error():
    d = error_of('problem "t"\nbody b: particle(mass = 1 kg)\n'
                 'state 1: b.v = (0, 0), b.pos = (0, 0)\nlet x = 2 in mm + 1 m\nfind x\n')
    assert "`in mm` gives the unit of a `find` item" in d.message and d.span.line == 4


def elastic_no_energy_lost():
    # elastic head-on impact of m1 = 2 kg at u = 3 m/s on m2 = 1 kg at rest:
    # v1 = (m1 - m2) u/(m1 + m2), v2 = 2 m1 u/(m1 + m2)
    a = ex("elastic_no_energy_lost.mom")
    m1, m2, u = 2.0, 1.0, 3.0
    assert a["A.vx@2"] == pytest.approx((m1 - m2) * u / (m1 + m2))
    assert a["B.vx@2"] == pytest.approx(2 * m1 * u / (m1 + m2))
    assert a["mean"] == pytest.approx((3 * m1 - m2) * u / (2 * (m1 + m2)))


def test_zero_with_a_unit_still_checks_dimension():
    d = error_of('problem "t"\nbody b: particle(mass = 1 kg)\n'
                 'state 1: b.v = (1 m/s, 0), b.pos = (0, 0)\n'
                 'equation b.vx@1 = 0 kg\nfind b.vy@1\n')
    assert "differ" in d.message


def rocket_dv_only():
    a = ex("rocket_dv_only.mom")
    assert a["dv"] == pytest.approx(3000 * math.log(1000 / 700))
    assert a["probe.mass@2"] == pytest.approx(700)


def test_burn_without_rate_under_gravity_asks_for_rate_or_duration():
    text = (EX / "rocket_dv_only.mom").read_text().replace(
        'problem "', 'gravity 9.81 m/s^2 down\nproblem "')
    assert "`rate MASS_RATE` or `duration TIME`" in error_of(text).message


def test_burn_with_mass_and_duration_has_its_rate():
    # free space, 300 kg of 1000 kg in 60 s at c = 3000 m/s: x = 0.3 burnt fraction,
    # travel relative to coasting: -c (t - (m1/mdot) ln(m0/m1)) along the exhaust
    text = (EX / "rocket_dv_only.mom").read_text().replace(
        "    burns 300 kg", "    burns 300 kg\n    duration 60 s").replace(
        "find dv", "find x2 = probe.x@2, dv")
    a = answers(text)
    c, m0, m1, t = 3000.0, 1000.0, 700.0, 60.0
    mdot = (m0 - m1) / t
    assert a["dv"] == pytest.approx(c * math.log(m0 / m1))
    assert a["x2"] == pytest.approx(7500 * t + c * (t - m1 / mdot * math.log(m0 / m1)))


# ---- item 11: units and names a student types -------------------------------------------
LB, LBF, FT, MI = 0.45359237, 4.4482216152605, 0.3048, 1609.344


def baseball_hit_back():
    a = ex("baseball_hit_back.mom")
    m = 5 / 16 * LB                            # 5 oz of mass
    u, v = 90 * MI / 3600, 110 * MI / 3600     # mi/h in m/s
    assert a["J_n[bat]@1->2"] == pytest.approx(m * (u + v))
    assert a["F_avg"] == pytest.approx(m * (u + v) / 0.001)
    assert a["ball.vx@2"] == pytest.approx(v)
    assert a["v_kmh"] == pytest.approx(v)
    assert a["T@2"] == pytest.approx(0.5 * m * v * v)


BASE = ('problem "t"\nbody A: particle(mass = 1 kg)\nbody B: particle(mass = 1 kg)\n'
        'state 1: A.v = (1 m/s, 0), B.v = (0, 0), A.pos = (0, 0), B.pos = (1 m, 0)\n'
        'state 2\nimpact 1 -> 2:\n    contact A with B normal (-1, 0): restitution 1\n')


@pytest.mark.parametrize("line,hint", [
    ("impakt 2 -> 3:", "did you mean 'impact'?"),
    ("bdy C: particle(mass = 1 kg)", "did you mean 'body'?"),
    ("conserve momentun x of {A, B} over 1 -> 2", "did you mean 'momentum'?"),
    ("find T_lots@1->2", "did you mean 'T_lost@1->2'?"),
    ("find Bb.vx@2", "did you mean 'B.vx@2'?"),
    ("find A.omgea@2", "did you mean 'omega'?"),
    ("find A.vx@2 in km", "did you mean 'km/h'?"),
    ("find A.vx@2 in kmph", "did you mean 'mph'?"),
])
def test_did_you_mean(line, hint):
    assert hint in error_of(BASE + line + "\n").message


@pytest.mark.parametrize("text,si", [
    ("3 hp", 3 * 550 * FT * LBF), ("2 kW", 2000.0), ("1.5 MW", 1.5e6), ("4 W", 4.0),
    ("30 kmh", 30 / 3.6), ("30 km/hr", 30 / 3.6), ("60 mi/h", 60 * MI / 3600),
    ("44 fps", 44 * FT), ("44 ft/sec", 44 * FT), ("2 sec", 2.0), ("1.5 hr", 5400.0),
    ("30°", math.pi / 6), ("30 °", math.pi / 6), ("2 mi", 2 * MI),
])
def test_student_units(text, si):
    assert answers(BASE + f"find q = {text}\n")["q"] == pytest.approx(si)


# ---- item 1: energy of part of the scene --------------------------------------------------
def _struck_rod(M=3.0, L=1.2, m=0.5, u=6.0, e=0.8, g=9.81):
    """Rod pinned at its top, struck at its lower end: angular momentum about O and
    Newton's law give omega; the rod alone then swings: I_O w^2/2 = M g (L/2)(1 - cos)."""
    I_O = M * L * L / 3
    w = m * u * L * (1 + e) / (I_O + m * L * L)
    v = w * L - e * u
    swing = math.degrees(math.acos(1 - 0.5 * I_O * w * w / (M * g * L / 2)))
    return w, v, swing


def pendulum_struck_ball_flies_off():
    a = ex("pendulum_struck_ball_flies_off.mom")
    w, v, swing = _struck_rod()
    assert a["rod.omega@2"] == pytest.approx(w)
    assert a["ball.vx@2"] == pytest.approx(v)
    assert a["swing"] == pytest.approx(math.radians(swing))


def _pendulum_text(energy_line: str, extra: str = "") -> str:
    text = (EX / "pendulum_struck_ball_flies_off.mom").read_text()
    return re.sub(r"^energy 2 -> 3 of \{rod\}.*$", energy_line + extra, text, flags=re.M)


def test_energy_splits_bodies_that_nothing_ties():
    # no `of`: the ball is tied to the rod by nothing, so each has its own balance
    a = answers(_pendulum_text("energy 2 -> 3"))
    assert a["swing"] == pytest.approx(math.radians(_struck_rod()[2]))


def test_energy_of_groups_and_free():
    for line in ("energy 2 -> 3 of {rod}, {ball}", "energy 2 -> 3:\n    free ball"):
        a = answers(_pendulum_text(line))
        assert a["swing"] == pytest.approx(math.radians(_struck_rod()[2])), line


def test_energy_over_tied_bodies_names_of_in_the_error():
    d = error_of(_pendulum_text("energy 2 -> 3", "\nequation ball.x@3 = rod.x@3"))
    assert d.code == "under-determined"
    assert any("energy 2 -> 3 of {" in n for n in d.notes)


def test_energy_of_that_cuts_a_joint_warns():
    from helpers import solve_text

    text = _pendulum_text("energy 2 -> 3 of {rod}").replace(
        "pin rod.end(-) to ground at (0, 0)",
        "pin rod.end(-) to ground at (0, 0)\nspring s: ball to rod.end(+) stiffness 10 N/m")
    sol = solve_text(text)
    items = sol.system.notes.items
    assert any("spring s joins ball and rod" in d.message for d in items)


def test_energy_of_is_only_for_energy_phases():
    d = error_of(_pendulum_text("energy 2 -> 3 of {rod}").replace(
        "impact 1 -> 2:", "impact 1 -> 2 of {rod}:"))
    assert "energy phase" in d.message


# ---- item 2: quantities of a body or a set ----------------------------------------------
def struck_rod_system_momentum():
    a = ex("struck_rod_system_momentum.mom")
    M, L, m, u = 3.0, 1.2, 0.5, 6.0
    w, v, _ = _struck_rod()
    p2 = m * v + M * w * L / 2          # the rod's centre moves at w L/2
    assert a["px[{rod,ball}]@1"] == pytest.approx(m * u)
    assert a["px[{rod,ball}]@2"] == pytest.approx(p2)
    assert a["py[{rod,ball}]@2"] == pytest.approx(0, abs=1e-12)
    assert a["Jx[O]@1->2"] == pytest.approx(p2 - m * u)
    # angular momentum about O: m u L before, I_O w + m v L after (equal)
    assert a["H_O[{rod,ball}]@1"] == pytest.approx(m * u * L)
    assert a["H_O[{rod,ball}]@2"] == pytest.approx(M * L * L / 3 * w + m * v * L)
    assert a["T[rod]@2"] == pytest.approx(0.5 * M * L * L / 3 * w * w)
    assert a["rod.T@2"] == pytest.approx(a["T[rod]@2"])
    assert a["B.vx@2"] == pytest.approx(w * L)
    assert a["B.speed@2"] == pytest.approx(w * L)


SET = ('problem "t"\nbody A: particle(mass = 1 kg)\nbody B: particle(mass = 2 kg)\n'
       'body r: rod(mass = 3 kg, length = 2 m)\n'
       'state 1: A.v = (1 m/s, 2 m/s), A.pos = (0, 0), B.v = (3 m/s, 0), B.pos = (1 m, 1 m), '
       'r.v = (0, 0), r.pos = (0, 2 m), r.omega = 2 rad/s, r.angle = 0\n')


def test_quantities_of_sets_by_hand():
    a = answers(SET + "find p[{A, B}]@1, q = py[{A, B, r}]@1, T[r]@1, T[{A, r}]@1, "
                      "H[{A, B, r}]@1 about r.end(+), H[B]@1 about A\n")
    assert (a["px[{A,B}]@1"], a["py[{A,B}]@1"], a["q"]) == (7.0, 2.0, 2.0)
    I = 3 * 2 ** 2 / 12
    assert a["T[r]@1"] == pytest.approx(0.5 * I * 4)
    assert a["T[{A,r}]@1"] == pytest.approx(0.5 * 5 + 0.5 * I * 4)
    # about (1, 2): A r=(-1,-2) v=(1,2): 0; B r=(0,-1) mv=(6,0): 6; rod I w = 2
    assert a["H_r.end(+)[{A,B,r}]@1"] == pytest.approx(8.0)
    assert a["H_A[B]@1"] == pytest.approx(-6.0)


@pytest.mark.parametrize("find,words", [
    ("H[{A, B}]@1", "about POINT"),
    ("T[{A, C}]@1", "unknown body 'C'"),
    ("T@1 about A", "'about' belongs to an angular momentum"),
])
def test_quantities_of_sets_errors(find, words):
    assert words in error_of(SET + f"find {find}\n").message


# ---- item 13: two cases in one file ------------------------------------------------------
def _disk_bounce(rough: bool, m=2.0, r=0.1, vx=2.0, vy=-3.0, e=0.5, g=9.81):
    """Closed form: vy' = -e vy; smooth keeps vx; rough (no slip at the contact point,
    I = m r^2/2): J_t = m vx/3 against the slip, vx' = 2 vx/3, omega' = -vx'/r."""
    vy2 = -e * vy
    vx2 = 2 * vx / 3 if rough else vx
    w2 = -vx2 / r if rough else 0.0
    T1 = 0.5 * m * (vx * vx + vy * vy)
    T2 = 0.5 * m * (vx2 * vx2 + vy2 * vy2) + 0.5 * (m * r * r / 2) * w2 * w2
    return vx2, vy2, w2, T1 - T2, vy2 * vy2 / (2 * g)


def disk_bounce_smooth_or_rough():
    a = ex("disk_bounce_smooth_or_rough.mom")
    for sid, case, rough in (("2", "a", False), ("3", "b", True)):
        vx, vy, w, lost, rise = _disk_bounce(rough)
        assert a[f"disk.vx@{sid}"] == pytest.approx(vx)
        assert a[f"disk.vy@{sid}"] == pytest.approx(vy)
        assert a[f"disk.omega@{sid}"] == pytest.approx(w, abs=1e-12)
        assert a[f"T_lost@1->{sid}"] == pytest.approx(lost)
        assert a[f"rise_{case}"] == pytest.approx(rise)


def test_t_lost_covers_only_what_the_impact_changes():
    # a second body whose speed nobody gives: T_lost of the disk's bounce does not need it
    text = (EX / "disk_bounce_smooth_or_rough.mom").read_text().replace(
        'body disk:', 'body other: particle(mass = 5 kg)\nbody disk:')
    a = answers(text)
    assert a["T_lost@1->3"] == pytest.approx(_disk_bounce(True)[3])


def test_report_says_which_bodies_a_t_covers():
    from helpers import solve_text
    from momentum_cli.report.model import build_report

    text = (EX / "disk_bounce_smooth_or_rough.mom").read_text().replace(
        'body disk:', 'body other: particle(mass = 5 kg)\nbody disk:')
    rep = build_report("t.mom", solve_text(text))
    details = [c.detail for c in rep.checks if c.name.startswith("kinetic energy")]
    assert len(details) == 2 and all(d.startswith("T of {disk}:") for d in details)


# the examples' checks, run by test_examples.py (one check for every example)
CHECKS = {f.__name__: f for f in [elastic_no_energy_lost, rocket_dv_only, baseball_hit_back,
                                   pendulum_struck_ball_flies_off, struck_rod_system_momentum,
                                   disk_bounce_smooth_or_rough]}
