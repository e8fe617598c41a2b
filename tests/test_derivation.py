"""The derivation reads like a textbook's: system statements, the parallel-axis step,
state indices, fully numeric lines, direction words, the reader's units, --steps and
the pager. Expected numbers come from closed forms written here."""
from __future__ import annotations

import io
import math
import re
import sys

import pytest
from conftest import EXAMPLES
from typer.testing import CliRunner

from momentum_cli.cli import app
from momentum_cli.numbers import fmt_num
from momentum_cli.pager import paged, should_page, show
from momentum_cli.run import read_source, solve_source
from momentum_cli.source import Source

runner = CliRunner()
SEEDS = sorted(EXAMPLES.glob("seed_*.mom"))
US = [EXAMPLES / "us_rod_center_of_percussion.mom", EXAMPLES / "us_railcars_couple.mom"]


def report(path, units: str = "file"):
    res = solve_source(read_source(str(path)), units=units)
    assert res.report is not None, res.diagnostics
    return res.report


def report_text(text: str, units: str = "file"):
    res = solve_source(Source("t.mom", text), units=units)
    assert res.report is not None, res.diagnostics
    return res.report


def plain(args) -> str:
    res = runner.invoke(app, ["solve", "--plain", *args])
    assert res.exit_code == 0, res.output
    return res.stdout


@pytest.fixture(scope="module")
def every_report():
    """Every example that solves, with its report (about 5 s)."""
    out = []
    for p in sorted(EXAMPLES.glob("*.mom")):
        res = solve_source(read_source(str(p)))
        if res.report is not None:
            out.append((p.name, res.report))
    assert len(out) > 50
    return out


# ---- the system statements -----------------------------------------------------------------
def test_bodies_locking_together_state_the_system_momentum():
    rep = report(EXAMPLES / "seed_plastic_collision.mom")
    system = rep.transitions[0]["system"]
    xs = [s for s in system if s["kind"] == "linear" and "along x" in s["principle"]]
    assert xs, system
    s = xs[0]
    assert s["symbolic"] == "m_A*A.vx@1 + m_B*B.vx@1 = (m_A + m_B)*vx'@2"
    assert s["numeric"] == "2*3 + 3*0 = (2 + 3)*vx'@2"
    v = (2 * 3 + 3 * 0) / (2 + 3)  # the system's momentum over its mass
    assert s["result"] == [f"vx'@2 = {fmt_num(v)} m/s: the bodies move together"]
    text = plain([str(EXAMPLES / "seed_plastic_collision.mom")])
    assert "(m_A + m_B)*vx'@2" in text and "body by body:" in text


def test_bodies_that_separate_state_the_sum_of_momenta():
    rep = report(EXAMPLES / "seed_billiards_elastic.mom")
    laws = [s for t in rep.transitions for s in t["system"] if s["kind"] == "linear"]
    assert laws
    for s in laws:
        assert "'" not in s["symbolic"]  # they do not move together
        lhs, rhs = s["symbolic"].split(" = ")
        assert lhs.count("m_") == rhs.count("m_") >= 2


def test_a_pinned_rod_takes_moments_about_the_pin_with_the_parallel_axis_step():
    m, L, d_hit, u, mb = 4.0, 1.2, 0.9, 6.0, 0.5
    rep = report_text(f"""
body rod: rod(mass = {m} kg, length = {L} m)
body ball: particle(mass = {mb} kg)
point O = rod.end(-)
point P = rod at ({d_hit - L / 2} m, 0)
pin O to ground
state 1: rod.angle = -90 deg, rod at rest, ball.v = ({u} m/s, 0)
state 2
impact 1 -> 2:
    contact hit: P with ball normal (1, 0): restitution 1, smooth
find rod.omega@2, J_n[hit]@1->2
""")
    pins = [s for t in rep.transitions for s in t["system"] if s["kind"] == "pin"]
    assert len(pins) == 1
    s = pins[0]
    I_G, d = m * L**2 / 12, L / 2
    I_O = I_G + m * d**2
    assert math.isclose(I_O, m * L**2 / 3)  # the closed form of a rod about its end
    f = fmt_num
    assert s["steps"][0].startswith(f"I_O = I_G + m*d^2 = {f(I_G)} + {f(m)}*{f(d)}^2 = "
                                    f"{f(I_O)} kg*m^2")
    assert s["symbolic"].startswith("I_O*(rod.omega@2 - rod.omega@1) = ")
    assert "Jx[O]" not in s["symbolic"] and "Jy[O]" not in s["symbolic"]
    # the statement holds with the solved values: I_O w2 = d_hit J (J at P, to the right,
    # d_hit below O: counterclockwise)
    ans = {a["name"]: a["si_value"] for a in rep.answers}
    assert math.isclose(I_O * ans["rod.omega@2"], d_hit * ans["J_n[hit]@1->2"], rel_tol=1e-9)


