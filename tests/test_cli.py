"""The command line: exit codes, many files, `-`, --quiet, --json (against the shipped
schema), --version, --help, `check`, colour, stderr vs stdout, shell completion.

Most tests run in-process through typer's CliRunner; the real entry point
(`python -m momentum_cli`) is exercised by the tests marked `subprocess`.
"""
from __future__ import annotations

import json
import os
import re
import signal
import subprocess
import sys
import time
from importlib.resources import files

import jsonschema
import pytest
from conftest import EXAMPLES, ROOT
from typer.testing import CliRunner

from momentum_cli import __version__
from momentum_cli.cli import app
from momentum_cli.diagnostics import ExitCode

PROBLEMS = sorted(EXAMPLES.glob("*.mom"))
GOOD = EXAMPLES / "seed_plastic_collision.mom"
GOOD2 = EXAMPLES / "seed_disk_wall.mom"
ANSI = re.compile(r"\x1b\[")
QUIET_LINE = re.compile(r"^\S+ = -?[0-9][0-9.e+-]* ?\S*$")

SYNTAX_ERROR = "problem \"x\"\nbody rod: rod(mass = 10 kg, length = 1 m\n"
UNDER = """\
problem "under-determined"
body rod: rod(mass = 10 kg, length = 1 m)
point A = rod.end(-)
state 1: rod.v = (0, -3 m/s), rod.omega = 0, rod.angle = 30 deg
state 2
impact 1 -> 2:
    contact A with ground normal (0, 1): restitution ?, smooth
find rod.omega@2
"""

runner = CliRunner()


def cli(args, input=None, env=None):
    """Run the app in-process; `prog_name` as the installed script would have it."""
    return runner.invoke(app, [str(a) for a in args], input=input, env=env,
                         prog_name="momentum")


def real(args, input=None, env=None) -> subprocess.CompletedProcess:
    """Run `python -m momentum_cli` in a subprocess (bytes in, text out)."""
    path = os.pathsep.join(filter(None, [str(ROOT), os.environ.get("PYTHONPATH")]))
    full_env = dict(os.environ, PYTHONPATH=path)
    full_env.update(env or {})
    if isinstance(input, str):
        input = input.encode()
    proc = subprocess.run([sys.executable, "-m", "momentum_cli", *map(str, args)], input=input,
                          capture_output=True, cwd=ROOT, env=full_env, timeout=120)
    proc.stdout = proc.stdout.decode("utf-8")
    proc.stderr = proc.stderr.decode("utf-8")
    return proc


@pytest.fixture(scope="module")
def validator():
    text = files("momentum_cli").joinpath("schema").joinpath(
        "momentum-result.schema.json").read_text(encoding="utf-8")
    schema = json.loads(text)
    jsonschema.Draft202012Validator.check_schema(schema)
    return jsonschema.Draft202012Validator(schema)


def strict_json(text: str):
    """Parse JSON, refusing NaN and Infinity (which Python's json would accept)."""
    def bad(name):
        raise AssertionError(f"{name} in JSON output")
    return json.loads(text, parse_constant=bad)


def write(tmp_path, name: str, text: str | bytes):
    p = tmp_path / name
    p.write_bytes(text if isinstance(text, bytes) else text.encode("utf-8"))
    return p


# ---- exit codes --------------------------------------------------------------------------
def test_solved_file_exits_0_and_prints_answers():
    res = cli(["solve", "--plain", GOOD])
    assert res.exit_code == ExitCode.OK, res.output
    assert "Answers" in res.stdout and "T_lost@1->2 = 7.8 J" in res.stdout
    assert res.stderr == ""


def test_problem_error_exits_1(tmp_path):
    res = cli(["solve", write(tmp_path, "bad.mom", SYNTAX_ERROR)])
    assert res.exit_code == ExitCode.PROBLEM


def test_missing_file_exits_2_and_names_it(tmp_path):
    missing = tmp_path / "nope.mom"
    res = cli(["solve", missing])
    assert res.exit_code == ExitCode.USAGE
    assert res.stderr == f"{missing}: error: no such file\n"
    assert res.stdout == ""


def test_directory_exits_2(tmp_path):
    res = cli(["solve", tmp_path])
    assert res.exit_code == ExitCode.USAGE
    assert "is a directory" in res.stderr


def test_bad_option_exits_2_with_usage():
    res = cli(["solve", "--no-such-option", GOOD])
    assert res.exit_code == ExitCode.USAGE
    assert "No such option" in res.stderr and "Usage: momentum solve" in res.stderr


