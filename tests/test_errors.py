"""Bad problem files: every class of mistake is a named error at the right line:column.

One table of snippets -> (line, column, message) checked twice: in-process through
`helpers.error_of`, and through the CLI, whose first stderr line must be exactly
`name:line:col: error: message` (GNU style) with exit code 1 and no traceback.
"""
from __future__ import annotations

import re

import pytest
from helpers import error_of
from typer.testing import CliRunner

from momentum_cli.cli import app
from momentum_cli.diagnostics import ExitCode
from momentum_cli.run import SourceTextError, decode_source, solve_source
from momentum_cli.source import Source

# Line numbers below refer to this file: 4 body, 5 point, 7-8 states, 10-11 impact, 13 find.
BASE = """\
problem "rod dropped on its end"
gravity 9.81 m/s^2 down

body rod: rod(mass = 10 kg, length = 1 m)
point A = rod.end(-)

state 1 "before": rod.v = (0, -3 m/s), rod.omega = 0, rod.angle = 30 deg
state 2 "after"

impact 1 -> 2:
    contact A with ground normal (0, 1): restitution 0.5, smooth

find rod.omega@2, rod.v@2, J_n[A]@1->2
"""

# A pendulum released from the horizontal: at the bottom omega = +-5.42 rad/s.
PENDULUM = """\
problem "pendulum released from horizontal"
gravity 9.81 m/s^2 down

body rod: rod(mass = 2 kg, length = 1 m)
point O = rod.end(-)
pin O to ground at (0, 0)

state 1 "horizontal": rod.angle = 0, rod.omega = 0
state 2 "hanging": rod.angle = -90 deg

energy 1 -> 2

find rod.omega@2
"""


def edit(old: str, new: str, text: str = BASE) -> str:
    assert old in text, old
    return text.replace(old, new, 1)


def test_the_base_problem_solves():
    res = solve_source(Source("base.mom", BASE))
    assert res.status == "solved", [d.message for d in res.diagnostics]