def test_energy_steps_carry_their_state_indices():
    rep = report(EXAMPLES / "seed_pendulum_wall.mom")
    t = [t for t in rep.transitions if t["kind"] == "energy" and t["before"] == "3"][0]
    assert t["equations"][0].principle == "work-energy: T3 + V3 + U34 = T4 + V4"
    assert any("U34" in w for w in t["why"])
    first = [t for t in rep.transitions if t["kind"] == "energy" and t["before"] == "1"][0]
    assert first["equations"][0].principle.endswith("T1 + V1 + U12 = T2 + V2")


# ---- numeric lines, round-off, direction words ------------------------------------------------
NAME = re.compile(r"[A-Za-z_][\w.]*(?:\[[^\]]*\])?(?:@[\w>\-]+)")


def test_numeric_lines_hold_no_solved_unknown_but_their_own(every_report):
    bad = []
    for name, rep in every_report:
        solved = {u["name"] for u in rep.unknowns}
        rows = [r for t in rep.transitions for r in t["equations"]]
        rows += [r for rs in rep.other_equations.values() for r in rs]
        for r in rows:
            if "integrated" in r.symbolic:
                continue
            left = (set(NAME.findall(r.numeric)) & solved) - set(r.solves)
            if left:
                bad.append(f"{name} ({r.index + 1}): {sorted(left)} in {r.numeric}")
    assert not bad, "\n".join(bad[:10])


def test_no_round_off_is_an_answer(every_report):
    for name, rep in every_report:
        for a in rep.answers:
            v = a["si_value"]
            assert v is None or v == 0 or abs(v) > 1e-12, (name, a)


def test_direction_words_follow_the_sign():
    rep = report(EXAMPLES / "seed_rod_drop_rough.mom")
    way = {a["name"]: (a["si_value"], a["direction"]) for a in rep.answers}
    v, w = way["rod.omega@3"]
    assert (v < 0) == (w == "clockwise") and w in ("clockwise", "counterclockwise")
    v, w = way["rod.vy@3"]
    assert (v < 0) == (w == "downward")
    v, w = way["rod.vx@3"]
    assert w == ("to the right" if v > 0 else "to the left")
    # the US example in closed form: the bar (6 lb, 3 ft) about its pin has an effective
    # mass I_O/d^2 at the struck point (d = 2 ft); restitution e = 0.5 along the line
    g, mb, e, u, d = 32.2, 0.5 / 32.2, 0.5, 40.0, 2.0
    m_eff = (6 / g) * 3.0**2 / 3 / d**2
    vb = (mb * u - e * u * m_eff) / (mb + m_eff)
    w = (vb + e * u) / d
    assert vb < 0 < w
    text = plain([str(EXAMPLES / "us_rod_center_of_percussion.mom")])
    assert f"ball.vx@2 = {fmt_num(vb)} ft/s (to the left)" in text
    assert f"bar.omega@2 = {fmt_num(w)} rad/s (counterclockwise)" in text


