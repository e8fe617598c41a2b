"""Problem sets as tests: `expect` lines, `momentum test`, `expect --write`, `--set`,
`variants`, `grade` and `--jsonl`.

Expected numbers come from closed forms written here (momentum, angular momentum about
a pin), never from the program's output.
"""
from __future__ import annotations

import csv
import json
import re
import os
import shutil
import xml.etree.ElementTree as ET
from importlib.resources import files

import jsonschema
import pytest
from typer.testing import CliRunner

from momentum_cli.cli import app
from momentum_cli.run import solve_source
from momentum_cli.source import Source
from momentum_cli.syntax import BinOp, Expect, Let, parse

from conftest import EXAMPLES

PSET = EXAMPLES / "problem-set"
runner = CliRunner()

# Two carts couple: v = m_a v0 / (m_a + m_b); T_lost = m_a v0^2 / 2 - (m_a + m_b) v^2 / 2.
CARTS = """problem "Two carts couple"
let v0 = 5 m/s
body a: particle(mass = 2 kg)
body b: particle(mass = 3 kg)
state 1: a.v = (v0, 0), b at rest
state 2: a.vy = 0, b.vy = 0
impact 1 -> 2:
    contact a with b normal (-1, 0): restitution 0, smooth
find a.vx@2, T_lost@1->2
"""


def carts_v(v0=5.0):
    return 2 * v0 / 5


def cli(args):
    return runner.invoke(app, [str(a) for a in args], prog_name="momentum")


def expect_nodes(text):
    return [s for s in parse(Source("t.mom", text)).statements if isinstance(s, Expect)]


def checks_of(text, name="t.mom"):
    return solve_source(Source(name, text)).expects


# ---- the statement ----------------------------------------------------------------------
def test_expect_forms_parse_into_frozen_nodes_with_spans():
    text = CARTS + ("expect a.vx@2 = 2.0 m/s\n"
                    "expect a.vx@2 = 2 m/s ± 0.01 m/s\n"
                    "expect a.vx@2 = 2 m/s +- 0.01\n"
                    "expect a.vx@2 = 2 m/s within 0.5 %\n"
                    "expect error under-determined\n")
    e = expect_nodes(text)
    assert [x.span.line for x in e] == [10, 11, 12, 13, 14]
    assert e[0].tolerance is None and e[0].percent is None
    assert e[1].tolerance.value == 0.01 and e[1].tolerance.unit == "m/s"
    assert e[2].tolerance.value == 0.01 and e[2].tolerance.unit is None  # `+-` split off
    assert e[3].percent.value == 0.5
    assert e[4].error == "under-determined" and e[4].quantity is None
    with pytest.raises(Exception):
        e[0].value = None  # frozen


def test_plus_minus_elsewhere_is_still_a_sum():
    doc = parse(Source("t.mom", "let a = 1 +-2\nlet b = 3 + -1\n"))
    lets = [s for s in doc.statements if isinstance(s, Let)]
    assert all(isinstance(s.value, BinOp) and s.value.op == "+" for s in lets)


@pytest.mark.parametrize("written,half", [("2.0", 0.05), ("2", 0.5), ("2.000", 0.0005),
                                          ("0.20e1", 0.05), ("2.00e0", 0.005), ("20e-1", 0.05)])
def test_tolerance_is_half_a_unit_in_the_last_digit_written(written, half):
    v = carts_v()
    (c,) = checks_of(CARTS + f"expect a.vx@2 = {written} m/s\n")
    assert c.spec.tolerance[0] == pytest.approx(half)
    assert c.met == (abs(v - float(written)) <= half)


