"""`momentum sweep`: designs, the batched solve against the scalar solve and closed forms.

Every expected number comes from outside the batch: the scalar `solve` of the same
variant written out (`--set`, or the file with the number replaced), or a closed form
derived here (a head-on collision as a function of e; a particle on a rough wall
that sticks or slides).
"""
from __future__ import annotations

import glob
import math
import os
import re

import numpy as np
import pytest
from typer.testing import CliRunner

from momentum_cli import syntax as S
from momentum_cli.cli import app
from momentum_cli.run import read_source, solve_source
from momentum_cli.scene import _Builder
from momentum_cli.source import Source
from momentum_cli.sweep.batch import SweepError, solve_batch
from momentum_cli.sweep.output import write_csv
from momentum_cli.sweep.spec import SpecError, parse_design
from momentum_cli.units import si_label

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
EX = os.path.join(ROOT, "examples")
runner = CliRunner()


def _close(got, want, scale=1.0, rel=1e-9):
    return abs(got - want) <= rel * abs(want) + 1e-12 * scale


# ---- designs ---------------------------------------------------------------------------
def test_grid_product_last_fastest():
    d = parse_design(["a=0..1:3", "b=10..20:2"], [], None, None)
    c = d.columns()
    assert d.size == 6
    assert c["a"].tolist() == [0, 0, 0.5, 0.5, 1, 1]
    assert c["b"].tolist() == [10, 20, 10, 20, 10, 20]


def test_grid_units_to_si():
    d = parse_design(["h=50..150:3 cm"], [], None, None)
    assert np.allclose(d.columns()["h"], [0.5, 1.0, 1.5])
    assert d.params[0].dim == (0, 1, 0)
    d = parse_design(["v=36 km/h..72 km/h:2"], [], None, None)
    assert np.allclose(d.columns()["v"], [10.0, 20.0])


def test_monte_carlo_seeded_and_distributed():
    spec = ["m~normal(2000 gram, 50 gram)", "e~uniform(0.5, 0.7)", "k~triangular(1, 2, 4)",
            "L~lognormal(3 m, 0.3 m)"]
    d = parse_design([], spec, 20000, 7)
    a, b = d.columns(), parse_design([], spec, 20000, 7).columns()
    assert all(np.array_equal(a[k], b[k]) for k in a)
    other = parse_design([], spec, 20000, 8).columns()
    assert not np.array_equal(a["e"], other["e"])
    se = 1 / math.sqrt(20000)
    assert abs(a["m"].mean() - 2.0) < 4 * 0.05 * se and abs(a["m"].std() - 0.05) < 0.002
    assert a["e"].min() >= 0.5 and a["e"].max() <= 0.7
    assert a["k"].min() >= 1 and a["k"].max() <= 4
    assert abs(a["k"].mean() - 7 / 3) < 4 * 0.63 * se  # (lo + mode + hi) / 3
    assert (a["L"] > 0).all() and abs(a["L"].mean() - 3) < 4 * 0.3 * se
    assert abs(a["L"].std() - 0.3) < 0.02


def test_grid_times_samples():
    d = parse_design(["e=0..1:3"], ["m~uniform(1 kg, 2 kg)"], 4, 1)
    c = d.columns()
    assert d.size == 12 and c["e"].tolist() == [0] * 4 + [0.5] * 4 + [1] * 4


@pytest.mark.parametrize("vary, sample, count, words", [
    (["e=1..0:x"], [], None, "not a whole number"),
    (["e=1..0:3"], [], None, "LO must not exceed HI"),
    (["e=0..1"], [], None, "NAME=LO..HI:N"),
    (["e=0 kg..1 m:3"], [], None, "different dimensions"),
    ([], ["m~gauss(1, 2)"], 3, "unknown distribution"),
    ([], ["m~normal(1)"], 3, "takes 2 values"),
    ([], ["m~normal(1 kg, -1 kg)"], 3, "must not be negative"),
    ([], ["m~normal(1 kg, 1 kg)"], None, "--count"),
    ([], ["m~uniform(1 furlong, 2)"], 3, "furlong"),
    ([], [], None, "at least one"),
])
def test_bad_specs_are_one_line_errors(vary, sample, count, words):
    with pytest.raises(SpecError) as exc:
        parse_design(vary, sample, count, None)
    assert words in str(exc.value) and "\n" not in str(exc.value)