# ---- the reader's units ---------------------------------------------------------------------
@pytest.mark.parametrize("path", US, ids=lambda p: p.stem)
def test_a_us_problem_reads_in_us_units(path):
    for text in (plain([str(path)]), plain(["--steps", "brief", str(path)])):
        assert "kg" not in text and "m/s" not in text and " N*s" not in text
        assert "ft/s" in text and "lb" in text
    full = plain([str(path)])
    assert "slug" in full and "32.2 ft/s^2" in full and "Knowns (US customary)" in full


def test_us_masses_and_numbers_are_converted():
    text = plain([str(EXAMPLES / "us_railcars_couple.mom")])
    assert f"A     particle  {fmt_num(30000 / 32.2)}" in text  # W/g in slug
    assert f"{fmt_num(30000 / 32.2)}*(A.vx@2 - 4) = -J_n[A-B]@1->2" in text


def test_units_si_and_find_in_unit_wins():
    text = plain(["--units", "si", str(EXAMPLES / "us_rod_center_of_percussion.mom")])
    assert "Knowns (SI)" in text and "kg" in text
    assert "ball.vx@2 = -14 ft/s" in text  # `find ball.vx@2 in ft/s`
    assert f"0.226613*(ball.vx@2 - {fmt_num(40 * 0.3048)})" in text


def test_json_numbers_stay_si():
    import json

    res = runner.invoke(app, ["solve", "--json", str(EXAMPLES / "us_railcars_couple.mom")])
    doc = json.loads(res.stdout)["results"][0]
    a = {x["name"]: x for x in doc["answers"]}
    assert math.isclose(a["A.vx@2"]["si_value"], 2.4 * 0.3048)
    assert a["A.vx@2"]["unit"] == "ft/s" and math.isclose(a["A.vx@2"]["value"], 2.4)
    u = {x["name"]: x for x in doc["unknowns"]}
    assert u["A.vx@2"]["unit"] == "m/s"


def test_degrees_typed_are_shown_in_degrees():
    text = plain([str(EXAMPLES / "seed_pendulum_wall.mom")])
    assert "pendulum.angle = -90 deg" in text and "sin(-90 deg)" in text
    assert "1.5708" not in text
    rad = plain(["--units", "si", str(EXAMPLES / "seed_pendulum_wall.mom")])
    assert "sin(-1.5708)" in rad


# ---- length control and the pager -----------------------------------------------------------
@pytest.mark.parametrize("path", SEEDS + US, ids=lambda p: p.stem)
def test_brief_fits_about_one_screen(path):
    brief = plain(["--steps", "brief", str(path)])
    full = plain([str(path)])
    n = brief.count("\n")
    assert n <= 64, n  # about one screen, the impulse diagram included
    assert n < full.count("\n")
    assert "Answers" in brief and "Solving, block by block" not in brief


def test_brief_is_the_terminal_default_and_plain_keeps_full():
    path = str(EXAMPLES / "seed_disk_wall.mom")
    assert "Solving, block by block" in plain([path])
    res = runner.invoke(app, ["solve", "--format", "rich", "--no-pager", path])
    assert res.exit_code == 0 and "Answers" in res.stdout
    assert "Solving, block by block" not in res.stdout
    res = runner.invoke(app, ["solve", "--format", "rich", "--steps", "full", path])
    assert "Solving, block by block" in res.stdout


class _Tty(io.StringIO):
    def isatty(self):
        return True


def test_pager_never_when_piped(monkeypatch, tmp_path):
    marker = tmp_path / "paged"
    monkeypatch.setenv("PAGER", f"{sys.executable} -c \"open(r'{marker}', 'w').write('x')\"")
    long = "line\n" * 500
    assert not should_page(long, io.StringIO())  # a pipe or a file
    assert should_page(long, _Tty(), rows=24) and not should_page("a\n", _Tty(), rows=24)
    out = io.StringIO()
    show(long, out)
    assert out.getvalue() == long and not marker.exists()
    # the CLI's stdout under a runner is not a terminal: printed as is
    res = runner.invoke(app, ["solve", "--plain", str(EXAMPLES / "seed_pendulum_wall.mom")])
    assert res.stdout.count("\n") > 100 and not marker.exists()
    with paged(enabled=True):  # stdout is not a terminal here: nothing is captured
        pass
    assert not marker.exists()