def test_bad_format_value_exits_2():
    res = cli(["solve", "--format", "xml", GOOD])
    assert res.exit_code == ExitCode.USAGE


@pytest.mark.parametrize("precision", ["float", "refine", "exact"])
def test_precision_modes_give_the_same_answers(precision):
    res = cli(["solve", "-q", "--precision", precision, GOOD2])
    assert res.exit_code == 0, res.output
    assert res.stdout == cli(["solve", "-q", GOOD2]).stdout


def test_unknown_precision_exits_2():
    assert cli(["solve", "--precision", "quad", GOOD]).exit_code == ExitCode.USAGE


def test_no_file_is_a_usage_error():
    res = cli(["solve"])
    assert res.exit_code == ExitCode.USAGE
    assert "Missing argument" in res.stderr


def test_internal_error_exits_3_with_one_line_and_no_traceback(monkeypatch):
    import momentum_cli.run as run

    def boom(*a, **k):
        raise RuntimeError("kaboom")

    monkeypatch.setattr(run, "solve_source", boom)
    res = cli(["solve", GOOD, GOOD2])
    assert res.exit_code == ExitCode.INTERNAL
    lines = res.stderr.splitlines()
    assert len(lines) == 2  # one line per file, and the second file was still tried
    assert "internal error: RuntimeError: kaboom" in lines[0]
    assert "--traceback" in lines[0] and "Traceback" not in res.stderr


def test_ctrl_c_exits_130(monkeypatch):
    import momentum_cli.run as run

    def interrupted(*a, **k):
        raise KeyboardInterrupt

    monkeypatch.setattr(run, "solve_source", interrupted)
    res = cli(["solve", GOOD])
    assert res.exit_code == ExitCode.INTERRUPTED


@pytest.mark.skipif(sys.platform == "win32", reason="POSIX signals")
def _wait_until_reading_stdin(pid: int) -> None:
    """Until the process blocks in read(0, ...) (Linux: /proc/PID/syscall); elsewhere, or
    after 60 s on a very busy machine, a fixed wait. A signal sent during start-up would
    test start-up, not the interrupted read."""
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline:
        try:
            with open(f"/proc/{pid}/syscall") as fh:
                if fh.read().startswith("0 0x0 "):
                    return
        except OSError:
            break
        time.sleep(0.05)
    time.sleep(2.0)


def test_real_ctrl_c_while_reading_stdin_exits_130():
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    proc = subprocess.Popen([sys.executable, "-m", "momentum_cli", "solve", "-"], cwd=ROOT,
                            env=env, stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE)
    try:
        _wait_until_reading_stdin(proc.pid)
        proc.send_signal(signal.SIGINT)
        _out, err = proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:
            proc.kill()
    assert proc.returncode == ExitCode.INTERRUPTED
    assert b"Traceback" not in err


# ---- many files -----------------------------------------------------------------------------
def test_one_broken_file_does_not_stop_the_others(tmp_path):
    bad = write(tmp_path, "bad.mom", SYNTAX_ERROR)
    res = cli(["solve", "--plain", GOOD, bad, GOOD2])
    assert res.exit_code == ExitCode.PROBLEM
    assert f"== {GOOD}:" in res.stdout and f"== {GOOD2}:" in res.stdout
    assert res.stderr.startswith(f"{bad}:2:41: error: syntax error: unexpected end of file")
    assert str(bad) not in res.stdout


def test_exit_code_is_the_worst_over_files(tmp_path):
    bad = write(tmp_path, "bad.mom", SYNTAX_ERROR)
    assert cli(["solve", GOOD, GOOD2]).exit_code == ExitCode.OK
    assert cli(["solve", bad, GOOD]).exit_code == ExitCode.PROBLEM
    assert cli(["solve", GOOD, tmp_path / "missing.mom", bad]).exit_code == ExitCode.USAGE
    assert cli(["check", bad, tmp_path / "missing.mom"]).exit_code == ExitCode.USAGE


def test_quiet_with_many_files_heads_each_file():
    res = cli(["solve", "-q", GOOD, GOOD2])
    assert res.exit_code == 0
    assert res.stdout.startswith(f"==> {GOOD} <==\n")
    assert f"==> {GOOD2} <==\n" in res.stdout


# ---- standard input -------------------------------------------------------------------------
def test_dash_reads_standard_input():
    res = cli(["solve", "-q", "-"], input=GOOD.read_text(encoding="utf-8"))
    assert res.exit_code == 0, res.output
    assert "T_lost@1->2 = 7.8 J" in res.stdout


