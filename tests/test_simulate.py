"""`momentum simulate`: closed forms, agreement with `solve`, events, effects, output.

Every expected number is derived here (closed forms of free flight, constant
deceleration, the physical pendulum and spring periods, the bouncing ball's
geometric series) or is the seeds' worked answer, or what `solve` gives for the same
file (the issue asks that both agree).
"""
from __future__ import annotations

import csv
import io
import json
import math
from pathlib import Path

import pytest
from conftest import EXAMPLES
from typer.testing import CliRunner

from momentum_cli.cli import app
from momentum_cli.scene import build
from momentum_cli.sim.integrate import simulate
from momentum_cli.source import Source
from momentum_cli.syntax import parse

runner = CliRunner()
G = 9.81
SIM_EXAMPLES = sorted(EXAMPLES.glob("simulate/*.mom"))
SEEDS = [p for p in sorted(EXAMPLES.glob("seed_*.mom")) if "simulate from" in p.read_text()]


def run(text: str, rtol: float = 1e-9, dt=None):
    return simulate(build(parse(Source("t.mom", text))), rtol=rtol, dt=dt)


def run_file(path: Path, rtol: float = 1e-9):
    return simulate(build(parse(Source(str(path), path.read_text()))), rtol=rtol)


def final(res, body):
    f = res.frame()
    return f.pose[body], f.twist[body]


def impacts(res):
    return [e for e in res.events if e.kind == "impact"]


def solve_values(path: Path) -> dict:
    from momentum_cli.solve import solve_scene

    sol = solve_scene(build(parse(Source(str(path), path.read_text()))), solve_all=True)
    return sol.values


# ---- closed forms ---------------------------------------------------------------------------
def test_free_flight_to_the_apex_is_the_closed_form():
    res = run_file(EXAMPLES / "simulate/projectile_apex.mom")
    v0, th = 20.0, math.radians(60)
    t = v0 * math.sin(th) / G
    (x, y, angle), (vx, vy, w) = final(res, "disk")
    assert res.stop == "apex"
    assert res.events[-1].t == pytest.approx(t, rel=1e-13)
    assert y == pytest.approx((v0 * math.sin(th)) ** 2 / (2 * G), rel=1e-13)
    assert x == pytest.approx(v0 * math.cos(th) * t, rel=1e-13)
    assert angle == pytest.approx(12 * t, rel=1e-13)  # no moment: spins uniformly
    assert {p.method for p in res.phases} == {"closed form"}


def test_sliding_disk_decelerates_uniformly_then_rolls():
    res = run_file(EXAMPLES / "simulate/disk_slide_then_roll.mom")
    v0, mu, r = 6.0, 0.25, 0.2
    t_roll = v0 / (3 * mu * G)  # friction mu m g: a = -mu g, alpha = 2 mu g / r
    stick = [e for e in res.events if e.kind == "stick"]
    assert len(stick) == 1 and stick[0].t == pytest.approx(t_roll, rel=1e-12)
    (x, _, _), (vx, vy, w) = final(res, "disk")
    assert vx == pytest.approx(2 * v0 / 3, rel=1e-12)
    assert w == pytest.approx(-2 * v0 / 3 / r, rel=1e-12)
    x_roll = v0 * t_roll - 0.5 * mu * G * t_roll ** 2
    assert x == pytest.approx(x_roll + 2 * v0 / 3 * (1.5 - t_roll), rel=1e-12)


PENDULUM = """
gravity 9.81 m/s^2 down
body bob: sphere(mass = 2 kg, radius = 0.05 m)
point P = bob at (0, 0.8 m)
pin P to ground at (0, 0)
state 1: bob.angle = {a0}, bob.omega = 0
simulate from 1:
    until bob.omega = 0
"""