def test_pager_runs_for_a_long_terminal_output(monkeypatch, tmp_path):
    got = tmp_path / "got"
    monkeypatch.setenv("PAGER", f"{sys.executable} -c \"import sys; "
                       f"open(r'{got}', 'w').write(sys.stdin.read())\"")
    monkeypatch.setenv("TERM", "xterm")
    long = "line\n" * 500
    show(long, _Tty())
    assert got.read_text() == long
    monkeypatch.setenv("PAGER", "cat")  # cat: no pager, written straight
    out = _Tty()
    show(long, out)
    assert out.getvalue() == long


def test_the_readme_sample_is_what_the_program_prints():
    from conftest import ROOT

    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    cmd = "momentum solve --plain --steps brief examples/seed_plastic_collision.mom"
    sample = re.search(re.escape(cmd) + r"`:\n\n```text\n(.*?)```", readme, flags=re.S)
    assert sample, "the README shows the brief derivation of seed_plastic_collision"
    assert sample.group(1) == plain(["--steps", "brief",
                                     str(EXAMPLES / "seed_plastic_collision.mom")]).replace(
        str(EXAMPLES / "seed_plastic_collision.mom"), "examples/seed_plastic_collision.mom")


@pytest.mark.parametrize("path", SEEDS, ids=lambda p: p.stem)
def test_every_seed_converts_to_us_units(path):
    """Every bare number of every line takes the dimension its place needs (lever arms
    in ft, inertias in slug*ft^2): no line falls back to SI."""
    text = plain(["--units", "us", str(path)])
    assert "(SI)" not in text and "kg" not in text and " m/s" not in text


def test_a_lever_arm_converts_to_feet():
    text = plain(["--units", "us", str(EXAMPLES / "seed_pendulum_wall.mom")])
    ft = 0.3048
    # the pin law: I_O (w3 - w2) = (2 m) J_n, with I_O in slug*ft^2 and the arm in ft
    assert f"= {fmt_num(2 / ft)}*J_n[B]@2->3" in text
    slug_ft2 = 4.4482216152605 / ft * ft**2  # slug = lbf s^2/ft
    I_O = 4 * 2**2 / 3 + (2 / 5 * 10 * 0.3**2 + 10 * 2**2)  # rod about its end + sphere
    assert f"{fmt_num(I_O / slug_ft2)}*(pendulum.omega@3" in text


def test_a_body_with_a_pinned_one_conserves_angular_momentum_about_the_pin():
    """Ballistic pendulum: m_b v_b d = I_O w2 + m_b v_b2 d, with I_O of rod + block
    about O (the bullet strikes d = L below O)."""
    rep = report(EXAMPLES / "ballistic_pendulum.mom")
    laws = [s for t in rep.transitions for s in t["system"] if s["kind"] == "pin-system"]
    assert len(laws) == 1
    s = laws[0]
    L, m_rod, m_blk, a, mb, u = 1.5, 2.0, 6.0, 0.2, 0.03, 500.0
    I_O = m_rod * L**2 / 3 + m_blk * a**2 / 6 + m_blk * L**2  # the block: m (a^2 + a^2)/12
    f = fmt_num
    assert s["symbolic"] == ("I_O*pendulum.omega@1 + m_bullet*1.5*bullet.vx@1 = "
                             "I_O*pendulum.omega@2 + m_bullet*1.5*bullet.vx@2")
    assert s["numeric"] == (f"{f(I_O)}*0 + {f(mb)}*{f(L)}*{f(u)} = "
                            f"{f(I_O)}*pendulum.omega@2 + {f(mb)}*{f(L)}*bullet.vx@2")
    # the parallel-axis step is shown once in the transition (the pin's own law has it)
    steps = [x for t in rep.transitions for y in t["system"] for x in y["steps"]]
    assert len(steps) == 1
