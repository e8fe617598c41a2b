"""Physically meaningless values: each `examples/hard/bad_*.mom` of this kind is an
error at its line and column, never an answer; its golden error (`bad_*.err`, the
plain stderr of `momentum solve`) is reviewed like code (`pytest --update-golden`).

The older `bad_*` files of section 7 (singular, under-determined, inconsistent) are
checked by tests/test_hard.py instead.
"""
from __future__ import annotations

import math
import re

import pytest
from conftest import EXAMPLES
from typer.testing import CliRunner

from momentum_cli.cli import app
from momentum_cli.run import solve_source
from momentum_cli.source import Source

HARD = EXAMPLES / "hard"
SECTION_7 = {"bad_duplicate_contact", "bad_double_pin", "bad_parallel_faces",
             "bad_restitution_unknown", "bad_inconsistent_momentum",
             "bad_inconsistent_restitution", "bad_inconsistent_hidden"}
BAD = [p for p in sorted(HARD.glob("bad_*.mom")) if p.stem not in SECTION_7]
LOCATED = re.compile(r"^examples/hard/bad_\w+\.mom:(\d+):(\d+): error: ")
runner = CliRunner()


@pytest.mark.parametrize("problem", BAD, ids=lambda p: p.stem)
@pytest.mark.parametrize("precision", ["float", "exact"])
def test_bad_value_is_a_located_error(problem, precision, monkeypatch, update_golden):
    monkeypatch.chdir(EXAMPLES.parent)
    rel = str(problem.relative_to(EXAMPLES.parent))
    res = runner.invoke(app, ["solve", "--plain", "--precision", precision, rel])
    assert res.exit_code == 1, res.output
    assert res.stdout == ""
    m = LOCATED.match(res.stderr)
    assert m, res.stderr
    line, col = int(m.group(1)), int(m.group(2))
    lines = problem.read_text(encoding="utf-8").split("\n")
    assert 1 <= line <= len(lines) and 1 <= col <= len(lines[line - 1]) + 1
    assert "^" in res.stderr.splitlines()[2]  # the caret under the snippet
    if precision != "float":
        return
    golden = problem.with_suffix(".err")
    if update_golden or not golden.exists():
        golden.write_text(res.stderr, encoding="utf-8")
        if not update_golden:
            pytest.fail(f"created {golden.name}; review and commit it")
        return
    assert res.stderr == golden.read_text(encoding="utf-8")


def test_every_bad_example_is_in_the_readme():
    text = (HARD / "README.md").read_text(encoding="utf-8")
    assert not [p.name for p in BAD if p.name not in text]


def test_a_huge_but_finite_direction_is_normalised_not_overflowed():
    """`along (-1e200, 0)` is the direction (-1, 0): the same answer as the plain one
    (the rocket equation, dv = c ln(m0/m1) = 3000 ln(1000/700) m/s)."""
    text = (HARD / "bad_negative_exhaust.mom").read_text(encoding="utf-8").replace(
        "exhaust -3000 m/s along (-1, 0)", "exhaust 3000 m/s along (-1e200, 0)")
    for precision in ("float", "refine", "exact"):
        res = solve_source(Source("t.mom", text), precision=precision)
        assert res.status == "solved", res.diagnostics
        got = {a["name"]: a["si_value"] for a in res.report.answers}
        assert math.isclose(got["probe.vx@2"], 3000 * math.log(1000 / 700), rel_tol=1e-12)
