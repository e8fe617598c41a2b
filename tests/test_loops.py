"""Loops in the language (issue 10, item 10): `body b[1..N]` and `for i in A..B:` blocks,
written out before parsing; answers against closed forms, errors located in the loop."""
import json
from pathlib import Path

import pytest

from momentum_cli.diagnostics import ProblemError
from momentum_cli.loops import expand
from momentum_cli.scene import build
from momentum_cli.solve import solve_scene
from momentum_cli.source import Source
from momentum_cli.syntax import parse

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


def solve(text: str):
    sol = solve_scene(build(parse(Source("loops.mom", text))))
    return {name: si for name, _v, _u, si in sol.answers}


def error(text: str):
    with pytest.raises(ProblemError) as exc:
        solve(text)
    return exc.value.diagnostics[0]


def cradle(n: int, e: str = "1", extra: str = "") -> str:
    return f"""\
problem "A row of {n} equal balls, written with loops"
let m = 0.1 kg
body b[1..{n}]: particle(mass = m, radius = 15 mm)
state 1 "b[1] meets b[2]":
    b[1].v = (2 m/s, 0)
    for i in 2..{n}:
        b[i] at rest
for i in 2..{n}:
    state i
for i in 1..{n - 1}:
    impact i -> i+1:
        contact c[i]: b[i+1] with b[i] normal (1, 0): restitution {e}, smooth
{extra}"""


def test_equal_balls_with_restitution_match_the_closed_form():
    """Equal masses, e: the struck ball leaves at (1+e)/2 of the striker's speed, the
    striker keeps (1-e)/2 of it; after n-1 impacts ball k has (1-e)/2 (1+e)/2^(k-1) v0."""
    n, e, v0 = 8, 0.6, 2.0
    a = solve(cradle(n, str(e), f"find b[{n}].vx@{n}, b[1].vx@{n}, b[4].vx@{n}, "
                                f"J_n[c[3]]@3->4\n"))
    h, k = (1 + e) / 2, (1 - e) / 2
    assert a[f"b[{n}].vx@{n}"] == pytest.approx(v0 * h ** (n - 1), rel=1e-12)
    assert a[f"b[1].vx@{n}"] == pytest.approx(v0 * k, rel=1e-12)
    assert a[f"b[4].vx@{n}"] == pytest.approx(v0 * k * h ** 3, rel=1e-12)
    assert a["J_n[c[3]]@3->4"] == pytest.approx(0.1 * h * v0 * h ** 2, rel=1e-12)


def cradle_loop_doubling_masses():
    """m, 2m, 4m, ... in a row, elastic: 2/3 of the speed passes on, the striker keeps -1/3."""
    text = (EXAMPLES / "cradle_loop_doubling_masses.mom").read_text()
    a = solve(text)
    v0, m0 = 3.0, 0.1
    assert a["b[12].vx@12"] == pytest.approx(v0 * (2 / 3) ** 11, rel=1e-12)
    assert a["b[6].vx@12"] == pytest.approx(-v0 / 3 * (2 / 3) ** 5, rel=1e-12)
    assert a["J_n[c[11]]@11->12"] == pytest.approx(m0 * v0 * (4 / 3) ** 11, rel=1e-12)
    assert a["T@12"] == pytest.approx(a["T@1"], rel=1e-12)  # elastic: nothing lost
    assert a["T@1"] == pytest.approx(m0 * v0 ** 2 / 2, rel=1e-12)


EXAMPLE_CHECKS = {"cradle_loop_doubling_masses": cradle_loop_doubling_masses}


def test_the_doubling_masses_example_matches_its_closed_form():
    cradle_loop_doubling_masses()


def test_a_loop_and_the_same_lines_written_out_give_the_same_answers():
    looped = cradle(5, "0.8", "find b[5].vx@5, b[2].vx@5\n")
    by_hand = looped.split("body b[")[0] + "".join(
        f"body b[{i}]: particle(mass = m, radius = 15 mm)\n" for i in range(1, 6)) + \
        "state 1: b[1].v = (2 m/s, 0), b[2] at rest, b[3] at rest, b[4] at rest, " \
        "b[5] at rest\n" + "".join(f"state {i}\n" for i in range(2, 6)) + "".join(
            f"impact {i} -> {i + 1}:\n    contact c[{i}]: b[{i + 1}] with b[{i}] normal (1, 0):"
            " restitution 0.8, smooth\n" for i in range(1, 5)) + "find b[5].vx@5, b[2].vx@5\n"
    assert solve(looped) == solve(by_hand)


def test_nested_loops_and_the_index_in_expressions():
    text = """\
problem "Three pairs of particles stick together"
for i in 1..3:
    for j in 1..2:
        body p[i][j]: particle(mass = i*j kg)
state 1:
    for i in 1..3:
        p[i][1].v = (i m/s, 0)
        p[i][2] at rest
state 2
impact 1 -> 2:
    for i in 1..3:
        contact k[i]: p[i][2] with p[i][1] normal (1, 0): restitution 0, smooth
find p[1][2].vx@2, p[2][2].vx@2, p[3][2].vx@2
"""
    a = solve(text)
    for i in 1, 2, 3:  # plastic: i*1*i = (i + 2i) v
        assert a[f"p[{i}][2].vx@2"] == pytest.approx(i * i / (3 * i), rel=1e-14)