def test_cli_bad_spec_exit_2_one_line():
    r = runner.invoke(app, ["sweep", os.path.join(EX, "seed_rod_drop_smooth.mom"),
                            "--vary", "e=1..0:x"])
    assert r.exit_code == 2
    lines = [x for x in r.output.splitlines() if x.strip()]
    assert len(lines) == 1 and "not a whole number" in lines[0]
    assert "Traceback" not in r.output


def test_cli_unknown_name_and_wrong_dimension(tmp_path):
    r = runner.invoke(app, ["sweep", os.path.join(EX, "seed_rod_drop_smooth.mom"),
                            "--vary", "q=0..1:3"])
    assert r.exit_code == 2 and "no `let q`" in r.output
    r = runner.invoke(app, ["sweep", os.path.join(EX, "seed_rod_drop_smooth.mom"),
                            "--vary", "rod.y@1=0.5..2:3"])
    assert r.exit_code == 2 and "length" in r.output and len(r.output.splitlines()) == 1


# ---- a closed form: two particles collide head on ---------------------------------------
COLLISION = """problem "Two particles collide head on"
let e = 0.5
let m1 = 2 kg
body a: particle(mass = m1)
body b: particle(mass = 3 kg)
state 1 "before": a.v = (4 m/s, 0), b.v = (-1 m/s, 0)
state 2 "after"
impact 1 -> 2:
    contact a with b normal (-1, 0): restitution e, smooth
find a.vx@2, b.vx@2, T_lost@1->2
"""


def test_collision_closed_form(tmp_path):
    path = tmp_path / "collide.mom"
    path.write_text(COLLISION)
    d = parse_design(["e=0..1:11"], ["m1~uniform(1 kg, 5 kg)"], 5, 3)
    cols = d.columns()
    r = solve_batch(str(path), cols, {p.name: p.dim for p in d.params})
    e, m1, m2, v1, v2 = cols["e"], cols["m1"], 3.0, 4.0, -1.0
    va = (m1 * v1 + m2 * v2 - m2 * e * (v1 - v2)) / (m1 + m2)
    vb = (m1 * v1 + m2 * v2 + m1 * e * (v1 - v2)) / (m1 + m2)
    lost = 0.5 * m1 * m2 / (m1 + m2) * (1 - e * e) * (v1 - v2) ** 2
    assert np.allclose(r.answers["a.vx@2"], va, rtol=1e-12, atol=1e-12)
    assert np.allclose(r.answers["b.vx@2"], vb, rtol=1e-12, atol=1e-12)
    assert np.allclose(r.answers["T_lost@1->2"], lost, rtol=1e-10, atol=1e-12)
    # e = 0 and e = 1 fold terms away in the structure: those go through the scalar solve
    ok = r.status == "ok"
    assert ok.sum() >= 45 and all(s != "" for s in r.status)
    assert not any(s.startswith("error") for s in r.status)


# ---- the batch against the scalar solve, over every example with `let` constants --------
def _lets(path):
    src = read_source(path)
    doc = S.parse(src)
    lets = [s.name for s in doc.statements if isinstance(s, S.Let)]
    if not lets:
        return src, {}
    b = _Builder(doc)
    b.run()
    return src, {n: b.constants[n] for n in lets if not b.constants[n].is_vector}


LET_FILES = [p for p in sorted(glob.glob(os.path.join(EX, "*.mom"))) if _lets(p)[1]]


@pytest.mark.parametrize("path", LET_FILES, ids=os.path.basename)
def test_batch_equals_scalar_solve_with_set(path):
    """Two random variants (every scalar `let` moved by up to 5 %): the batch's answers
    are the scalar solve's with `--set`, to the solve's rounding."""
    src, consts = _lets(path)
    rng = np.random.default_rng(abs(hash(os.path.basename(path))) % 2**32)
    base = {n: float(q.value.value) for n, q in consts.items()}
    dims = {n: q.dim for n, q in consts.items()}
    cols = {n: np.array([v * (1 + 0.05 * rng.uniform(-1, 1)) for _ in range(2)]) if v else
            rng.uniform(0.01, 0.1, 2) for n, v in base.items()}
    r = solve_batch(path, cols, dims)
    for i in range(2):
        sets = tuple((n, repr(float(cols[n][i])) + (f" {si_label(dims[n])}"
                                                     if si_label(dims[n]) else ""))
                     for n in cols)
        res = solve_source(src, overrides=sets)
        if res.report is None:
            assert r.status[i].startswith("error"), r.status[i]
            continue
        want = {a["name"]: a["value"] for a in res.report.answers}
        scale = max([abs(v) for v in want.values()] + [1.0])
        for name, w in want.items():
            got = r.answers[name][i] / r.display[name][1]
            assert _close(got, w, scale * 10), (name, got, w, r.status[i])


