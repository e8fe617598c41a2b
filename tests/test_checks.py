"""Checks with honest tolerances: redundant statements, round-off, derived answers.

A redundant equation is judged against the size of the quantities in it and the
solve's own error bound (exactly in exact mode); where float cannot decide, the
check says so and names `--precision exact`; a value within its error bound of zero
is zero; derived answers are evaluated in the solve's precision, and every answer's
error bound covers what it prints. Expected numbers are closed forms derived here.
"""
from __future__ import annotations

import math
from fractions import Fraction as F
from pathlib import Path

import pytest

from momentum_cli.diagnostics import ProblemError
from momentum_cli.scene import build
from momentum_cli.solve import solve_scene
from momentum_cli.source import Source
from momentum_cli.syntax import parse

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
HARD = EXAMPLES / "hard"


def solve(text: str, precision: str = "float"):
    return solve_scene(build(parse(Source("test.mom", text))), precision=precision)


def answers(sol) -> dict[str, float]:
    return {name: si for name, _v, _u, si in sol.answers}


def crash_text(vA_kmh: float) -> str:
    text = (EXAMPLES / "crash_cars_lock_skid.mom").read_text(encoding="utf-8")
    assert "let vA = 50 km/h" in text
    return text.replace("let vA = 50 km/h", f"let vA = {vA_kmh} km/h")


@pytest.mark.parametrize("precision", ["float", "exact"])
@pytest.mark.parametrize("vA", [40, 45, 50, 54, 60, 70])
def test_crash_redundant_stop_holds_at_every_speed(vA, precision):
    """`A stops` (x and y) for one duration: the second equation is a check whose
    residual is round-off around zero; it once failed 'inconsistent' at 45-60 km/h."""
    sol = solve(crash_text(vA), precision)
    mA, mB, mu, g = 1500.0, 1000.0, 0.7, 9.81
    vx, vy = mA * vA / 3.6 / (mA + mB), mB * 30 / 3.6 / (mA + mB)
    V = math.hypot(vx, vy)
    a = answers(sol)
    for key, want in {"A.vx@2": vx, "A.vy@2": vy, "t@2->3": V / (mu * g),
                      "d": V * V / (2 * mu * g)}.items():
        assert math.isclose(a[key], want, rel_tol=1e-12), (key, a[key], want)
    stops = [c for c in sol.checks if c.name == "A stops"]
    assert stops and all(c.status == "ok" for c in stops), stops


def _grazing_with(value: str) -> str:
    text = (HARD / "grazing_wall.mom").read_text(encoding="utf-8")
    return text + f"\nequation puck.vx@2 = {value} m/s\n"


def test_grazing_wall_accepts_its_own_solved_value():
    text = (HARD / "grazing_wall.mom").read_text(encoding="utf-8")
    for precision in ("float", "exact"):
        own = answers(solve(text, precision))["puck.vx@2"]
        sol = solve(_grazing_with(repr(own)), precision)
        checks = [c for c in sol.checks if c.name == "equation"]
        assert checks and checks[0].status == "ok", checks


def test_grazing_wall_refuses_a_value_1e3_off():
    own = answers(solve((HARD / "grazing_wall.mom").read_text(encoding="utf-8")))["puck.vx@2"]
    text = _grazing_with(repr(own * (1 + 1e-3)))
    with pytest.raises(ProblemError) as exc:
        solve(text)
    d = exc.value.diagnostics[0]
    assert d.code == "inconsistent"
    assert d.span.line == len(text.rstrip("\n").split("\n"))


def _ridge_with(statement: str) -> str:
    return (HARD / "ridge_near_singular.mom").read_text(encoding="utf-8") + statement + "\n"


def test_ridge_float_cannot_decide_and_says_so():
    """cond ~5e14: a statement 1e-3 off the closed form (v_y = -2.5 m/s) is inside the
    float solve's error bound: not 'holds', but a warning naming --precision exact."""
    sol = solve(_ridge_with("equation rod.vy@2 = -2.5025 m/s"))
    c = [c for c in sol.checks if c.name == "equation"]
    assert c and c[0].status == "warning", c
    assert "cannot decide" in c[0].detail and "--precision exact" in c[0].detail