def test_errors_from_standard_input_are_named_stdin():
    res = cli(["solve", "-"], input=SYNTAX_ERROR)
    assert res.exit_code == ExitCode.PROBLEM
    assert res.stderr.startswith("<stdin>:2:41: error: ")


def test_dash_mixes_with_files_and_is_named_stdin_in_json():
    res = cli(["solve", "--json", GOOD, "-"], input=UNDER)
    assert res.exit_code == ExitCode.PROBLEM
    doc = strict_json(res.stdout)
    assert [r["file"] for r in doc["results"]] == [str(GOOD), "<stdin>"]
    assert [r["status"] for r in doc["results"]] == ["solved", "error"]


def test_dash_twice_is_a_usage_error():
    res = cli(["solve", "-", "-"], input="")
    assert res.exit_code == ExitCode.USAGE
    assert "only once" in res.stderr


def test_binary_standard_input_is_a_named_error():
    res = cli(["solve", "-"], input=b"\xff\xfe\x00\x01")
    assert res.exit_code == ExitCode.PROBLEM
    assert res.stderr.startswith("<stdin>:1:3: error: not a text file")


# ---- output formats -------------------------------------------------------------------------
def test_quiet_prints_only_name_value_unit_lines():
    res = cli(["solve", "--quiet", GOOD2])
    assert res.exit_code == 0
    lines = res.stdout.splitlines()
    assert lines == ["t@1->2 = 3.04808 s", "disk.dtheta@1->2 = -91.4423 rad",
                     "alpha = 19.6845 rad/s^2", "J_n[disk]@1->2 = 300 N*s"]


@pytest.mark.parametrize("problem", PROBLEMS, ids=lambda p: p.stem)
def test_quiet_lines_have_the_name_value_unit_shape(problem):
    res = cli(["solve", "-q", problem])
    if res.exit_code == 0:
        assert res.stdout and all(QUIET_LINE.match(x) for x in res.stdout.splitlines()), \
            res.stdout


@pytest.mark.parametrize("problem", PROBLEMS, ids=lambda p: p.stem)
def test_json_of_every_example_matches_the_schema(problem, validator):
    res = cli(["solve", "--json", problem])
    doc = strict_json(res.stdout)
    validator.validate(doc)
    assert doc["schema_version"] == "1" and doc["momentum_version"] == __version__
    (r,) = doc["results"]
    assert r["file"] == str(problem)
    assert res.exit_code == (0 if r["status"] == "solved" else 1)


def test_json_answers_carry_value_unit_and_si_value(validator):
    doc = strict_json(cli(["solve", "--json", EXAMPLES / "seed_pendulum_wall.mom"]).stdout)
    answers = {a["name"]: a for a in doc["results"][0]["answers"]}
    angle = answers["pendulum.angle@4"]
    assert angle["unit"] == "deg"
    assert angle["value"] == pytest.approx(-39.7918, rel=1e-5)
    assert angle["si_value"] == pytest.approx(angle["value"] * 3.141592653589793 / 180)
    eq = doc["results"][0]["equations"][0]
    assert eq["index"] == 1 and isinstance(eq["line"], int)


ERROR_FILES = {
    "syntax": SYNTAX_ERROR,
    "under": UNDER,
    "empty": "",
    "binary": b"\x00\x01\x02",
    "latin1": 'problem "caf\xe9"\n'.encode("latin-1"),
    "deep": "let a = " + "(" * 500 + "1" + ")" * 500 + "\n",
    "huge": "let a = 1e999\n",
    "comments-only": "# nothing here\n",
}


@pytest.mark.parametrize("command", ["solve", "check"])
def test_json_of_errors_matches_the_schema_and_goes_to_stdout_only(command, tmp_path, validator):
    paths = [write(tmp_path, f"{k}.mom", v) for k, v in ERROR_FILES.items()]
    paths.append(tmp_path / "missing.mom")
    res = cli([command, "--json", *paths])
    assert res.exit_code == ExitCode.USAGE  # the missing file is the worst
    assert res.stderr == ""
    doc = strict_json(res.stdout)
    validator.validate(doc)
    statuses = [r["status"] for r in doc["results"]]
    assert statuses == ["error"] * len(ERROR_FILES) + ["unreadable"]
    for r in doc["results"]:
        assert any(d["severity"] == "error" for d in r["diagnostics"])


def test_json_error_diagnostics_carry_one_based_positions(tmp_path):
    path = write(tmp_path, "bad.mom", SYNTAX_ERROR)
    doc = strict_json(cli(["solve", "--json", path]).stdout)
    (d,) = doc["results"][0]["diagnostics"]
    assert (d["severity"], d["code"], d["line"], d["column"]) == ("error", "syntax", 2, 41)


