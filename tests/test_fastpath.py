"""The fast path (a one-shot `solve` without typer) against typer's `solve`: the same
standard output, standard error and exit code byte for byte, for every example and
several option combinations; anything else goes to typer; typer is not imported.
"""
from __future__ import annotations

import io
import os
import subprocess
import sys

import pytest
from conftest import EXAMPLES

from momentum_cli import fastpath, solve_cmd
from momentum_cli.cli import app

ROOT = EXAMPLES.parent
PROBLEMS = sorted(EXAMPLES.glob("*.mom"))
SEED = "examples/seed_rod_drop_smooth.mom"


class _Bytes(io.BytesIO):
    def close(self):  # the text wrapper, when dropped, leaves the bytes readable
        pass


def _capture(call):
    """(exit code, stdout bytes, stderr bytes) of `call`, which ends in SystemExit."""
    out, err = _Bytes(), _Bytes()
    saved = sys.stdout, sys.stderr
    sys.stdout = io.TextIOWrapper(out, encoding="utf-8", write_through=True)
    sys.stderr = io.TextIOWrapper(err, encoding="utf-8", write_through=True)
    code = "returned"
    try:
        call()
    except SystemExit as done:
        code = done.code
    finally:
        sys.stdout.flush()
        sys.stderr.flush()
        sys.stdout, sys.stderr = saved
    return code, out.getvalue(), err.getvalue()


def _both(argv):
    def fast():
        if fastpath.try_solve(argv) is False:
            raise AssertionError(f"the fast path did not take {argv}")

    typer_run = _capture(lambda: app(argv, prog_name="momentum"))
    return _capture(fast), typer_run


@pytest.mark.parametrize("path", PROBLEMS, ids=lambda p: p.name)
def test_every_example_plain_is_identical(path, monkeypatch):
    monkeypatch.chdir(ROOT)
    fast, typer_run = _both(["solve", "--plain", str(path.relative_to(ROOT))])
    assert fast == typer_run


OPTIONS = [["--json"], ["-q"], ["--quiet", "--all"], ["--plain", "--all", "-p", "4"],
           ["--precision", "exact", "--plain"], ["--precision=refine", "--plain"],
           ["--units", "us", "--plain"], ["--steps", "brief", "--plain", "--no-pager"],
           ["--format", "json", "--digits=3"], ["--jsonl"], ["--strict", "--plain"],
           ["-f", "plain", "--color", "never"], ["--json", "--units", "si", "-p", "17"]]


@pytest.mark.parametrize("opts", OPTIONS, ids=" ".join)
@pytest.mark.parametrize("name", ["seed_rod_drop_smooth.mom", "seed_pendulum_wall.mom",
                                  "seed_disk_wall.mom"])
def test_options_are_identical(name, opts, monkeypatch):
    monkeypatch.chdir(ROOT)
    fast, typer_run = _both(["solve", *opts, f"examples/{name}"])
    assert fast == typer_run


def test_several_files_and_a_missing_one_are_identical(monkeypatch):
    monkeypatch.chdir(ROOT)
    argv = ["solve", "--plain", SEED, "examples/no_such_file.mom",
            "examples/seed_disk_wall.mom"]
    fast, typer_run = _both(argv)
    assert fast == typer_run
    assert fast[0] == 2


@pytest.mark.parametrize("argv", [
    ["solve", "--help"], ["solve", "-h"], ["solve", "--set", "x=1", SEED],
    ["solve", "--sensitivity", SEED], ["check", SEED], ["simulate", SEED], ["--version"],
    ["solve"], [], ["solve", "--json", "--plain", SEED], ["solve", "-p", "0", SEED],
    ["solve", "-p4", SEED], ["solve", "-qp", "4", SEED], ["solve", "--digits", "x", SEED],
    ["solve", "--format", "rich", SEED], ["solve", "--format", "html", SEED],
    ["solve", "--precision", "fast", SEED], ["solve", "--plain=1", SEED],
    ["solve", "-o", "out.md", SEED], ["solve", "--", SEED], ["solve", "examples"],
    ["solve", "-p", "3", "-p", "4", SEED], ["solve", "--traceback", SEED],
    ["solve", "-", "-"], ["solve", "--unknown", SEED]])