def test_expectations_in_other_units_and_explicit_tolerances():
    v = carts_v()
    lost = 0.5 * 2 * 5 ** 2 - 0.5 * 5 * v ** 2
    kmh = v * 3.6
    text = CARTS + (f"expect a.vx@2 = {kmh:.3f} km/h\n"            # met, in km/h
                    f"expect a.vx@2 = {v + 0.02} m/s ± 0.01 m/s\n"  # off by 0.02: not met
                    f"expect a.vx@2 = {v + 0.02} m/s +- 3 cm/s\n"   # met
                    f"expect T_lost@1->2 = {lost * 1.004} J within 0.5 %\n"  # met
                    f"expect T_lost@1->2 = {lost * 1.01} J within 0.5 %\n")  # not met
    got = [c.met for c in checks_of(text)]
    assert got == [True, False, True, True, False]


def test_a_vector_expectation_checks_both_components():
    # head-on, e = 1, equal masses: the velocities swap
    text = """body A: particle(mass = 1 kg)
body B: particle(mass = 1 kg)
state 1: A.v = (3 m/s, 0), B at rest
state 2
impact 1 -> 2:
    contact A with B normal (-1, 0): restitution 1, smooth
find A.v@2
expect B.v@2 = (3.00 m/s, 0)
expect A.v@2 = (0.1 m/s, 0 m/s)
"""
    a, b = checks_of(text)
    assert a.met and a.got == pytest.approx((3.0, 0.0))
    assert not b.met


def test_wrong_dimension_of_an_expectation_is_an_error_at_its_line():
    res = solve_source(Source("t.mom", CARTS + "expect a.vx@2 = 2 kg\n"))
    assert res.status == "error"
    d = res.diagnostics[0]
    assert d.code == "units" and d.span.line == 10


def test_solve_reports_each_expectation_in_plain_and_json(tmp_path):
    f = tmp_path / "carts.mom"
    f.write_text(CARTS + "expect a.vx@2 = 2.00 m/s\nexpect a.vx@2 = 2.5 m/s\n")
    plain = cli(["solve", "--plain", f])
    assert plain.exit_code == 0
    assert re.search(r"expect, line 10: a.vx@2 +ok +met: expected a.vx@2 = 2 \+- 0.005 m/s",
                     plain.stdout)
    assert "not met: expected a.vx@2 = 2.5 +- 0.05 m/s, got 2 m/s (difference -0.5 m/s)" \
        in plain.stdout
    doc = json.loads(cli(["solve", "--json", f]).stdout)
    ex = doc["results"][0]["expectations"]
    assert [e["met"] for e in ex] == [True, False]
    assert ex[1]["difference"] == pytest.approx(0.5) and ex[1]["unit"] == "m/s"


# ---- momentum test ------------------------------------------------------------------------
def test_the_problem_set_and_the_failing_examples_pass():
    r = cli(["test", PSET, EXAMPLES / "hard", "-k", "bad_"])
    # -k keeps the bad_* files only; the problem set has none: run it on its own
    assert r.exit_code == 0, r.stdout
    n_bad = len(list((EXAMPLES / "hard").glob("bad_*.mom")))
    assert r.stdout.strip().splitlines()[-1] == f"{n_bad} passed, 0 failed"
    r = cli(["test", PSET])
    assert r.exit_code == 0, r.stdout
    assert r.stdout.strip().splitlines()[-1] == "13 passed, 0 failed"


def test_a_changed_answer_fails_with_file_and_line_and_exit_1(tmp_path):
    src = (PSET / "p01_carts_couple.mom").read_text()
    assert "expect a.vx@2 = 2.00 m/s" in src
    bad = tmp_path / "p01.mom"
    bad.write_text(src.replace("expect a.vx@2 = 2.00 m/s", "expect a.vx@2 = 2.50 m/s"))
    line = src.splitlines().index("expect a.vx@2 = 2.00 m/s") + 1
    r = cli(["test", tmp_path])
    assert r.exit_code == 1
    assert f"{bad}:{line}: expected a.vx@2 = 2.5 +- 0.005 m/s, got 2 m/s" in r.stdout
    assert r.stdout.strip().splitlines()[-1] == "0 passed, 1 failed"