def test_ridge_exact_decides():
    with pytest.raises(ProblemError) as exc:
        solve(_ridge_with("equation rod.vy@2 = -2.5025 m/s"), "exact")
    assert exc.value.diagnostics[0].code == "inconsistent"
    sol = solve(_ridge_with("equation rod.vy@2 = -2.5 m/s"), "exact")
    c = [c for c in sol.checks if c.name == "equation"]
    assert c and c[0].status == "ok", c


def test_truck_dv_is_exact_in_exact_mode():
    """dv_truck = -2 m U/(m + M): a cancellation in float, exact in rationals."""
    sol = solve((HARD / "truck_hits_fly.mom").read_text(encoding="utf-8"), "exact")
    m, M, U = F(1e-5), F(1e4), F(25)
    want = -2 * m * U / (m + M)
    got = answers(sol)["dv_truck"]
    assert abs(F(got) - want) <= F(math.ulp(float(want))), (got, float(want))


@pytest.mark.parametrize("precision", ["float", "exact"])
def test_restitution_nearly_one_t_lost(precision):
    """T_lost = m_eff (1 - e^2) u^2 / 2, with 1 - e^2 from the file's float e: from the
    impulses, -J (1 - e) v_n / 2, float keeps the digits T1 - T2 cancels."""
    sol = solve((HARD / "restitution_nearly_one.mom").read_text(encoding="utf-8"), precision)
    m, M, L, d, u = F(1, 2), F(3), F(2), F(3, 5), F(8)
    e = F(1 - 1e-12)
    I = M * L * L / 12
    meff = 1 / (1 / m + 1 / M + F(0.6) ** 2 / I)
    want = meff * (1 - e * e) * u * u / 2
    got = answers(sol)["T_lost@1->2"]
    assert math.isclose(got, float(want), rel_tol=1e-9), (got, float(want))


HARD_FILES = sorted(p.name for p in HARD.glob("*.mom")
                    if not p.name.startswith(("bad_", "cradle_")))


@pytest.mark.parametrize("name", HARD_FILES)
def test_answer_bounds_cover_the_float_error(name):
    """Every answer's error bound covers |float - exact| (exact: the rational solve)."""
    text = (HARD / name).read_text(encoding="utf-8")
    try:
        exact = solve(text, "exact")
    except ProblemError:
        pytest.skip("refused in exact mode")
    try:
        flt = solve(text)
    except ProblemError:
        pytest.skip("refused in float (ill-conditioned beyond float64)")
    want = answers(exact)
    for key, got in answers(flt).items():
        bound = flt.answer_errors[key] + exact.answer_errors[key]
        assert abs(F(got) - F(want[key])) <= F(bound) * (1 + 1e-9), (key, got, want[key], bound)


def test_roundoff_values_are_zero_and_said_so():
    """The ballistic pendulum's vertical velocities are 0 (cos 90 deg = 6e-17 in float)."""
    sol = solve((EXAMPLES / "ballistic_pendulum.mom").read_text(encoding="utf-8"))
    for name in ("bullet.vy@2", "pendulum.vy@2", "Jy[O]@1->2"):
        assert sol.values[name] == 0.0, (name, sol.values[name])
    notes = [c for c in sol.checks if c.name == "round-off"]
    assert notes and "bullet.vy@2" in notes[0].detail


# ---- roots of nonlinear blocks: the physics chooses, the hint separates ----------------------

def _text(name: str) -> str:
    return (EXAMPLES / f"{name}.mom").read_text(encoding="utf-8")


def test_redundant_energy_statement_is_a_check_not_a_second_root():
    """Energy stated with e = 1 on a pinned rod: the impact's rows decide (the physical
    answer, the closed form with the effective mass I_O/d^2 at the struck point), and the
    energy statement, true for e = 1, is checked instead of offering the root 'rod at
    rest, ball bounced straight back'."""
    sol = solve(_text("rod_pinned_struck_energy"))
    m, M, L, d, u = 0.5, 4.0, 1.2, 0.9, 6.0
    mP = M * L * L / 3 / d**2
    got = answers(sol)
    assert got["ball.vx@2"] == pytest.approx((m - mP) / (m + mP) * u, rel=1e-12)
    assert got["rod.omega@2"] == pytest.approx(2 * m * u / ((m + mP) * d), rel=1e-12)
    held = [c for c in sol.checks if c.name.startswith("work-energy")]
    assert held and all(c.status == "ok" for c in held)