def test_anything_else_goes_to_typer(argv, monkeypatch):
    monkeypatch.chdir(ROOT)
    code, out, err = _capture(lambda: sys.exit(7) if fastpath.try_solve(argv) is False
                              else None)
    assert (code, out, err) == (7, b"", b"")


def test_rich_output_on_a_terminal_goes_to_typer(monkeypatch):
    monkeypatch.chdir(ROOT)
    monkeypatch.delenv("TERM", raising=False)

    class Terminal(io.StringIO):
        def isatty(self):
            return True

    monkeypatch.setattr(sys, "stdout", Terminal())
    assert fastpath.try_solve(["solve", SEED]) is False
    assert fastpath.parse(["solve", "--plain", SEED]) is not None  # --plain: still fast


def test_typer_solve_has_the_shared_defaults():
    """The two entries cannot disagree: typer's options default to SOLVE_DEFAULTS, and
    every option the fast path reads is typer's option of the same keyword."""
    import typer.main

    solve = typer.main.get_command(app).commands["solve"]
    params = {p.name: p for p in solve.params if p.name != "files"}
    assert set(params) == set(solve_cmd.SOLVE_DEFAULTS)
    for name, param in params.items():
        want = solve_cmd.SOLVE_DEFAULTS[name]
        got = param.default
        if name == "sets":
            assert not got and not want
        else:
            assert got == (want.value if hasattr(want, "value") else want), name
    for table in (fastpath._FLAGS, fastpath._VALUED):
        for opt, key in table.items():
            assert opt in params[key].opts + params[key].secondary_opts, opt


# ---- whole processes: `python -m momentum_cli` with and without the fast path ----------

def _process(args, fast: bool, stdin: bytes | None = None):
    env = dict(os.environ, NO_COLOR="1")
    env.pop("MOMENTUM_NO_FASTPATH", None)
    if not fast:
        env["MOMENTUM_NO_FASTPATH"] = "1"
    p = subprocess.run([sys.executable, "-m", "momentum_cli", *args], cwd=ROOT, env=env,
                       input=stdin, capture_output=True,
                       stdin=None if stdin is not None else subprocess.DEVNULL)
    return p.returncode, p.stdout, p.stderr


def _bad_file(tmp_path):
    bad = tmp_path / "bad.mom"
    text = (EXAMPLES / "seed_rod_drop_smooth.mom").read_text(encoding="utf-8")
    bad.write_text(text.replace("find", "fnd", 1), encoding="utf-8")
    return str(bad)


@pytest.mark.parametrize("case", ["plain", "json", "error", "missing", "stdin"])
def test_processes_are_identical(case, tmp_path):
    stdin = None
    if case == "plain":
        args = ["solve", "--plain", SEED]
    elif case == "json":
        args = ["solve", "--json", SEED, "examples/seed_disk_wall.mom"]
    elif case == "error":
        args = ["solve", "--plain", _bad_file(tmp_path)]
    elif case == "missing":
        args = ["solve", "-q", "examples/no_such_file.mom"]
    else:
        args, stdin = ["solve", "-q", "-"], (ROOT / SEED).read_bytes()
    fast = _process(args, True, stdin)
    assert fast == _process(args, False, stdin)
    assert fast[0] == {"plain": 0, "json": 0, "error": 1, "missing": 2, "stdin": 0}[case]
    if case == "error":
        assert b"bad.mom:" in fast[2] and b": error: " in fast[2]


def test_a_fast_solve_does_not_import_typer(tmp_path):
    code = ("import sys; sys.argv = ['momentum', 'solve', '--plain', %r]\n"
            "from momentum_cli.__main__ import main\n"
            "try:\n    main()\nexcept SystemExit as e:\n    rc = e.code\n"
            "sys.stderr.write(repr((rc, [m for m in ('typer', 'click', 'typer._click', "
            "'rich', 'numpy', 'momentum_cli.cli') if m in sys.modules])))\n" % SEED)
    p = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True)
    assert p.stderr.decode().strip().endswith("(0, [])"), p.stderr.decode()[-2000:]
    assert p.stdout.startswith(b"== " + SEED.encode())