@pytest.mark.parametrize("theta0", [1e-3, 0.05])
def test_physical_pendulum_half_period(theta0):
    m, r, d = 2.0, 0.05, 0.8
    I_O = 2 / 5 * m * r * r + m * d * d
    T0 = 2 * math.pi * math.sqrt(I_O / (m * G * d))
    T = T0 * (1 + theta0 ** 2 / 16 + 11 * theta0 ** 4 / 3072)  # the amplitude series
    res = run(PENDULUM.format(a0=f"{theta0} rad"), rtol=1e-12)
    assert res.events[-1].t == pytest.approx(T / 2, rel=1e-9)
    (_, _, angle), _ = final(res, "bob")
    assert angle == pytest.approx(-theta0, rel=1e-9)  # the other side, same height


def test_spring_mass_returns_after_one_period():
    res = run_file(EXAMPLES / "simulate/spring_mass.mom", rtol=1e-11)
    (x, y, _), (vx, vy, _) = final(res, "block")
    assert x == pytest.approx(0.6, abs=1e-9)
    assert vx == pytest.approx(0.0, abs=1e-8)
    # energy: the spring's and the block's exchange, total constant
    assert max(p.drift for p in res.phases) < 1e-9 * 0.5 * 50 * 0.1 ** 2
    half = run((EXAMPLES / "simulate/spring_mass.mom").read_text().replace(
        "until t = 1.2566370614359172 s", "until block.vx = 0"), rtol=1e-11)
    assert half.events[-1].t == pytest.approx(math.pi * math.sqrt(2 / 50), rel=1e-9)
    assert final(half, "block")[0][0] == pytest.approx(0.4, abs=1e-10)  # amplitude 0.1


def test_ball_bounce_times_are_the_geometric_series():
    res = run_file(EXAMPLES / "simulate/ball_bounces.mom")
    e, h = 0.8, 1.0
    t1 = math.sqrt(2 * h / G)
    want = [t1 * (1 + 2 * sum(e ** j for j in range(1, k))) for k in range(1, 6)]
    got = [ev.t for ev in impacts(res)]
    assert got == pytest.approx(want, rel=1e-12)
    for k, ev in enumerate(impacts(res)):
        assert ev.after["ball"][1] == pytest.approx(e ** (k + 1) * G * t1, rel=1e-12)


def test_bouncing_ball_comes_to_rest_at_the_series_sum():
    text = (EXAMPLES / "simulate/ball_bounces.mom").read_text().replace(
        "until 5 impacts", "until t = 6 s")
    res = run(text)
    e, t1 = 0.8, math.sqrt(2 / G)
    t_rest = t1 * (1 + e) / (1 - e)
    # a rebound that would not clear the contact tolerance (1e-9 of the size) is rest:
    # the remaining flights, 2 v / (g (1 - e)) with v = sqrt(2 g 2e-11 m), are cut short
    cut = 2 * math.sqrt(2 * G * 2e-11) / (G * (1 - e))
    assert t_rest - 2 * cut < impacts(res)[-1].t <= t_rest
    (x, y, _), (vx, vy, _) = final(res, "ball")
    assert (y, vy) == (pytest.approx(0.02, abs=1e-9), 0.0)
    assert res.events[-1].t == 6.0


# ---- seeds: simulate agrees with solve ---------------------------------------------------------
def test_seed_disk_against_wall_stops_at_the_solved_time():
    path = EXAMPLES / "seed_disk_wall.mom"
    res = run_file(path)
    assert res.events[-1].t == pytest.approx(3.0480762, rel=1e-7)  # DESIGN / seed answer
    assert res.events[-1].t == pytest.approx(solve_values(path)["t@1->2"], rel=1e-12)
    (_, _, angle), _ = final(res, "disk")
    assert angle == pytest.approx(-91.44, rel=1e-3)  # the notes' 91.44 rad, clockwise


def test_seed_pendulum_rebounds_to_the_solved_angle():
    path = EXAMPLES / "seed_pendulum_wall.mom"
    res = run_file(path, rtol=1e-12)
    (_, _, angle), _ = final(res, "pendulum")
    exact = -math.asin(1 - 0.6 ** 2)  # the rise is e^2 of the drop: sin(theta) = 1 - e^2
    assert angle == pytest.approx(exact, abs=1e-12)
    assert angle == pytest.approx(solve_values(path)["pendulum.angle@4"], abs=1e-12)
    assert math.degrees(-angle) == pytest.approx(39.79, abs=5e-3)