def test_an_unexpected_error_fails_and_an_expected_one_passes(tmp_path):
    (tmp_path / "a.mom").write_text(CARTS.replace("restitution 0", "restitution ?"))
    (tmp_path / "b.mom").write_text(CARTS.replace("restitution 0", "restitution ?") +
                                    "expect error under-determined\n")
    (tmp_path / "c.mom").write_text(CARTS + "expect error inconsistent\n")
    r = cli(["test", tmp_path])
    assert r.exit_code == 1
    out = r.stdout
    assert "FAIL  " + str(tmp_path / "a.mom") in out and "unexpected error" in out
    assert "PASS  " + str(tmp_path / "b.mom") in out
    assert f"{tmp_path / 'c.mom'}:10: expected error inconsistent, got solved" in out
    assert out.strip().splitlines()[-1] == "1 passed, 2 failed"


def test_usage_errors_exit_2(tmp_path):
    assert cli(["test", tmp_path / "nowhere"]).exit_code == 2
    assert cli(["test", tmp_path]).exit_code == 2  # no *.mom
    (tmp_path / "a.mom").write_text(CARTS)
    assert cli(["test", tmp_path, "-k", "zzz"]).exit_code == 2


def test_junit_xml_is_valid_junit(tmp_path):
    shutil.copy(PSET / "p01_carts_couple.mom", tmp_path / "good.mom")
    (tmp_path / "bad.mom").write_text(CARTS + "expect a.vx@2 = 3 m/s\n")
    xml = tmp_path / "report.xml"
    r = cli(["test", "--junit-xml", xml, tmp_path])
    assert r.exit_code == 1
    root = ET.parse(xml).getroot()  # a real XML parser
    assert root.tag == "testsuites"
    (suite,) = root.findall("testsuite")
    for el in (root, suite):
        assert (el.get("tests"), el.get("failures"), el.get("errors"), el.get("skipped")) == \
            ("2", "1", "0", "0")
        float(el.get("time"))
    cases = suite.findall("testcase")
    assert [c.get("name") for c in cases] == ["bad.mom", "good.mom"]
    for c in cases:
        assert c.get("classname") and float(c.get("time")) >= 0
        assert set(c.attrib) <= {"name", "classname", "time", "file"}
    (fail,) = cases[0].findall("failure")
    assert fail.get("message").startswith(f"{tmp_path / 'bad.mom'}:10: expected a.vx@2 = 3")
    assert not cases[1].findall("failure")
    # pytest's own JUnit reader agrees (the same structure pytest writes)
    assert {child.tag for c in cases for child in c} <= {"failure", "error", "skipped",
                                                         "system-out", "system-err"}


@pytest.fixture(scope="module")
def schemas():
    from referencing import Registry, Resource

    load = lambda n: json.loads(files("momentum_cli").joinpath("schema", n).read_text())  # noqa
    result, test = load("momentum-result.schema.json"), load("momentum-test.schema.json")
    reg = Registry().with_resources([(s["$id"], Resource.from_contents(s))
                                     for s in (result, test)])
    jsonschema.Draft202012Validator.check_schema(test)
    one = lambda s, d: jsonschema.Draft202012Validator({"$ref": f"{s['$id']}#/$defs/{d}"},  # noqa
                                                       registry=reg)
    return one(result, "result"), jsonschema.Draft202012Validator(test, registry=reg), \
        one(test, "file")