def _with(text: str, pattern: str, new: str) -> str:
    out, n = re.subn(pattern, new, text, count=1)
    assert n == 1, pattern
    return out


def test_given_numbers_without_lets_match_edited_file(tmp_path):
    """The rod dropped on a smooth floor has no `let`: its restitution `e[A]` and drop
    height `rod.y@1` are varied by name; each variant equals the file with those numbers
    written in, solved alone. e = 1 and e = 0 fold terms: solved on their own."""
    path = os.path.join(EX, "seed_rod_drop_smooth.mom")
    text = open(path, encoding="utf-8").read()
    cols = {"e[A]": np.array([0.0, 0.3, 0.62, 1.0]), "rod.y@1": np.array([0.4, 1.0, 1.7, 2.5])}
    r = solve_batch(path, cols, {"e[A]": (0, 0, 0), "rod.y@1": (0, 1, 0)})
    for i in range(4):
        t = _with(text, r"restitution 1,", f"restitution {float(cols['e[A]'][i])!r},")
        t = _with(t, r"rod\.y = 1 m", f"rod.y = {float(cols['rod.y@1'][i])!r} m")
        res = solve_source(Source("v.mom", t))
        assert res.report is not None, [d.message for d in res.diagnostics]
        for a in res.report.answers:
            assert _close(r.answers[a["name"]][i], a["value"], 30.0), (i, a["name"])
    assert r.status[1] == "ok" and r.status[2] == "ok"
    assert r.status[0] != "ok" and r.status[3] != "ok"  # fell back; still right (above)


# ---- friction: stick or slide, variant by variant -----------------------------------------
def test_stick_slide_counted_and_solved():
    """A particle strikes a rough wall at beta = 20 deg from the normal (e = 0.6): it
    sticks where tan(beta) <= mu (1 + e); else it slides and the friction impulse
    mu J_n changes the tangential velocity by mu (1 + e) v_n."""
    path = os.path.join(EX, "wall_oblique_stick.mom")
    mu = np.linspace(0.1, 0.5, 41)
    r = solve_batch(path, {"mu[ball]": mu}, {"mu[ball]": (0, 0, 0)})
    v, beta, e = 8.0, math.radians(20), 0.6
    vn, vt = v * math.cos(beta), -v * math.sin(beta)
    sticks = math.tan(beta) <= mu * (1 + e)
    want_vy = np.where(sticks, 0.0, vt + mu * (1 + e) * vn)
    assert np.allclose(r.answers["ball.vy@2"], want_vy, atol=1e-12)
    assert np.allclose(r.answers["ball.vx@2"], -e * vn, atol=1e-12)
    slid = np.array(["slide" in x for x in r.regimes])
    assert (slid == ~sticks).all() and slid.sum() == 13
    from momentum_cli.sweep.output import summary_text

    text = summary_text(r, "wall")
    assert "13 variants: ball (1->2): slide+" in text
    assert "28 variants: ball (1->2): stick" in text


# ---- output ----------------------------------------------------------------------------
def test_same_seed_gives_identical_csv(tmp_path):
    path = os.path.join(EX, "seed_rod_drop_smooth.mom")
    args = ["sweep", path, "--sample", "e[A]~uniform(0.5, 0.7)",
            "--sample", "rod.y@1~normal(1 m, 0.05 m)", "--count", "300", "--seed", "5"]
    outs = []
    for k in range(2):
        f = tmp_path / f"run{k}.csv"
        r = runner.invoke(app, args + ["--csv", str(f)])
        assert r.exit_code == 0, r.output
        outs.append(f.read_bytes())
    assert outs[0] == outs[1]
    lines = outs[0].decode().splitlines()
    assert lines[0].startswith("e[A],rod.y@1 (m),rod.omega@3 (rad/s),")
    assert lines[0].endswith(",status") and len(lines) == 301
    first = lines[1].split(",")
    assert float(first[0]) == float(repr(float(first[0])))  # repr-exact floats


def test_json_and_jsonl(tmp_path):
    import json

    path = os.path.join(EX, "seed_rod_drop_smooth.mom")
    r = runner.invoke(app, ["sweep", path, "--vary", "e[A]=0.4..0.8:5", "--json"])
    doc = json.loads(r.output)
    assert doc["variants"] == 5 and len(doc["rows"]) == 5
    names = [s["name"] for s in doc["summary"]]
    assert "rod.omega@3" in names
    r = runner.invoke(app, ["sweep", path, "--vary", "e[A]=0.4..0.8:5", "--jsonl"])
    rows = [json.loads(x) for x in r.output.splitlines()]
    assert len(rows) == 5 and rows[0]["e[A]"] == 0.4 and rows[0]["status"] == "ok"


