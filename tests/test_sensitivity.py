"""`momentum solve --sensitivity`: d answer / d given number through the solved system.

Every derivative is checked against central finite differences of whole solves, with
the number changed in the source text at its line and column (an independent path:
parse, build, compile and solve again), and one against a closed form derived here.
"""
from __future__ import annotations

import json
import os
import re
from pathlib import Path

import pytest

from momentum_cli.diagnostics import ProblemError
from momentum_cli.given_numbers import given_numbers
from momentum_cli.scene import build
from momentum_cli.sensitivity import sensitivities
from momentum_cli.solve import solve_scene
from momentum_cli.source import Source
from momentum_cli.syntax import parse

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
SEEDS = sorted(p.name for p in EXAMPLES.glob("seed_*.mom"))
OTHERS = ["disk_climbs_curb.mom", "crate_pushed_force.mom", "flow_cart_loaded_sand.mom",
          "centre_of_percussion.mom", "disk_slide_then_roll.mom", "baseball_hit_back.mom",
          "ballistic_pendulum_pin_from_impact.mom"]  # (a rank-revealed block)
# MOMENTUM_SENS_ALL=1: every example that solves (a few minutes)
if os.environ.get("MOMENTUM_SENS_ALL"):
    OTHERS = sorted(p.name for p in EXAMPLES.glob("*.mom") if not p.name.startswith("seed_"))
NUMBER = re.compile(r"(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?")
TOL = 1e-6
FD_STEP = 1e-5  # of whole solves: truncation ~1e-10, round-off ~1e-11 relative


def _answers(text: str, name: str) -> list[float] | None:
    """SI answers of a whole solve of `text`, or None if it does not solve."""
    try:
        sol = solve_scene(build(parse(Source(name, text))))
    except ProblemError:
        return None
    return [a[1] for a in sol.answers]


def _with_number(text: str, line: int, col: int, value: float) -> str:
    """`text` with the number written at line:col replaced by `value`."""
    lines = text.split("\n")
    row = lines[line - 1]
    m = NUMBER.match(row, col - 1)
    assert m, (line, col, row)
    lines[line - 1] = row[:m.start()] + repr(value) + row[m.end():]
    return "\n".join(lines)


def _fd(text: str, name: str, prm, step: float = FD_STEP) -> list[float] | None:
    """d answers / d number by central differences of whole solves (one-sided at the
    edge of the domain, e = 1; a smaller step where a redundant statement that holds to
    first order, a hit at the centre of percussion, fails at the second)."""
    p = prm.value
    h = step * abs(p) if p else step
    at = lambda d: _answers(_with_number(text, prm.line, prm.column, p + d), name)  # noqa
    up, down = at(h), at(-h)
    if up is not None and down is not None:
        return [(u - d) / (2 * h) for u, d in zip(up, down)]
    side = 1.0 if up is not None else -1.0
    base, a, b = _answers(text, name), at(side * h), at(2 * side * h)
    if a is None or b is None:
        return _fd(text, name, prm, step / 100) if step > FD_STEP / 200 else None
    return [side * (-3 * x + 4 * y - z) / (2 * h) for x, y, z in zip(base, a, b)]


def _compare(name: str) -> float:
    """The largest difference between the sensitivities and finite differences (relative
    to the derivative, or to the answer's scale where the derivative is tiny)."""
    text = (EXAMPLES / name).read_text()
    doc = parse(Source(name, text))
    sol = solve_scene(build(doc))
    sens = sensitivities(doc, sol)
    assert sens.unavailable is None, sens.unavailable
    assert len(sens.answers) == len(sol.answers)
    worst = 0.0
    vals = {p.id: p.value for p in sens.parameters}
    scale = {a.name: max([abs(a.value), a.size] + [abs(d * (vals[k] or 1.0))
                                         for k, d in a.derivatives.items()])
             for a in sens.answers}
    for prm in sens.parameters:
        fd = _fd(text, name, prm)
        if prm.id in sens.skipped:  # the number alone breaks a redundant equation:
            assert fd is None, (prm, sens.skipped[prm.id])  # the moved file has no solution
            continue
        assert fd is not None, prm
        for a, d_fd in zip(sens.answers, fd):
            d = a.derivatives[prm.id]
            # the answer's scale per unit of the number: a derivative this small is zero
            # (absolute: 1e-9 of the answer's scale per relative change of the number)
            floor = 1e-3 * scale[a.name] / (abs(prm.value) or 1.0)
            err = abs(d - d_fd) / max(abs(d_fd), floor, 1e-300)
            assert err <= TOL, (name, a.name, prm.label, d, d_fd)
            worst = max(worst, err)
    return worst