def test_test_json_and_jsonl_match_the_schema(tmp_path, schemas):
    _, test_v, file_v = schemas
    shutil.copy(PSET / "p01_carts_couple.mom", tmp_path / "a.mom")
    shutil.copy(PSET / "p12_wrong_principle.mom", tmp_path / "b.mom")
    (tmp_path / "c.mom").write_text(CARTS + "expect a.vx@2 = 3 m/s\n")
    doc = json.loads(cli(["test", "--json", tmp_path]).stdout)
    test_v.validate(doc)
    assert [f["outcome"] for f in doc["files"]] == ["passed", "passed", "failed"]
    assert doc["summary"] == dict(passed=2, failed=1, error=0, skipped=0, total=3)
    lines = cli(["test", "--jsonl", tmp_path]).stdout.splitlines()
    assert len(lines) == 4
    for ln in lines[:3]:
        file_v.validate(json.loads(ln))
    assert json.loads(lines[3]) == dict(type="summary", passed=2, failed=1, error=0,
                                        skipped=0, total=3)


def test_solve_jsonl_prints_one_result_per_line(tmp_path, schemas):
    result_v, _, _ = schemas
    shutil.copy(PSET / "p01_carts_couple.mom", tmp_path / "a.mom")
    shutil.copy(PSET / "p13_missing_restitution.mom", tmp_path / "b.mom")
    r = cli(["solve", "--jsonl", tmp_path / "a.mom", tmp_path / "b.mom"])
    assert r.exit_code == 1
    lines = r.stdout.splitlines()
    assert len(lines) == 2
    for ln in lines:
        result_v.validate(json.loads(ln))
    a, b = (json.loads(x) for x in lines)
    assert a["status"] == "solved" and all(e["met"] for e in a["expectations"])
    assert b["status"] == "error" and b["expectations"][0]["met"]


# ---- momentum expect ----------------------------------------------------------------------
def test_expect_prints_lines_and_never_writes_without_write(tmp_path):
    f = tmp_path / "carts.mom"
    f.write_text(CARTS)
    before = f.stat().st_mtime_ns
    r = cli(["expect", f])
    assert r.exit_code == 0
    assert r.stdout.splitlines() == ["expect a.vx@2 = 2.000 m/s", "expect T_lost@1->2 = 15.00 J"]
    assert f.read_text() == CARTS and f.stat().st_mtime_ns == before


def test_expect_write_changes_only_expect_lines_atomically(tmp_path, monkeypatch):
    text = CARTS.replace("find a.vx@2, T_lost@1->2\n",
                         "find a.vx@2, T_lost@1->2   # asked\n"
                         "expect a.vx@2 = 9 m/s ± 0.1 m/s  # keep me\n"
                         "# a comment\r\n") + "\n\n# end"
    f = tmp_path / "carts.mom"
    f.write_bytes(text.encode())
    os.chmod(f, 0o640)
    replaced = []
    real_replace = os.replace

    def spy(src, dst):
        replaced.append((os.path.dirname(os.path.abspath(src)), os.path.abspath(dst)))
        return real_replace(src, dst)

    monkeypatch.setattr(os, "replace", spy)
    r = cli(["expect", "--write", f])
    assert r.exit_code == 0, r.stdout
    assert replaced == [(str(tmp_path), str(f))]  # a temporary file in the same folder
    new = f.read_bytes().decode()
    old_lines, new_lines = text.splitlines(keepends=True), new.splitlines(keepends=True)
    kept = [ln for ln in new_lines if not ln.startswith("expect ")]
    assert kept == [ln for ln in old_lines if not ln.startswith("expect ")]
    assert "expect a.vx@2 = 2.000 m/s ± 0.1 m/s  # keep me\n" in new_lines
    assert "expect T_lost@1->2 = 15.00 J\n" in new_lines
    assert oct(f.stat().st_mode & 0o777) == oct(0o640)
    assert "+expect T_lost@1->2 = 15.00 J" in r.stdout  # the diff is shown
    assert not [p for p in os.listdir(tmp_path) if p != "carts.mom"]  # no temp left
    # refreshed again: nothing to change
    assert "up to date" in cli(["expect", "--write", f]).stdout


