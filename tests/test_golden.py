"""Golden files: each example's plain and JSON output (and the seeds' Markdown), reviewed
like code.

`pytest --update-golden` rewrites them deliberately; a missing golden is created
and the test fails so that it gets reviewed. On a mismatch the obtained output is
written beside the golden as NAME.obtained.out (git-ignored).
"""
from __future__ import annotations

import json
import math

import pytest
from conftest import EXAMPLES
from typer.testing import CliRunner

from momentum_cli.cli import app

PROBLEMS = sorted(EXAMPLES.glob("*.mom"))
runner = CliRunner()


def run_cli(args: list[str]) -> str:
    res = runner.invoke(app, args)
    assert res.exit_code == 0, res.output
    return res.stdout


def _rel(path):
    return str(path.relative_to(EXAMPLES.parent))


def _written(golden, text: str, update: bool) -> bool:
    """With --update-golden, rewrite the golden (True). A missing golden is created and
    the test fails, so that it is reviewed before it is committed."""
    if update:
        golden.write_text(text, encoding="utf-8")
        return True
    if not golden.exists():
        golden.write_text(text, encoding="utf-8")
        pytest.fail(f"created {golden.name}; review and commit it")
    return False


@pytest.mark.parametrize("problem", PROBLEMS, ids=lambda p: p.stem)
def test_plain_output_matches_golden(problem, update_golden, monkeypatch):
    monkeypatch.chdir(EXAMPLES.parent)
    got = run_cli(["solve", "--plain", _rel(problem)])
    golden = problem.with_suffix(".out")
    if _written(golden, got, update_golden):
        return
    want = golden.read_text(encoding="utf-8")
    if got != want:
        problem.with_suffix(".obtained.out").write_text(got, encoding="utf-8")
    assert got == want


def _close(a, b, path="$"):
    """JSON equality with a tolerance on numbers (BLAS may touch the last digit)."""
    if isinstance(a, float) or isinstance(b, float):
        assert isinstance(a, (int, float)) and isinstance(b, (int, float)), path
        assert math.isclose(a, b, rel_tol=1e-9, abs_tol=1e-12), f"{path}: {a} != {b}"
    elif isinstance(a, dict):
        assert isinstance(b, dict) and a.keys() == b.keys(), path
        for k in a:
            _close(a[k], b[k], f"{path}.{k}")
    elif isinstance(a, list):
        assert isinstance(b, list) and len(a) == len(b), path
        for i, (x, y) in enumerate(zip(a, b)):
            _close(x, y, f"{path}[{i}]")
    else:
        assert a == b, f"{path}: {a!r} != {b!r}"


@pytest.mark.parametrize("problem", PROBLEMS, ids=lambda p: p.stem)
def test_json_output_matches_golden(problem, update_golden, monkeypatch):
    monkeypatch.chdir(EXAMPLES.parent)
    got = run_cli(["solve", "--json", _rel(problem)])
    doc = json.loads(got)
    doc.pop("momentum_version")
    golden = problem.with_suffix(".json")
    text = json.dumps(doc, indent=2, ensure_ascii=False) + "\n"
    if _written(golden, text, update_golden):
        return
    want = json.loads(golden.read_text(encoding="utf-8"))
    try:
        _close(doc, want)
    except AssertionError:
        problem.with_suffix(".obtained.json").write_text(text, encoding="utf-8")
        raise


SEEDS = sorted(EXAMPLES.glob("seed_*.mom"))


@pytest.mark.parametrize("problem", SEEDS, ids=lambda p: p.stem)
def test_markdown_matches_golden(problem, update_golden, monkeypatch):
    """The seeds' Markdown solution sheets (`examples/seed_*.md`), reviewed like code."""
    monkeypatch.chdir(EXAMPLES.parent)
    got = run_cli(["solve", "--format", "markdown", _rel(problem)])
    golden = problem.with_suffix(".md")
    if _written(golden, got, update_golden):
        return
    want = golden.read_text(encoding="utf-8")
    if got != want:
        problem.with_suffix(".obtained.md").write_text(got, encoding="utf-8")
    assert got == want