@pytest.mark.parametrize("name", SEEDS + OTHERS)
def test_sensitivities_match_finite_differences(name):
    _compare(name)


def test_every_seed_has_given_numbers_and_answers():
    for name in SEEDS:
        doc = parse(Source(name, (EXAMPLES / name).read_text()))
        sens = sensitivities(doc, solve_scene(build(doc)))
        assert sens.parameters and sens.answers, name
        assert all(why.startswith("moving it alone breaks equation")
                   for why in sens.skipped.values()), sens.skipped


COLLISION = """\
problem "Two particles, head on"
body a: particle(mass = {ma} kg)
body b: particle(mass = {mb} kg)
state 1: a.v = ({va} m/s, 0), b.v = ({vb} m/s, 0)
state 2
impact 1 -> 2:
    contact a with b normal (-1, 0): restitution {e}, smooth
find a.vx@2, b.vx@2
"""


def test_restitution_closed_form():
    """v_A' = (m_A v_A + m_B v_B - e m_B (v_A - v_B)) / (m_A + m_B), so
    d v_A'/d e = -m_B (v_A - v_B) / (m_A + m_B) and d v_B'/d e = m_A (v_A - v_B)/(m_A + m_B)."""
    ma, mb, va, vb, e = 2.0, 3.0, 5.0, 1.5, 0.6
    text = COLLISION.format(ma=ma, mb=mb, va=va, vb=vb, e=e)
    doc = parse(Source("collision.mom", text))
    sens = sensitivities(doc, solve_scene(build(doc)))
    (pe,) = [p for p in sens.parameters if p.label.startswith("restitution")]
    (pma,) = [p for p in sens.parameters if p.label == "a mass"]
    dva, dvb = (a.derivatives[pe.id] for a in sens.answers)
    assert dva == pytest.approx(-mb * (va - vb) / (ma + mb), rel=1e-9)
    assert dvb == pytest.approx(ma * (va - vb) / (ma + mb), rel=1e-9)
    # d v_A'/d m_A = (v_A - v') (1 + e)... from the formula: (v_A(m_A+m_B) - N) / (m_A+m_B)^2
    num = ma * va + mb * vb - e * mb * (va - vb)
    want = (va * (ma + mb) - num) / (ma + mb) ** 2
    assert sens.answers[0].derivatives[pma.id] == pytest.approx(want, rel=1e-9)


def test_given_numbers_name_their_place():
    text = (EXAMPLES / "seed_rod_drop_smooth.mom").read_text()
    params = given_numbers(parse(Source("x.mom", text)))
    labels = {p.label: p for p in params}
    assert labels["rod mass"].text == "10 kg" and labels["rod mass"].line == 6
    assert "g" in labels and "rod.angle@1" in labels
    # hints (`rod.vy < 0`), bare zeros and `find` lines are not data
    assert all(p.value != 0 for p in params)