def test_expect_write_on_a_read_only_file_is_one_clear_error(tmp_path):
    f = tmp_path / "carts.mom"
    f.write_text(CARTS)
    os.chmod(f, 0o444)
    try:
        r = runner.invoke(app, ["expect", "--write", str(f)], prog_name="momentum")
        assert r.exit_code == 2
        err = r.stderr.strip().splitlines()
        assert err == [f"{f}: cannot write: the file is read-only (nothing changed)"]
        assert f.read_text() == CARTS
        assert os.listdir(tmp_path) == ["carts.mom"]
    finally:
        os.chmod(f, 0o644)


def test_expect_write_records_an_expected_error(tmp_path):
    f = tmp_path / "e.mom"
    f.write_text(CARTS.replace("restitution 0", "restitution ?"))
    assert cli(["expect", "--write", f]).exit_code == 0
    assert f.read_text().endswith("find a.vx@2, T_lost@1->2\nexpect error under-determined\n")
    assert cli(["test", f]).exit_code == 0


# ---- --set --------------------------------------------------------------------------------
def test_set_overrides_a_let_in_solve_test_expect(tmp_path):
    f = tmp_path / "carts.mom"
    f.write_text(CARTS + "expect a.vx@2 = 2.00 m/s\n")
    r = cli(["solve", "-q", "--set", "v0=10 m/s", f])
    assert r.stdout.splitlines()[0] == f"a.vx@2 = {carts_v(10):g} m/s"
    assert cli(["test", f]).exit_code == 0
    r = cli(["test", "--set", "v0=36 km/h", f])
    assert r.exit_code == 1 and "got 4 m/s" in r.stdout
    assert cli(["expect", "--set", "v0=2.5 m/s", f]).stdout.splitlines()[0] == \
        "expect a.vx@2 = 1.000 m/s"


def test_set_with_an_unknown_name_is_a_usage_error_with_did_you_mean(tmp_path):
    f = tmp_path / "carts.mom"
    f.write_text(CARTS)
    r = runner.invoke(app, ["solve", "--set", "vo=3 m/s", str(f)], prog_name="momentum")
    assert r.exit_code == 2
    assert "has no `let vo`; did you mean 'v0'?" in r.output
    assert runner.invoke(app, ["solve", "--set", "v0", str(f)]).exit_code == 2


def test_set_in_simulate():
    r = cli(["simulate", "--plain", "--set", "h=1 m", EXAMPLES / "simulate" / "ball_bounces.mom"])
    assert r.exit_code == 2  # that scene has no `let h`


# ---- variants -----------------------------------------------------------------------------
def test_variants_are_deterministic_and_pass_their_own_expectations(tmp_path):
    key = tmp_path / "key.mom"
    key.write_text(CARTS.replace("let v0 = 5 m/s", "let v0 = 5 m/s   # the speed"))
    outs = []
    for run in ("one", "two"):
        r = cli(["variants", key, "--vary", "v0=4..6", "--count", "3", "--seed", "7",
                 "--out", tmp_path / run])
        assert r.exit_code == 0, r.output
        outs.append({p: (tmp_path / run / p).read_bytes()
                     for p in sorted(os.listdir(tmp_path / run))})
    assert outs[0] == outs[1]
    assert sorted(outs[0]) == ["index.csv", "key-v01.mom", "key-v02.mom", "key-v03.mom"]
    rows = list(csv.DictReader((tmp_path / "one" / "index.csv").open()))
    for row in rows:
        v0 = float(row["v0"].split()[0])
        assert 4 <= v0 <= 6 and len(row["v0"].split()[0].replace(".", "")) == 3
        assert float(row["a.vx@2 (m/s)"]) == pytest.approx(carts_v(v0), rel=1e-3)
        text = outs[0][row["file"]].decode()
        assert f"let v0 = {row['v0']}   # the speed" in text
    assert cli(["test", tmp_path / "one"]).exit_code == 0