def test_write_csv_to_stream():
    import io

    r = solve_batch(os.path.join(EX, "seed_rod_drop_smooth.mom"),
                    {"e[A]": np.array([0.5, 0.6])})
    buf = io.StringIO()
    write_csv(r, buf)
    assert buf.getvalue().count("\n") == 3


def test_unreadable_file_is_sweep_error(tmp_path):
    with pytest.raises(SweepError):
        solve_batch(str(tmp_path / "missing.mom"), {"e": np.array([1.0])})


def test_parts_with_a_common_base_give_the_same_bits():
    """Solving a design in parts (as Dask does) with the base `choose_base` picks for
    the whole gives the same numbers and statuses as solving it whole."""
    from momentum_cli.sweep.batch import choose_base

    path = os.path.join(EX, "seed_rod_drop_smooth.mom")
    d = parse_design(["e[A]=0..1:21", "rod.y@1=0.5..1.5:3 m"], [], None, None)
    cols = d.columns()
    dims = {p.name: p.dim for p in d.params}
    whole = solve_batch(path, cols, dims)
    base = choose_base(path, cols, dims)
    parts = [solve_batch(path, {k: v[lo:hi] for k, v in cols.items()}, dims, base=base)
             for lo, hi in ((0, 7), (7, 63))]
    for name, arr in whole.answers.items():
        joined = np.concatenate([p.answers[name] for p in parts])
        assert np.array_equal(arr, joined, equal_nan=True), name
    assert whole.status.tolist() == sum((p.status.tolist() for p in parts), [])
    import io

    from momentum_cli.sweep.batch import concat

    a, b = io.StringIO(), io.StringIO()
    write_csv(whole, a)
    write_csv(concat(parts), b)
    assert a.getvalue() == b.getvalue()


RISE = """problem "A ball thrown up: its speed at a height"
gravity 9.81 m/s^2 down
let v0 = 6 m/s
let h = 1 m
body ball: particle(mass = 0.2 kg)
state 1 "thrown": ball.pos = (0, 0), ball.v = (0, v0)
state 2 "at height h": ball.y = h, ball.vx = 0, ball.vy > 0
energy 1 -> 2
find ball.vy@2
"""


def test_energy_roots_and_variants_that_do_not_solve(tmp_path):
    """vy = +sqrt(v0^2 - 2 g h) where the ball gets that high (the hint picks the
    root); where it does not, that variant alone is an error, counted, exit code 1."""
    path = tmp_path / "rise.mom"
    path.write_text(RISE)
    v0 = np.linspace(2, 8, 13)
    h = np.full(13, 1.3)
    r = solve_batch(str(path), {"v0": v0, "h": h})
    reach = v0 ** 2 >= 2 * 9.81 * h
    want = np.sqrt(np.where(reach, v0 ** 2 - 2 * 9.81 * h, np.nan))
    assert np.allclose(r.answers["ball.vy@2"][reach], want[reach], rtol=1e-12)
    assert all(s.startswith("error: no real solution") for s in r.status[~reach])
    assert all(s == "ok" for s in r.status[reach])
    res = runner.invoke(app, ["sweep", str(path), "--vary", "v0=2..8:13 m/s"])
    assert res.exit_code == 1 and "did not solve: no real solution" in res.output


# ---- where the CSV goes ----------------------------------------------------------------------
def test_csv_dash_is_standard_output_and_a_file_is_never_overwritten_silently(tmp_path,
                                                                              monkeypatch):
    monkeypatch.chdir(tmp_path)
    args = ["sweep", os.path.join(EX, "seed_rod_drop_smooth.mom"), "--vary", "e[A]=0.5..1:3"]
    r = runner.invoke(app, args + ["--csv", "-"])
    assert r.exit_code in (0, 1), r.output
    assert r.stdout.startswith("e[A],rod.omega@3 (rad/s),")
    assert not (tmp_path / "-").exists()
    out = tmp_path / "out.csv"
    out.write_text("precious\n", encoding="utf-8")
    r = runner.invoke(app, args + ["--csv", str(out)])
    assert r.exit_code == 2 and "exists; add --force" in r.output
    assert out.read_text(encoding="utf-8") == "precious\n"  # refused before any work
    r = runner.invoke(app, args + ["--csv", str(out), "--force"])
    assert r.exit_code in (0, 1) and out.read_text(encoding="utf-8").startswith("e[A],")