CASES = [
    # ---- syntax
    pytest.param(edit("impact 1 -> 2:", "impact 1 -> 2"), 10, 14,
                 "unexpected indented block after this line; is a ':' missing here?",
                 id="missing_colon_after_impact_points_past_the_arrow_line"),
    pytest.param(edit("body rod: rod", "body rod rod"), 4, 10, "unexpected 'rod'; expected ':'",
                 id="missing_colon_after_body_name_points_at_the_shape"),
    pytest.param(edit("restitution 0.5, smooth", "restitution 0.5 smooth"), 11, 58,
                 "unknown unit 'smooth'",
                 id="missing_comma_between_contact_properties_points_at_the_word"),
    pytest.param(edit("find rod.omega@2,", "find rod.omega@2 +,"), 13, 19,
                 "syntax error: unexpected ','", id="unexpected_token_in_find"),
    pytest.param(BASE + "find dot(rod.v@2, (1, 0)\n", 14, 25, "unexpected end of file",
                 id="unclosed_bracket_is_unexpected_end_of_file_just_past_the_last_character"),
    pytest.param(edit("10 kg", "10 kg $"), 4, 28, "unexpected character '$'",
                 id="stray_character_is_named"),
    pytest.param(edit("    contact", "contact"), 11, 1,
                 "expected an indented block after the ':' on line 10",
                 id="unindented_clause_asks_for_an_indented_block"),
    pytest.param(edit("smooth\n", "smooth\n  contact A with ground normal (1, 0): restitution 0\n"),
                 12, 3, "matches no enclosing block (indent it by 0 or 4 columns)",
                 id="inconsistent_dedent_points_at_the_line"),
    pytest.param(BASE.replace("\n", "\r"), 1, 33, "unexpected character U+000D",
                 id="old_mac_line_ends_are_named_as_a_code_point"),
    # ---- units and dimensions
    pytest.param(edit("10 kg", "10 kgg"), 4, 25, "unknown unit 'kgg'; did you mean 'kg'?",
                 id="unknown_unit_suggests_the_close_one"),
    pytest.param(edit("mass = 10 kg", "mass = 1 m"), 4, 22, "'mass' needs a mass; got a length",
                 id="mass_in_metres_is_a_dimension_error"),
    pytest.param(edit("mass = 10 kg", "mass = 10 g"), 4, 25, "'g' is the file's gravity",
                 id="g_is_not_grams"),
    # ---- names
    pytest.param(edit("point A = rod.end(-)", "point A = rdo.end(-)"), 5, 11,
                 "unknown body 'rdo'; did you mean 'rod'?", id="misspelt_body_suggests_the_body"),
    pytest.param(edit("contact A with", "contact AA with"), 11, 13,
                 "unknown point or body 'AA'; did you mean 'A'?",
                 id="misspelt_point_suggests_the_point"),
    pytest.param(edit("find rod.omega@2", "find rdo.omega@2"), 13, 6,
                 "did you mean 'rod.omega@2'?", id="misspelt_body_in_find_suggests_the_quantity"),
    pytest.param(edit("rod.omega = 0", "rod.omgea = 0"), 7, 40,
                 "'omgea' is not a state quantity; did you mean 'omega'?",
                 id="misspelt_state_quantity_suggests_omega"),
    pytest.param(edit("find rod.omega@2", "find rod.omega@5"), 13, 6, "state 5 is not declared",
                 id="undeclared_state_in_find"),
    pytest.param(edit("restitution 0.5", "restitution elastik",
                      edit("problem", "let elastic = 0.5\nproblem")), 12, 54,
                 "unknown name 'elastik'; did you mean 'elastic'?",
                 id="misspelt_constant_suggests_the_let_name"),
    pytest.param(edit("rod.angle = 30 deg", "rod.angle = sinn(30 deg)"), 7, 67,
                 "unknown function 'sinn'; did you mean 'sin'?",
                 id="unknown_function_suggests_sin"),
    pytest.param(edit("gravity 9.81 m/s^2 down\n", "", edit("mass = 10 kg", "mass = 100 N / g")),
                 3, 30, "'g' is used but no gravity is declared", id="g_without_gravity"),
    # ---- physical values
    pytest.param(edit("10 kg", "-10 kg"), 4, 22, "'mass' must be positive; got -10",
                 id="negative_mass"),
    pytest.param(edit("restitution 0.5", "restitution 1.5"), 11, 54,
                 "coefficient of restitution must be between 0 and 1; got 1.5",
                 id="restitution_above_one"),
    pytest.param(edit("smooth", "friction -0.2"), 11, 68,
                 "friction coefficient cannot be negative; got -0.2", id="negative_friction"),
    pytest.param(edit("gravity 9.81 m/s^2 down\n", "", edit("mass = 10 kg", "weight = 100 N")),
                 3, 24, "a weight needs the file's g", id="weight_without_gravity"),
    # ---- numbers
    pytest.param(edit("10 kg", "1e999 kg"), 4, 22, "number too large", id="huge_literal"),
    pytest.param(edit("10 kg", "1e200 kg * 1e200"), 4, 22, "too large",
                 id="overflowing_product"),
    pytest.param(edit("30 deg", "exp(1000)"), 7, 67, "too large", id="overflowing_function"),
    pytest.param(edit("10 kg", "nan"), 4, 22, "unknown name 'nan'", id="nan_is_not_a_number"),
    pytest.param(edit("10 kg", "inf kg"), 4, 26, "syntax error: unexpected 'kg'",
                 id="inf_is_not_a_number"),
    pytest.param(edit("10 kg", "10 kg / 0"), 4, 30, "division by zero", id="division_by_zero"),
    pytest.param(edit("10 kg", "(" * 300 + "10 kg" + ")" * 300), 4, 221,
                 "nested too deeply", id="deep_brackets"),
    pytest.param(edit("10 kg", "+".join(["1"] * 5000) + " kg"), 4, 22,
                 "expression too long or nested too deeply", id="very_long_sum"),
    pytest.param(edit("10 kg", "-" * 3000 + "10 kg"), 4, 22,
                 "expression too long or nested too deeply", id="very_long_chain_of_signs"),
    # ---- the file itself
    pytest.param("", 1, 1, "empty problem file", id="empty_file"),
    pytest.param("  \n\n\t\n", 1, 1, "empty problem file", id="blank_file"),
    pytest.param("\x00\x01\x02\xff", 1, 1, "not a text file", id="binary_file"),
    pytest.param('problem "x"\nbody \x00', 2, 6, "not a text file",
                 id="nul_byte_is_located"),
    # ---- the equations
    pytest.param(edit("restitution 0.5", "restitution ?"), 8, 1,
                 "under-determined: ", id="under_determined_names_the_unknowns"),
    pytest.param(edit('state 2 "after"', 'state 2 "after": rod.vy = 1 m/s'), 10, 1,
                 "inconsistent: ", id="inconsistent_over_determined"),
    pytest.param(PENDULUM, 11, 1, "more than one solution for rod.omega@2",
                 id="energy_without_a_hint_is_ambiguous"),
]

GNU = re.compile(r"^(?P<name>.+?):(?P<line>\d+):(?P<col>\d+): error: (?P<msg>.+)$")


@pytest.mark.parametrize("text, line, column, message", CASES)
def test_error_is_named_at_its_line_and_column(text, line, column, message):
    d = error_of(text, "bad.mom")
    assert d.severity == "error"
    assert message in d.message
    assert d.span is not None, d.message
    assert (d.span.line, d.span.column) == (line, column), d.message
    first = d.format(Source("bad.mom", text)).splitlines()[0]
    m = GNU.match(first)
    assert m, first
    assert (m["name"], int(m["line"]), int(m["col"])) == ("bad.mom", line, column)


runner = CliRunner()