@pytest.mark.parametrize("name,omega", [("seed_rod_drop_smooth", -14.1637424),
                                        ("seed_rod_drop_rough", -5.7540203)])
def test_seed_rod_leaves_the_floor_with_the_solved_omega(name, omega):
    path = EXAMPLES / f"{name}.mom"
    res = run_file(path)
    (hit,) = impacts(res)
    assert hit.t == pytest.approx(math.sqrt(2 * 1.0 / G), rel=1e-9)  # it fell 1 m
    assert hit.after["rod"][2] == pytest.approx(omega, rel=1e-7)
    v = solve_values(path)
    assert hit.after["rod"] == pytest.approx((v["rod.vx@3"], v["rod.vy@3"], v["rod.omega@3"]),
                                             rel=1e-9, abs=1e-12)


def test_seed_billiard_balls_leave_with_the_solved_speeds():
    for path in (EXAMPLES / "seed_billiards_elastic.mom",
                 EXAMPLES / "simulate/billiards_spheres.mom"):
        res = run_file(path)
        (hit,) = impacts(res)
        v = 5.0
        assert hit.after["C"][0] == pytest.approx(-v / 5, rel=1e-12)
        for b in "AB":
            assert math.hypot(*hit.after[b][:2]) == pytest.approx(2 * math.sqrt(3) / 5 * v,
                                                                  rel=1e-12)
    # the spheres meet both balls at one instant: one impact with both contacts
    assert hit.what == "A-C, B-C"
    r = 0.0285
    assert hit.t == pytest.approx(0.1 / v, rel=1e-9)
    assert final(res, "A")[0][1] > r  # and A, B separate (their contact is not held)


def test_seed_rod_and_disk_bearing_lock_at_the_solved_omega():
    path = EXAMPLES / "seed_rod_disk_bearing.mom"
    res = run_file(path)
    (lock,) = [e for e in res.events if e.kind == "lock"]
    assert lock.after["rod"][2] == pytest.approx(0.0707965, rel=1e-6)
    assert lock.after["rod"][2] == pytest.approx(solve_values(path)["rod.omega@2"], rel=1e-9)
    _, (_, _, w) = final(res, "rod")
    assert w == pytest.approx(lock.after["rod"][2], rel=1e-9)  # they turn on together


# ---- events and effects -------------------------------------------------------------------------
TWO_BALLS = """
gravity 9.81 m/s^2 down
body p: sphere(mass = 1 kg, radius = 0.1 m)
body q: sphere(mass = 3 kg, radius = 0.1 m)
surface floor normal (0, 1) at (0, 0)
state 1: p.pos = (0, {hp}), q.pos = (1 m, {hq}), p at rest, q at rest
simulate from 1:
    contact p with floor: restitution 0.5
    contact q with floor: restitution 0.9
    until 2 impacts
"""


@pytest.mark.parametrize("dh", [1e-7, -1e-7, 1e-11])
def test_near_simultaneous_contacts_are_resolved_in_order(dh):
    hp, hq = 1.1, 1.1 + dh  # centres; the balls fall 1 m and 1 m + dh
    res = run(TWO_BALLS.format(hp=f"{hp} m", hq=f"{hq} m"), rtol=1e-12)
    tp, tq = math.sqrt(2 * (hp - 0.1) / G), math.sqrt(2 * (hq - 0.1) / G)
    hits = impacts(res)
    if abs(dh) < 1e-10:  # within the contact tolerance: one impact with both contacts
        assert hits[0].what == "p, q"
        assert set(hits[0].impulses) >= {"J_n[p]", "J_n[q]"}
        return
    first, second = sorted([("p", tp), ("q", tq)], key=lambda x: x[1])
    assert [h.what for h in hits] == [first[0], second[0]]
    assert [h.t for h in hits] == pytest.approx([first[1], second[1]], rel=1e-12)
    e = {"p": 0.5, "q": 0.9}
    for h in hits:
        assert h.after[h.what][1] == pytest.approx(e[h.what] * G * dict([first, second])[h.what],
                                                   rel=1e-9)