def test_cli_plain_and_json(tmp_path):
    from typer.testing import CliRunner

    from momentum_cli.cli import app

    src = tmp_path / "c.mom"
    src.write_text(COLLISION.format(ma=2, mb=3, va=5, vb=1.5, e=0.6))
    res = CliRunner().invoke(app, ["solve", "--plain", "--sensitivity", str(src)])
    assert res.exit_code == 0, res.output
    assert "Sensitivities" in res.output and "restitution at a (1->2)" in res.output
    res = CliRunner().invoke(app, ["solve", "--json", "--sensitivity", str(src)])
    assert res.exit_code == 0, res.output
    doc = json.loads(res.output)
    sec = doc["results"][0]["sensitivities"]
    ids = {p["label"]: p["id"] for p in sec["parameters"]}
    first = sec["answers"][0]
    row = next(r for r in first["derivatives"] if r["parameter"] == ids["restitution at a (1->2)"])
    assert row["derivative"] == pytest.approx(-3 * 3.5 / 5, rel=1e-9)
    assert row["unit"] == "m/s"
    from importlib.resources import files

    import jsonschema

    schema = json.loads(files("momentum_cli").joinpath("schema").joinpath(
        "momentum-result.schema.json").read_text(encoding="utf-8"))
    jsonschema.Draft202012Validator(schema).validate(doc)


def test_set_override_is_the_parameter():
    """With `--set v0=4 m/s` the let's new value is the given number differentiated:
    v_B' = (1 + e) m_A v0 / (m_A + m_B), so d v_B'/d v0 = (1 + e) m_A / (m_A + m_B)."""
    from momentum_cli.run import solve_source

    text = ("let v0 = 3 m/s\nbody a: particle(mass = 2 kg)\nbody b: particle(mass = 1 kg)\n"
            "state 1: a.v = (v0, 0), b at rest\nstate 2\nimpact 1 -> 2:\n"
            "    contact a with b normal (-1, 0): restitution 0.5, smooth\n"
            "find a.vx@2, b.vx@2\n")
    res = solve_source(Source("let.mom", text), overrides=(("v0", "4 m/s"),), sensitivity=True)
    sec = res.report.sensitivities
    (v0,) = [p for p in sec["parameters"] if p["label"] == "let v0"]
    assert v0["value"] == 4 and v0["text"] == "4 m/s"
    vb = sec["answers"][1]
    assert vb["value"] == pytest.approx(1.5 * 2 * 4 / 3, rel=1e-12)
    row = next(r for r in vb["derivatives"] if r["parameter"] == v0["id"])
    assert row["derivative"] == pytest.approx(1.5 * 2 / 3, rel=1e-9)
    assert row["relative"] == pytest.approx(1.0, rel=1e-9)


def test_unavailable_is_said_not_guessed():
    """A phase integrated numerically has no derivatives here: the section says why and
    the answers are still printed."""
    name = "flow_raindrop_in_mist.mom"
    doc = parse(Source(name, (EXAMPLES / name).read_text()))
    sens = sensitivities(doc, solve_scene(build(doc)))
    assert sens.unavailable and "integrated" in sens.unavailable and not sens.answers


def test_seeds_use_no_residual_difference():
    """Every number of every seed enters the equations through the trace: dF/dp is
    exact (expr.diff of the traced trees), none is left to a residual difference."""
    for name in SEEDS:
        doc = parse(Source(name, (EXAMPLES / name).read_text()))
        sens = sensitivities(doc, solve_scene(build(doc)))
        assert sens.by_difference == {}, (name, sens.by_difference)
        assert "residual difference" not in sens.note, (name, sens.note)


def test_special_values_keep_their_derivatives():
    """At m_A = 1 kg, e = 1 and v_B = 0 m/s the compile folds 1*x and 0*x away; the
    traced build keeps the terms, so the derivatives are still the closed form's:
    v_A' = (m_A v_A + m_B v_B - e m_B (v_A - v_B)) / M, M = m_A + m_B."""
    ma, mb, va, vb, e = 1.0, 3.0, 5.0, 0.0, 1.0
    text = COLLISION.format(ma="1", mb="3", va="5", vb="0", e="1")
    doc = parse(Source("special.mom", text))
    sens = sensitivities(doc, solve_scene(build(doc)))
    assert sens.by_difference == {}, sens.by_difference
    ids = {p.label: p.id for p in sens.parameters}
    d = sens.answers[0].derivatives
    M = ma + mb
    num = ma * va + mb * vb - e * mb * (va - vb)
    assert d[ids["a mass"]] == pytest.approx((va * M - num) / M ** 2, rel=1e-12)
    assert d[ids["restitution at a (1->2)"]] == pytest.approx(-mb * (va - vb) / M, rel=1e-12)
    assert d[ids["b.v@1 x"]] == pytest.approx(mb * (1 + e) / M, rel=1e-12)