@pytest.mark.parametrize("text, line, column, message", CASES)
def test_cli_prints_the_error_gnu_style_and_exits_1(text, line, column, message, tmp_path):
    path = tmp_path / "bad.mom"
    path.write_bytes(text.encode("utf-8", errors="surrogateescape"))
    res = runner.invoke(app, ["solve", "--plain", str(path)])
    assert res.exit_code == ExitCode.PROBLEM, res.output
    assert res.exception is None or isinstance(res.exception, SystemExit)
    assert res.stdout == ""
    first = res.stderr.splitlines()[0]
    assert first.startswith(f"{path}:{line}:{column}: error: "), first
    assert message in first
    assert "Traceback" not in res.stderr


def test_missing_comma_before_a_keyword_read_as_a_unit_suggests_the_comma():
    d = error_of(edit("restitution 0.5, smooth", "restitution 0.5 smooth"))
    assert d.notes == ("a unit follows its number directly: is a ',' missing before 'smooth'?",)


def test_snippet_puts_the_caret_under_the_column():
    text = edit("mass = 10 kg", "mass = 1 m")
    lines = error_of(text).format(Source("t.mom", text)).splitlines()
    assert lines[1] == "    4 | body rod: rod(mass = 1 m, length = 1 m)"
    assert lines[2] == "      |                      ^~~"


def test_caret_lines_up_after_a_tab():
    text = edit("    contact A", "\tcontact AA")
    d = error_of(text)
    assert (d.span.line, d.span.column) == (11, 10)
    snippet = d.format(Source("t.mom", text)).splitlines()
    code, marker = snippet[1], snippet[2]
    assert marker.index("^") == code.index("AA")


def test_long_line_is_cut_to_a_window_around_the_caret():
    text = edit("10 kg", "1 kg" + " " * 400 + "+ 1 m")
    d = error_of(text)
    lines = d.format(Source("t.mom", text)).splitlines()
    assert d.span.line == 4 and "cannot add a mass and a length" in d.message
    assert all(len(x) < 140 for x in lines)


def test_notes_follow_the_snippet():
    text = edit("restitution 0.5", "restitution ?")
    lines = error_of(text).format(Source("t.mom", text)).splitlines()
    assert lines[1].startswith("    note: ")


def test_hint_less_energy_problem_lists_both_roots_and_asks_for_a_hint():
    d = error_of(PENDULUM)
    assert d.code == "ambiguous"
    assert "5.425" in d.notes[0] and "-5.425" in d.notes[0]
    assert "rod.omega < 0" in d.notes[1]


def test_a_hint_picks_the_root():
    text = edit("rod.angle = -90 deg", "rod.angle = -90 deg, rod.omega < 0", PENDULUM)
    res = solve_source(Source("p.mom", text))
    assert res.status == "solved"
    assert res.report.answers[0]["si_value"] == pytest.approx(-5.42494, rel=1e-5)


def test_under_determined_problem_names_the_unknowns_and_suggests_a_fix():
    d = error_of(edit("restitution 0.5", "restitution ?"))
    assert d.code == "under-determined"
    for name in ("rod.omega@2", "rod.vy@2"):
        assert name in d.message
    assert any("restitution" in n for n in d.notes)


def test_inconsistent_problem_names_the_conflicting_lines():
    d = error_of(edit('state 2 "after"', 'state 2 "after": rod.vy = 1 m/s'))
    assert d.code == "inconsistent"
    assert any("lines 10, 11" in n for n in d.notes)


def test_undeclared_state_in_a_transition_is_named():
    d = error_of(edit("impact 1 -> 2", "impact 1 -> 3"))
    assert d.span.line == 10 and "state 3 is not declared" in d.message


def test_non_utf8_file_is_an_encoding_error_at_the_byte():
    with pytest.raises(SourceTextError) as exc:
        decode_source("latin1.mom", 'problem "x"\n# caf\xe9\n'.encode("latin-1"))
    d = exc.value.diagnostics[0]
    assert (d.span.line, d.span.column, d.code) == (2, 6, "encoding")
    assert "0xe9" in d.message


def test_non_utf8_file_exits_1_through_the_cli(tmp_path):
    path = tmp_path / "latin1.mom"
    path.write_bytes('problem "caf\xe9"\n'.encode("latin-1"))
    res = runner.invoke(app, ["solve", str(path)])
    assert res.exit_code == ExitCode.PROBLEM
    assert res.stderr.startswith(f"{path}:1:13: error: not UTF-8 text")


def test_byte_order_mark_is_ignored():
    res = solve_source(decode_source("bom.mom", b"\xef\xbb\xbf" + BASE.encode()))
    assert res.status == "solved"


def test_read_source_reads_past_its_first_read_and_stops_at_the_limit(tmp_path, monkeypatch):
    """read_source reads a small first piece and the rest only when there is more: a
    file larger than that piece is read whole, one over the limit is cut at the limit
    (parse then refuses it as too large), as one read of READ_LIMIT bytes did."""
    from momentum_cli import run

    monkeypatch.setattr(run, "FIRST_READ", 8)
    monkeypatch.setattr(run, "READ_LIMIT", 20)
    for n in (0, 7, 8, 9, 19, 20, 21, 100):
        p = tmp_path / f"f{n}.mom"
        p.write_bytes(b"x" * n)
        assert run.read_source(str(p)).text == "x" * min(n, 20)