def test_no_gravity_declared_nothing_moves():
    res = run("""
body b: disk(mass = 1 kg, radius = 0.1 m)
surface floor normal (0, 1) at (0, 0)
state 1: b.pos = (0, 0.5 m), b at rest
simulate from 1:
    contact b with floor: restitution 0.5
    until t = 5 s
""")
    (x, y, a), (vx, vy, w) = final(res, "b")
    assert (x, y, a, vx, vy, w) == (0.0, 0.5, 0.0, 0.0, 0.0, 0.0)
    assert not impacts(res) and {p.method for p in res.phases} == {"closed form"}


def test_without_gravity_a_moving_body_coasts_uniformly():
    res = run("""
body b: particle(mass = 1 kg)
state 1: b.pos = (0, 0), b.v = (3 m/s, -4 m/s)
simulate from 1:
    until t = 2 s
""")
    (x, y, _), (vx, vy, _) = final(res, "b")
    assert (x, y, vx, vy) == (6.0, -8.0, 3.0, -4.0)


def test_damper_dissipates_what_the_energy_loses():
    res = run("""
body m: particle(mass = 1 kg)
point O = ground at (0, 0)
spring s: m to O stiffness 100 N/m length 1 m
state 1: m.pos = (1.2 m, 0), m at rest
simulate from 1:
    damper d: m to O damping 2 N*s/m
    until t = 3 s
""", rtol=1e-11)
    k, c, mass = 100.0, 2.0, 1.0
    wn = math.sqrt(k / mass)
    zeta = c / (2 * math.sqrt(k * mass))
    wd = wn * math.sqrt(1 - zeta ** 2)
    t = 3.0
    x = 0.2 * math.exp(-zeta * wn * t) * (math.cos(wd * t) + zeta * wn / wd * math.sin(wd * t))
    (px, _, _), _ = final(res, "m")
    assert px - 1.0 == pytest.approx(x, abs=1e-9)
    # what the damper took (W < 0) is exactly what the spring and block lost
    assert max(p.drift for p in res.phases) < 1e-9 * 0.5 * k * 0.2 ** 2


def test_fixed_step_converges_to_the_closed_form():
    path = EXAMPLES / "seed_pendulum_wall.mom"
    exact = -math.asin(1 - 0.36)
    errs = []
    for dt in (0.1, 0.05):
        res = simulate(build(parse(Source(str(path), path.read_text()))), dt=dt,
                       closed_forms=False)
        errs.append(abs(final(res, "pendulum")[0][2] - exact))
        assert {p.method for p in res.phases} == {"fixed step"}
    # DOP853 is of order 8: halving the step divides the error by about 2^8
    assert errs[1] < errs[0] / 50 and errs[0] < 1e-4


@pytest.mark.parametrize("a0,w0", [("60 deg", "0"), ("-90 deg", "9 rad/s"),
                                   ("-90 deg", "-9 rad/s"), ("170 deg", "-0.5 rad/s")])
def test_pendulum_closed_form_agrees_with_integration(a0, w0):
    """Swinging and turning over (k > 1) in both senses: the elliptic closed form and
    DOP853 at rtol 1e-12 agree, and the closed form conserves energy exactly."""
    from momentum_cli.sim.dynamics import Frame
    from momentum_cli.sim.forces import energy

    text = PENDULUM.format(a0=a0).replace("bob.omega = 0", f"bob.omega = {w0}").replace(
        "until bob.omega = 0", "until t = 2.5 s")
    closed, numeric = run(text), simulate(build(parse(Source("t.mom", text))), rtol=1e-12,
                                          closed_forms=False)
    assert {p.method for p in closed.phases} == {"closed form"}
    (_, _, a1), (_, _, w1) = final(closed, "bob")
    (_, _, a2), (_, _, w2) = final(numeric, "bob")
    assert a1 == pytest.approx(a2, abs=1e-9) and w1 == pytest.approx(w2, abs=1e-9)
    n = closed.model.n
    E = [energy(closed.model, Frame(closed.model, y[:n], y[n:2 * n])) for y in closed.states]
    assert max(E) - min(E) <= 1e-12 * max(abs(x) for x in E)