def test_check_json_matches_the_schema(validator):
    res = cli(["check", "--json", *PROBLEMS])
    doc = strict_json(res.stdout)
    validator.validate(doc)
    for r in doc["results"]:
        assert r["status"] in ("checked", "error")
        assert set(r["counts"]) >= {"unknowns", "equations", "blocks"}


def test_json_never_contains_nan_even_for_non_finite_values(tmp_path, validator):
    # a problem whose numbers overflow to inf inside the solver: JSON must say null
    text = GOOD.read_text(encoding="utf-8").replace("3 m/s", "1e300 m/s").replace(
        "2 m/s", "1e300 m/s")
    res = cli(["solve", "--json", write(tmp_path, "big.mom", text)])
    doc = strict_json(res.stdout)
    validator.validate(doc)
    assert "NaN" not in res.stdout and "Infinity" not in res.stdout


def test_schema_file_ships_inside_the_package():
    schema = files("momentum_cli").joinpath("schema").joinpath("momentum-result.schema.json")
    assert schema.is_file()
    assert json.loads(schema.read_text(encoding="utf-8"))["$schema"].endswith("2020-12/schema")


# ---- colour, streams ------------------------------------------------------------------------
def test_errors_go_to_stderr_and_results_to_stdout(tmp_path):
    bad = write(tmp_path, "bad.mom", SYNTAX_ERROR)
    res = cli(["solve", "--plain", bad, GOOD])
    assert "error:" not in res.stdout
    assert "Answers" not in res.stderr and "error:" in res.stderr


def test_plain_output_has_no_ansi_escapes_even_when_colour_is_forced(tmp_path):
    bad = write(tmp_path, "bad.mom", SYNTAX_ERROR)
    env = {"FORCE_COLOR": "1", "TERM": "xterm-256color", "NO_COLOR": "", "TTY_COMPATIBLE": "1",
           "PY_COLORS": "1"}
    proc = real(["solve", "--plain", GOOD, bad], env=env)
    assert proc.returncode == ExitCode.PROBLEM
    assert "Answers" in proc.stdout
    assert not ANSI.search(proc.stdout) and not ANSI.search(proc.stderr)
    proc = real(["solve", "--help"], env=env)
    assert not ANSI.search(proc.stdout)


def test_non_ascii_title_under_an_ascii_locale_prints_escaped_not_a_traceback(tmp_path):
    text = GOOD.read_text(encoding="utf-8").replace(
        "Perfectly plastic collision of two particles", "plastic \u2014 \u00fc \u2206")
    path = write(tmp_path, "uni.mom", text)
    env = {"PYTHONIOENCODING": "ascii"}
    proc = real(["solve", "--plain", path], env=env)
    assert proc.returncode == 0 and "Traceback" not in proc.stderr
    assert "plastic \\u2014" in proc.stdout
    proc = real(["solve", "--json", path], env=env)
    assert proc.returncode == 0
    assert strict_json(proc.stdout)["results"][0]["title"] == "plastic \u2014 \u00fc \u2206"


def test_piped_output_defaults_to_plain():
    proc = real(["solve", GOOD])
    assert proc.returncode == 0
    assert proc.stdout == cli(["solve", "--plain", GOOD]).stdout


# ---- version, help ---------------------------------------------------------------------------
def test_version_prints_the_version_and_exits_0():
    for flag in ("--version", "-V"):
        res = cli([flag])
        assert res.exit_code == 0
        assert res.stdout == f"momentum {__version__}\n"


@pytest.mark.parametrize("args", [["--help"], ["-h"], ["solve", "--help"], ["check", "--help"],
                                  ["solve", "-h"]], ids=" ".join)
def test_help_on_every_command(args):
    res = cli(args)
    assert res.exit_code == 0
    assert res.stdout.startswith("Usage: momentum")
    assert "--help" in res.stdout


def test_app_help_lists_commands_and_exit_codes():
    out = cli(["--help"]).stdout
    assert "solve" in out and "check" in out
    assert "Exit codes" in out and "130" in out


def test_solve_help_shows_examples_and_options():
    out = cli(["solve", "--help"]).stdout
    for word in ("--format", "--json", "--quiet", "--plain", "momentum solve --json"):
        assert word in out