def test_an_error_in_a_loop_names_the_line_column_and_index():
    text = cradle(6).replace("contact c[i]: b[i+1]", "contact c[i]: b[6-i]")
    d = error(text + "find b[6].vx@6\n")
    assert d.span.line == 12 and d.span.column == 9
    assert d.span.where == "in loop iteration i = 3"  # b[6-3] with b[3]: itself
    assert "in loop iteration i = 3" in d.format(Source("loops.mom", text))


def test_a_syntax_error_in_a_loop_points_into_the_block():
    text = cradle(4).replace("restitution 1, smooth", "restitution 1, smoth") + "find b[4].vx@4\n"
    d = error(text)
    line = text.split("\n")[d.span.line - 1]
    assert d.code == "syntax" and d.span.line == 12
    assert line[d.span.column - 1:].startswith("smoth")
    assert d.span.where == "in loop iteration i = 1"


def test_the_json_diagnostic_carries_the_loop_index():
    text = cradle(4).replace("b[i] at rest", "b[i+3] at rest") + "find b[4].vx@4\n"
    d = error(text)
    out = json.loads(json.dumps(d.to_json()))
    assert out["line"] == 7 and out["loop"] == "in loop iteration i = 2"
    jsonschema = pytest.importorskip("jsonschema")
    from importlib.resources import files

    schema = json.loads(files("momentum_cli").joinpath("schema").joinpath(
        "momentum-result.schema.json").read_text(encoding="utf-8"))
    jsonschema.Draft202012Validator(schema["$defs"]["diagnostic"] | {
        "$defs": schema["$defs"]}).validate(out)


@pytest.mark.parametrize("head, words", [
    ("for i in 1..x:", "not a whole number"),
    ("for i in 5..1:", "is empty"),
    ("for i in 1:", "A..B"),
])
def test_bad_loop_ranges_are_refused_at_the_for_line(head, words):
    text = cradle(3).replace("for i in 1..2:", head) + "find b[3].vx@3\n"
    d = error(text)
    assert d.span.line == 10 and words in d.message


def test_a_for_line_without_a_block_is_refused():
    d = error('problem "x"\nbody a: particle(mass = 1 kg)\nfor i in 1..3:\nfind a.vx@1\n')
    assert d.span.line == 3 and "indented block" in d.message


def test_a_file_without_loops_is_not_rewritten():
    assert expand((EXAMPLES / "newtons_cradle_sequence.mom").read_text()) is None


def test_a_thousand_ball_cradle_is_a_few_lines():
    """The 1,000-ball cradle in 12 lines expands into its 3,000 statements, in order."""
    text = cradle(1000, extra="find b[1000].vx@1000\n")
    assert len(text.split("\n")) < 16
    doc = parse(Source("c.mom", text))
    kinds = [type(s).__name__ for s in doc.statements]
    assert kinds.count("BodyDecl") == 1000 and kinds.count("Transition") == 999
    assert kinds.count("StateDecl") == 1000
    last = [s for s in doc.statements if type(s).__name__ == "Transition"][-1]
    assert (last.before, last.after) == ("999", "1000") and last.span.line == 11
    assert last.span.where == "in loop iteration i = 999"


def test_a_malformed_for_line_says_how_a_loop_is_written():
    d = error('problem "x"\nbody b[1..3]: particle(mass = 1 kg)\nfor i in 1..3\n    state i\n'
              'find b[1].vx@1\n')
    assert d.span.line == 3 and "for NAME in A..B:" in d.message


@pytest.mark.parametrize("text", [cradle(30, extra="find b[30].vx@30\n"),
                                  (EXAMPLES / "cradle_loop_doubling_masses.mom").read_text()])
def test_reusing_the_parse_of_repeated_iterations_changes_nothing(text, monkeypatch):
    """The parser parses an iteration whose text differs from an earlier one only in its
    digits once and moves copies into place: the nodes (and every span) are those of
    parsing the whole written-out text."""
    from momentum_cli import syntax

    reused = parse(Source("c.mom", text)).statements
    monkeypatch.setattr(syntax, "_parse_runs", lambda loops: None)
    assert parse(Source("c.mom", text)).statements == reused


def test_loop_bounds_may_name_a_whole_number_let():
    text = cradle(6, extra="find b[6].vx@6\n")
    text = text.replace("let m = 0.1 kg", "let m = 0.1 kg\nlet N = 6")
    text = text.replace("b[1..6]", "b[1..N]").replace("2..6", "2..N").replace("1..5", "1..N-1")
    assert solve(text)["b[6].vx@6"] == pytest.approx(2.0, rel=1e-14)  # e = 1: all passed on