def test_a_number_outside_the_trace_falls_back():
    """A build that reads one number as a plain float (as code folding it with math.cos
    would) is found by the probe compile; that number alone gets a residual difference,
    said in the note, and its derivative is still right."""
    from momentum_cli import syntax as S
    from momentum_cli.given_numbers import replaced

    ma, mb, va, vb, e = 2.0, 3.0, 5.0, 1.5, 0.6
    text = COLLISION.format(ma=ma, mb=mb, va=va, vb=vb, e=e)
    doc = parse(Source("leak.mom", text))
    (pma,) = [p for p in given_numbers(doc) if p.label == "a mass"]
    span = pma.node.span

    def leaky(d):
        nums = {}

        def walk(node):
            if isinstance(node, S.Num) and node.span == span:
                nums[id(node)] = float(node.value)  # the trace is lost here
            elif isinstance(node, tuple):
                for x in node:
                    walk(x)
            else:
                for f in getattr(type(node), "_fields", ()):
                    walk(getattr(node, f))

        for st in d.statements:
            walk(st)
        return build(replaced(d, nums))

    sens = sensitivities(doc, solve_scene(build(doc)), build=leaky)
    assert set(sens.by_difference) == {pma.id}, sens.by_difference
    assert f"d/d{pma.id} by a residual difference" in sens.note
    num = ma * va + mb * vb - e * mb * (va - vb)
    want = (va * (ma + mb) - num) / (ma + mb) ** 2
    assert sens.answers[0].derivatives[pma.id] == pytest.approx(want, rel=1e-8)


def test_a_zero_given_keeps_its_derivative():
    """`equation a.vx@2 = 0 m/s` with e unknown: the compile would fold the zero away
    (x - 0); traced, it stays. From v_A' = (m_A v_A - e m_B v_A) / M = c (B at rest),
    e = (m_A v_A - c M) / (m_B v_A), so d e / d c = -M / (m_B v_A)."""
    ma, mb, va = 2.0, 3.0, 5.0
    text = COLLISION.format(ma=ma, mb=mb, va=va, vb=0, e="?").replace(
        "find a.vx@2, b.vx@2", "equation a.vx@2 = 0 m/s\nfind e[a-b]")
    doc = parse(Source("zero.mom", text))
    sens = sensitivities(doc, solve_scene(build(doc)))
    assert sens.by_difference == {}, sens.by_difference
    (pc,) = [p for p in sens.parameters if p.label.startswith("userequation")]
    assert sens.answers[0].value == pytest.approx(ma / mb, rel=1e-12)
    assert sens.answers[0].derivatives[pc.id] == pytest.approx(-(ma + mb) / (mb * va),
                                                               rel=1e-12)


def test_a_loops_literal_is_one_given_number():
    """`mass = 0.1 kg * 2^(i-1)` in a `for` loop is written once: one given number for
    all twelve passes, as moving it in the text moves every mass. The velocities after
    the elastic impacts depend only on the mass ratios, so their derivative by it is 0,
    and v_12 = v0 (2/3)^11 gives d v_12 / d v0 = (2/3)^11."""
    name = "cradle_loop_doubling_masses.mom"
    doc = parse(Source(name, (EXAMPLES / name).read_text()))
    sens = sensitivities(doc, solve_scene(build(doc)))
    (m0,) = [p for p in sens.parameters if p.text == "0.1 kg"]
    (v0,) = [p for p in sens.parameters if p.label == "let v0"]
    assert len(m0.nodes) == 12 and "12 loop passes" in m0.label
    v12 = next(a for a in sens.answers if a.name == "b[12].vx@12")
    assert abs(v12.derivatives[m0.id]) <= 1e-12 * abs(v12.value) / m0.value
    assert v12.derivatives[v0.id] == pytest.approx((2 / 3) ** 11, rel=1e-12)