# ---- grading ------------------------------------------------------------------------------
# The mistakes written into examples/problem-set/answers.csv, by design (every other
# answer there is the key's value as printed in the problem's comment).
DESIGNED = {
    ("ana", "p02_ball_rebound", "ball.vy@2"): "rounding",       # -6.3 for -6.264
    ("ben", "p02_ball_rebound", "ball.vy@2"): "sign error",     # +6.264
    ("ben", "p04_bullet_block", "block.vx@2"): "unit slip",     # 7.164 (km/h) as m/s
    ("ben", "p11_rod_falls_from_horizontal", "rod.omega@2"): "sign error",
    ("chloe", "p01_carts_couple", "a.vx@2"): "wrong",           # 2.5 m/s
    ("chloe", "p03_pool_head_on", "A.vx@2"): "missing",         # no rows for p03
    ("chloe", "p03_pool_head_on", "B.vx@2"): "missing",
    ("chloe", "p05_rod_struck_at_end", "rod.omega@2"): "missing",  # left blank
    ("dev", "p06_block_pushed", "block.vx@2"): "wrong",         # friction forgotten: 12 m/s
    ("dev", "p07_flywheel", "wheel.omega@2"): "unit slip",      # 611 (rpm) as rad/s
    ("dev", "p08_rocket", "dv"): "rounding",                    # 719 for 719.2
    ("eli", "p02_ball_rebound", "ball.y@4"): "wrong",           # e h instead of e^2 h
}


def test_grade_classifies_every_mistake_of_the_problem_set(tmp_path):
    out = tmp_path / "grades.csv"
    r = cli(["grade", PSET, "--answers", PSET / "answers.csv", "--csv", out, "--format",
             "plain"])
    assert r.exit_code == 0, r.output
    rows = list(csv.DictReader(out.open()))
    got = {(g["student"], g["problem"], g["quantity"]): g["verdict"] for g in rows}
    assert {k: v for k, v in got.items() if v != "right"} == DESIGNED
    assert len({s for s, _, _ in got}) >= 4
    assert set(DESIGNED.values()) | {"right"} == {"right", "rounding", "sign error",
                                                  "unit slip", "wrong", "missing"}
    # an answer in another unit than the key's, converted right, is right
    assert got[("ana", "p04_bullet_block", "block.vx@2")] == "right"       # 7.164 km/h
    assert got[("eli", "p10_ball_thrown_up", "ball.y@2")] == "right"       # 326.2 cm
    doc = json.loads(cli(["grade", PSET, "--answers", PSET / "answers.csv", "--json"]).stdout)
    by = {p["quantity"]: p for p in doc["problems"] if p["problem"] == "p02_ball_rebound"}
    assert by["ball.vy@2"]["right"] == 3 and by["ball.vy@2"]["students"] == 5
    assert doc["statistics"]["students"] == 5
    assert "Problems" in r.stdout and "most common mistake" in r.stdout


def test_grade_classes_from_first_principles(tmp_path):
    from momentum_cli.grading import KeyItem, classify

    # key: 2.04 m/s (asked to 3 digits, +- 0.005)
    k = KeyItem("p", "a.vx@2", 2.04, 0.005, "m/s", 1.0, (0, 1, -1), 3)
    assert classify(k, "2.04", "") == "right"
    assert classify(k, "204", "cm/s") == "right"
    assert classify(k, "-2.04", "m/s") == "sign error"
    assert classify(k, "7.344", "m/s") == "unit slip"   # 2.04 m/s = 7.344 km/h
    assert classify(k, "2", "m/s") == "rounding"      # 1 digit of 3, right when rounded
    assert classify(k, "2.1", "m/s") == "wrong"
    assert classify(k, "", "m/s") == "missing"