def test_energy_is_not_gained_in_a_frictionless_elastic_bounce():
    text = (EXAMPLES / "simulate/ball_bounces.mom").read_text().replace(
        "restitution 0.8", "restitution 1")
    res = run(text)
    for h in impacts(res):
        assert h.energy_lost == pytest.approx(0.0, abs=1e-12)
    (_, y, _), _ = final(res, "ball")
    assert y == pytest.approx(0.02, abs=1e-9)


# ---- errors ------------------------------------------------------------------------------------
@pytest.mark.parametrize("text,message,line", [
    ("body b: particle(mass = 1 kg)\nstate 1: b at rest\nfind b.vx@1\n", "nothing to simulate",
     None),
    ("body b: particle(mass = 1 kg)\nstate 1: b at rest\nsimulate from 1:\n    until apex\n",
     "`until apex` needs gravity", 4),
    ("body b: particle(mass = 1 kg)\nstate 1: b at rest\nsimulate from 2:\n    until t = 1 s\n",
     "state 2 is not declared", 3),
    ("body b: particle(mass = 1 kg)\nstate 1: b.pos = (0, 0)\nsimulate from 1:\n"
     "    until t = 1 s\n", "b.vx@1, b.vy@1 are not known", 3),
    ("body b: particle(mass = 1 kg)\nstate 1: b at rest\nsimulate from 1:\n    until b.speed = 1\n",
     "'speed' is not a state quantity", 4),
    ("body b: particle(mass = 1 kg)\nstate 1: b at rest\nsimulate from 1:\n    until t = 1 kg\n",
     "a stop time needs a time", 4),
    ("body b: particle(mass = 1 kg)\nstate 1: b at rest\nsimulate from 1:\n"
     "    contact b with ground normal (0, 1)\n    until t = 1 s\n", "needs a restitution", 4),
    ("body b: particle(mass = 1 kg)\nstate 1: b at rest\nsimulate from 1:\n"
     "    damper d: b to ground damping 2 N\n    until t = 1 s\n", "damping coefficient", 4),
    ("body b: particle(mass = 1 kg)\nstate 1: b at rest\nsimulate from 1:\n    until t = 1 s\n"
     "simulate from 1:\n    until t = 2 s\n", "a file has one `simulate` block", 5),
    ("body b: particle(mass = 1 kg)\nstate 1: b at rest\nsimulate from 1:\n    until 2 impacts\n",
     "no contact is watched", 4),
    ("gravity 9.81 m/s^2 down\nbody b: particle(mass = 1 kg)\nstate 1: b.pos = (0, 0), "
     "b.v = (0, -1 m/s)\nsimulate from 1:\n    until apex\n", "the motion never ends", 4),
    (PENDULUM.format(a0="10 deg").replace("until bob.omega = 0", "until 1 impacts\n"
     "    contact bob with wall: restitution 1") + "surface wall normal (-1, 0) at (2 m, 0)\n",
     "never ends", 7),
])
def test_bad_simulations_are_located_errors(text, message, line, tmp_path):
    path = tmp_path / "bad.mom"
    path.write_text(text)
    res = runner.invoke(app, ["simulate", "--plain", str(path)])
    assert res.exit_code == 1, res.output
    err = res.stderr
    assert message in err, err
    if line is not None:
        assert f"bad.mom:{line}:" in err
    assert "Traceback" not in res.output


# ---- output ------------------------------------------------------------------------------------
def _golden(path: Path) -> Path:
    return path.with_suffix(".sim.out")