# ---- check -------------------------------------------------------------------------------------
def test_check_reports_counts_for_a_good_file_and_exits_0():
    res = cli(["check", GOOD2])
    assert res.exit_code == 0
    assert re.match(rf"{re.escape(str(GOOD2))}: ok: \d+ unknowns, \d+ equations", res.stdout)


def test_check_reports_every_file_and_exits_with_the_worst(tmp_path):
    under = write(tmp_path, "under.mom", UNDER)
    bad = write(tmp_path, "bad.mom", SYNTAX_ERROR)
    res = cli(["check", GOOD, under, bad])
    assert res.exit_code == ExitCode.PROBLEM
    assert f"{GOOD}: ok:" in res.stdout
    assert f"{under}: error:" in res.stdout
    assert "under-determined: " in res.stderr and "rod.omega@2" in res.stderr
    assert f"{bad}:2:41: error: syntax error" in res.stderr


def test_check_of_every_example_does_not_crash():
    res = cli(["check", *PROBLEMS])
    assert res.exit_code in (0, 1)
    assert "internal error" not in res.stderr


# ---- shell completion ---------------------------------------------------------------------
COMPLETE = {"_MOMENTUM_COMPLETE": "complete_bash", "COMP_WORDS": "momentum solve --f",
            "COMP_CWORD": "2"}


def test_completion_offers_format():
    res = cli([], env=COMPLETE)
    assert res.exit_code == 0
    assert "--format" in res.stdout.split()


def test_completion_offers_the_format_values():
    res = cli([], env=dict(COMPLETE, COMP_WORDS="momentum solve --format ", COMP_CWORD="3"))
    assert res.stdout.split() == ["auto", "rich", "plain", "json", "markdown", "latex", "html"]


def test_completion_through_the_real_entry_point():
    proc = real([], env=COMPLETE)
    assert proc.returncode == 0
    assert "--format" in proc.stdout.split()


# ---- the real entry point ---------------------------------------------------------------------
def test_real_entry_point_exit_codes(tmp_path):
    bad = write(tmp_path, "bad.mom", SYNTAX_ERROR)
    assert real(["solve", "-q", GOOD]).returncode == 0
    proc = real(["solve", "-q", GOOD, bad])
    assert proc.returncode == 1
    assert proc.stderr.startswith(f"{bad}:2:41: error: ")
    assert "T_lost@1->2 = 7.8 J" in proc.stdout
    assert real(["solve", tmp_path / "missing.mom"]).returncode == 2
    proc = real(["solve", "--bogus", GOOD])
    assert proc.returncode == 2 and "Usage: momentum solve" in proc.stderr
    proc = real(["--version"])
    assert (proc.returncode, proc.stdout) == (0, f"momentum {__version__}\n")


def test_real_entry_point_reads_stdin_and_writes_valid_json(validator):
    proc = real(["solve", "--json", "-"], input=UNDER)
    assert proc.returncode == 1 and proc.stderr == ""
    doc = strict_json(proc.stdout)
    validator.validate(doc)
    assert doc["results"][0]["file"] == "<stdin>"


def test_real_entry_point_never_prints_a_traceback(tmp_path):
    paths = [write(tmp_path, f"{k}.mom", v) for k, v in ERROR_FILES.items()]
    proc = real(["solve", *paths])
    assert proc.returncode == 1
    assert "Traceback" not in proc.stderr
    assert len([x for x in proc.stderr.splitlines() if ": error: " in x]) == len(paths)


def test_many_files_are_solved_in_parallel_with_the_same_output_in_order(tmp_path):
    """From PARALLEL_MIN files on, worker processes solve them; the report must be the
    serial one, in the given order, with the worst exit code."""
    from momentum_cli.run import PARALLEL_MIN

    seeds = sorted(EXAMPLES.glob("seed_*.mom"))
    paths = []
    for k in range(PARALLEL_MIN + 2):
        p = tmp_path / f"p{k:03d}.mom"
        p.write_text(seeds[k % len(seeds)].read_text(encoding="utf-8"), encoding="utf-8")
        paths.append(str(p))
    bad = tmp_path / "bad.mom"
    bad.write_text("body b: rod(mass = 1 m, length = 1 m)\n", encoding="utf-8")
    args = [sys.executable, "-m", "momentum_cli", "solve", "--plain", *paths, str(bad)]
    par = subprocess.run(args, capture_output=True, text=True, timeout=300)
    ser = subprocess.run(args + ["--traceback"], capture_output=True, text=True, timeout=300)
    assert par.returncode == ser.returncode == 1
    assert par.stdout == ser.stdout and par.stderr == ser.stderr
    assert par.stdout.count("\n== ") == len(paths) - 1