def test_the_readme_expect_lines_hold_for_the_carts(tmp_path):
    readme = (EXAMPLES.parent / "README.md").read_text(encoding="utf-8")
    block = next(b for b in re.findall(r"```text\n(.*?)```", readme, flags=re.S)
                 if "expect a.vx@2 = 2.00 m/s" in b)
    src = (PSET / "p01_carts_couple.mom").read_text()
    body = "".join(ln for ln in src.splitlines(keepends=True)
                   if not ln.startswith(("find", "expect")))
    checks = checks_of(body + block)
    assert len(checks) == 3 and all(c.met for c in checks)
    sample = next(b for b in re.findall(r"```text\n(.*?)```", readme, flags=re.S)
                  if b.startswith("FAIL  hw/"))
    hw = tmp_path / "hw"
    hw.mkdir()
    (hw / "p01_carts_couple.mom").write_text(src.replace("expect a.vx@2 = 2.00 m/s",
                                                         "expect a.vx@2 = 2.50 m/s"))
    old = os.getcwd()
    os.chdir(tmp_path)
    try:
        out = cli(["test", "hw"]).stdout
    finally:
        os.chdir(old)
    assert out.startswith(sample)


def test_simulate_scenes_are_solved_and_with_simulate_simulated():
    scene = EXAMPLES / "simulate" / "ball_bounces.mom"
    r = cli(["test", scene])
    assert r.exit_code == 0 and "(no expect lines)" in r.stdout
    r = cli(["test", "--simulate", scene])
    assert r.exit_code == 0 and "(simulated)" in r.stdout


def test_expect_write_keeps_each_line_in_its_own_unit(tmp_path):
    # flywheel: w = M t / (m r^2 / 2) = 5 * 4 / 0.3125 = 64 rad/s = 611.15 rpm
    f = tmp_path / "p07.mom"
    f.write_text((PSET / "p07_flywheel.mom").read_text().replace("= 64.0 rad/s", "= 60 rad/s"))
    assert cli(["expect", "--write", "-p", "3", f]).exit_code == 0
    lines = f.read_text().splitlines()
    assert "expect wheel.omega@2 = 64.0 rad/s" in lines
    assert "expect wheel.omega@2 = 611 rpm" in lines
    assert sum(ln.startswith("expect ") for ln in lines) == 3


def test_expect_write_on_examples_passes_its_own_tests_and_is_idempotent(tmp_path):
    """Written for the seeds, a US-units file (a zero reaction: round-off) and the files
    meant to fail, the lines pass `momentum test`; a second --write changes nothing."""
    picked = sorted(EXAMPLES.glob("seed_*.mom")) + sorted((EXAMPLES / "hard").glob("bad_*"))
    picked.append(EXAMPLES / "us_rod_center_of_percussion.mom")
    for p in picked:
        shutil.copy(p, tmp_path / p.name)
    assert cli(["expect", "--write", *sorted(tmp_path.iterdir())]).exit_code == 0
    # the zero reaction is solved as exactly 0 (round-off within its error bound is 0)
    written = (tmp_path / "us_rod_center_of_percussion.mom").read_text()
    assert "expect Jy[O]@1->2 = 0.000 lb*s" in written or "Jy[O]@1->2 = 0 lb*s +- " in written
    r = cli(["test", tmp_path])
    assert r.exit_code == 0, r.stdout
    again = cli(["expect", "--write", *sorted(tmp_path.iterdir())]).stdout.splitlines()
    assert again and all(ln.endswith("expect lines up to date") for ln in again)


def test_set_reaches_simulate_and_agrees_with_solve():
    """The disk against the wall with mu doubled: simulate's stop time is solve's t@1->2
    (each from its own method), and no longer the seed's 3.04808 s."""
    f = EXAMPLES / "seed_disk_wall.mom"
    solved = cli(["solve", "-q", "--set", "mu=0.6", f]).stdout
    t = float(re.search(r"t@1->2 = (\S+) s", solved).group(1))
    sim = cli(["simulate", "--plain", "--set", "mu=0.6", f]).stdout
    t_sim = float(re.search(r"stopped at disk.omega = 0, t = (\S+) s", sim).group(1))
    assert t == pytest.approx(t_sim, rel=1e-5)
    assert abs(t - 3.04808) > 0.5