@pytest.mark.parametrize("problem", SIM_EXAMPLES + SEEDS, ids=lambda p: p.stem)
def test_event_table_matches_golden(problem, update_golden, monkeypatch):
    monkeypatch.chdir(EXAMPLES.parent)
    res = runner.invoke(app, ["simulate", "--plain", str(problem.relative_to(EXAMPLES.parent))])
    assert res.exit_code == 0, res.output
    golden = _golden(problem)
    if update_golden:
        golden.write_text(res.stdout, encoding="utf-8")
        return
    if not golden.exists():
        golden.write_text(res.stdout, encoding="utf-8")
        pytest.fail(f"created {golden.name}; review and commit it")
    want = golden.read_text(encoding="utf-8")
    if res.stdout != want:
        problem.with_suffix(".obtained.sim.out").write_text(res.stdout, encoding="utf-8")
    assert res.stdout == want


def test_json_output_follows_the_schema():
    from importlib.resources import files

    import jsonschema

    schema = json.loads(files("momentum_cli").joinpath(
        "schema/momentum-simulation.schema.json").read_text())
    paths = [str(p) for p in SIM_EXAMPLES + SEEDS]
    res = runner.invoke(app, ["simulate", "--json", *paths])
    assert res.exit_code == 0, res.output
    doc = json.loads(res.stdout)
    jsonschema.validate(doc, schema)
    assert [s["status"] for s in doc["simulations"]] == ["solved"] * len(paths)
    bad = runner.invoke(app, ["simulate", "--json", str(EXAMPLES / "seed_oblique_particles.mom")])
    assert bad.exit_code == 1
    jsonschema.validate(json.loads(bad.stdout), schema)


def test_csv_holds_the_time_series(tmp_path):
    out = tmp_path / "series.csv"
    res = runner.invoke(app, ["simulate", "--plain", "--csv", str(out),
                              str(EXAMPLES / "simulate/ball_bounces.mom")])
    assert res.exit_code == 0, res.output
    rows = list(csv.DictReader(io.StringIO(out.read_text())))
    assert list(rows[0])[:4] == ["t", "ball.x", "ball.y", "ball.angle"]
    ts = [float(r["t"]) for r in rows]
    assert ts == sorted(ts) and ts[0] == 0.0
    assert min(float(r["ball.y"]) for r in rows) == pytest.approx(0.02, abs=1e-12)
    E = [float(r["energy"]) - float(r["work"]) for r in rows]
    assert max(E) <= E[0] * (1 + 1e-12)  # impacts only take energy away


def test_plot_needs_the_extra_or_draws(tmp_path):
    target = tmp_path / "run.png"
    res = runner.invoke(app, ["simulate", "--plain", "--plot", str(target),
                              str(EXAMPLES / "simulate/ball_bounces.mom")])
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        assert res.exit_code == 2 and "matplotlib" in res.output
        return
    assert res.exit_code == 0 and target.read_bytes()[:4] == b"\x89PNG"


@pytest.mark.parametrize("rtol", [1e-5, 1e-10])
def test_double_pendulum_holds_its_pin_and_conserves_energy(rtol):
    from momentum_cli.sim.drift import residuals
    from momentum_cli.sim.dynamics import Frame
    from momentum_cli.sim.forces import Phase, energy, kinetic

    res = run_file(EXAMPLES / "simulate/double_pendulum.mom", rtol=rtol)
    model, n = res.model, res.model.n
    assert [b.size for b in model.bodies] == [1, 3]  # upper: its angle; lower: free + pin
    tol = max(rtol, 1e-9) * model.length_scale
    frames = [Frame(model, y[:n], y[n:2 * n]) for y in res.states]
    worst = max(max(abs(c) for c in residuals(model, Phase(), f, {})) for f in frames)
    assert worst <= tol * (1 + 1e-6)
    E0 = energy(model, frames[0])
    scale = max(kinetic(model, f) for f in frames)  # released at the zero of potential
    assert max(abs(energy(model, f) - E0) for f in frames) <= 10 * rtol * scale


def test_bench_compares_with_solve_at_each_tolerance():
    from momentum_cli.sim.bench import cases
    from momentum_cli.sim.bench import run as bench_run

    found = [c for c in cases(str(EXAMPLES.parent)) if "pendulum" in c[0]]
    rows = bench_run(found, repeat=1, rtols=(1e-4, 1e-10), steps=(0.05,))
    assert [r.setting for r in rows] == ["default: closed forms, rtol 1e-9",
                                         "integrated, rtol 1e-04", "integrated, rtol 1e-10",
                                         "integrated, dt 0.05 s"]
    assert rows[0].error < 1e-9 and rows[2].error < rows[1].error  # degrees
    assert all(r.seconds > 0 and r.unit == "deg" for r in rows)