def test_unphysical_root_is_rejected_with_its_reason():
    """e unknown and no energy lost: e = -1 (zero impulse, the bodies pass through each
    other) is rejected, e = 1 is the answer."""
    sol = solve(_text("find_e_no_energy_lost"))
    assert answers(sol)["e[hit]"] == pytest.approx(1.0, rel=1e-12)
    rejected = [c.detail for c in sol.checks if c.name.startswith("root rejected")]
    assert rejected and "outside [0, 1]" in rejected[0]


def test_root_before_impact_must_approach():
    """Without its hint `ball.vy < 0`, the ball's speed just before the bounce has two
    roots; the one moving up (separating before the impact) is rejected."""
    text = _text("ball_bounce_rebound").replace(", ball.vy < 0", "")
    assert text != _text("ball_bounce_rebound")
    sol = solve(text)
    assert sol.values["ball.vy@2"] < 0
    rejected = [c.detail for c in sol.checks if c.name.startswith("root rejected")]
    assert rejected and "separate before the impact" in rejected[0]


def _hint_note(text: str) -> str:
    with pytest.raises(ProblemError) as exc:
        solve(text)
    d = exc.value.diagnostics[0]
    assert d.code == "ambiguous"
    notes = [n for n in d.notes if n.startswith("choose one with a hint")]
    assert notes, d.notes
    return notes[0]


@pytest.mark.parametrize("written", ["", ", wheel.vx > -100 m/s"])
def test_suggested_hint_separates_the_roots(written):
    """Both roots satisfy the hint already written (or there is none): the suggestion
    is a different one that keeps exactly one root, and applying it solves the file."""
    base = _text("disk_rolls_down_ramp")
    text = base.replace(", wheel.vx > 0", written)
    note = _hint_note(text)
    hint = note.split("`")[1]
    assert hint not in written
    qty, rest = hint.split(" ", 1)
    state = note.split("in state ")[1].split(" ")[0]
    lines = text.split("\n")
    k = next(i for i, line in enumerate(lines) if line.startswith(f"state {state} "))
    lines[k] += f", {qty.split('.', 1)[0]}.{qty.split('.', 1)[1]} {rest}"
    kept = solve("\n".join(lines))
    want = answers(solve(base))
    got = answers(kept)
    # the hint keeps one root: either the example's own, or its mirror image
    assert all(abs(abs(got[k]) - abs(v)) <= 1e-9 * max(1.0, abs(v)) for k, v in want.items())


def test_only_root_left_by_a_hint_is_said_not_physical():
    """A hint that keeps only the unphysical root (the ball moving up just before it
    bounces): the file's choice is kept, and a warning says why it is not physical."""
    text = _text("ball_bounce_rebound").replace("ball.vy < 0", "ball.vy > 0")
    assert text != _text("ball_bounce_rebound")
    sol = solve(text)
    warn = [c for c in sol.checks if c.name.startswith("only root")]
    assert warn and warn[0].status == "warning" and "separate before the impact" in warn[0].detail


STUCK = """
body ball: sphere(mass = 3.92 kg, radius = 0.48 m)
link strut: ball.center to ground along (1, 4)
state 1:
    ball.angle = 0, ball.pos = (-2.07 m, 2.96 m)
    ball.vy = -0.5382352941176471 m/s, ball.omega = 2.19 rad/s
state 2
impact 1 -> 2:
    contact k1: ball with ground normal (0, 1): restitution 0, rough
equation ball.omega@2 = {w} rad/s
find ball.vx@2, ball.vy@2
"""


def test_a_round_off_zero_angular_velocity_is_read_against_the_given_ones():
    """The strut allows motion only along (1, 4), the plastic rough floor stops that and
    the spin: every velocity after is 0 (closed form). A statement of 0 to round-off
    holds, read against the given 2.19 rad/s; one off by 1e-9 rad/s is refused."""
    from helpers import answers, error_of

    got = answers(STUCK.format(w="-1.1564823173178715e-15"))
    assert abs(got["ball.vx@2"]) < 1e-14 and abs(got["ball.vy@2"]) < 1e-14
    assert "inconsistent" in error_of(STUCK.format(w="1e-9")).message