def test_progress_is_reported_with_the_stop_time():
    calls = []
    text = (EXAMPLES / "simulate/double_pendulum.mom").read_text()
    simulate(build(parse(Source("d.mom", text))), progress=lambda t, end: calls.append((t, end)))
    assert calls and all(end == 3.0 and 0 <= t <= 3.0 for t, end in calls)
    assert calls[-1][0] == 3.0 and [t for t, _ in calls] == sorted(t for t, _ in calls)


def test_elliptic_functions_agree_with_scipy():
    """Our plain-Python Jacobi functions, F(phi|m) and K(m) (no scipy import at run time)
    against scipy.special, over swings near and far from going over the top."""
    import random

    from scipy.special import ellipj as sj
    from scipy.special import ellipk as sK
    from scipy.special import ellipkinc as sF

    from momentum_cli.sim.elliptic import ellipj, ellipk, ellipkinc, root

    rng = random.Random(7)
    for _ in range(2000):
        m = rng.choice([rng.random(), rng.random() * 1e-6, 1 - rng.random() * 1e-6])
        u = rng.uniform(-60, 60)
        ours, ref = ellipj(u, m), sj(u, m)
        assert abs(ours[0] - ref[0]) < 5e-14 and abs(ours[1] - ref[1]) < 5e-14
        assert abs(ours[2] - ref[2]) < 5e-12 and abs(ours[3] - ref[3]) < 5e-14 * (1 + abs(u))
        phi = rng.uniform(-math.pi / 2, math.pi / 2)
        assert ellipkinc(phi, m) == pytest.approx(sF(phi, m), rel=5e-15, abs=1e-300)
        assert ellipk(m) == pytest.approx(sK(m), rel=5e-15)
    assert root(lambda x: math.cos(x) - x, 0.0, 1.0) == pytest.approx(0.7390851332151607,
                                                                      rel=1e-15)


def test_rod_end_strikes_a_wheel_with_friction():
    res = run_file(EXAMPLES / "simulate/rod_end_strikes_wheel.mom")
    (hit,) = impacts(res)
    assert hit.t == pytest.approx((1.5 - 0.5 - math.sqrt(0.2 ** 2 - 0.1 ** 2)) / 2, rel=1e-12)
    p = [1 * hit.after["stick"][k] + 2 * hit.after["wheel"][k] for k in (0, 1)]
    assert p == pytest.approx([2.0, 0.0], abs=1e-12)  # no external impulse on the table
    jn, jt = hit.impulses["J_n[stick.end(+)-wheel]"], hit.impulses["J_t[stick.end(+)-wheel]"]
    assert abs(jt) == pytest.approx(0.2 * jn, rel=1e-12) and "slides" in hit.note
    assert hit.energy_lost > 0


def test_a_given_normal_between_round_bodies_keeps_both_radii():
    """Two spheres (r = 0.1 m and 0.2 m) on a line, the contact normal given: they touch
    when their centres are 0.3 m apart, 0.7 m of closing at 2 m/s."""
    res = run("""
body a: sphere(mass = 1 kg, radius = 0.1 m)
body b: sphere(mass = 1 kg, radius = 0.2 m)
state 1: a.pos = (0, 0), b.pos = (1 m, 0), a.v = (2 m/s, 0), b at rest, a.omega = 0
simulate from 1:
    contact a with b normal (-1, 0): restitution 1
    until 1 impacts
""")
    (hit,) = impacts(res)
    assert hit.t == pytest.approx(0.7 / 2, rel=1e-12)
    assert hit.after["a"][0] == pytest.approx(0.0, abs=1e-12)  # equal masses, e = 1: swap
    assert hit.after["b"][0] == pytest.approx(2.0, rel=1e-12)
