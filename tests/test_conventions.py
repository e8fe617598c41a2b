"""Command-line conventions: conflicting flags, --strict, colour, directories, titles of
files with errors, reproducible simulate JSON, options that are not finite, limits on a
run, and files written on request (checked first, atomic, never over data)."""
from __future__ import annotations

import json
import os
import subprocess
import sys

import pytest
from conftest import EXAMPLES
from typer.testing import CliRunner

from momentum_cli.cli import app
from momentum_cli.diagnostics import ExitCode

runner = CliRunner()
GOOD = EXAMPLES / "ball_bounce_rebound.mom"
WARNS = EXAMPLES / "hard" / "km_rod_pinned_struck_near_pin.mom"
SIM = EXAMPLES / "simulate" / "ball_bounces.mom"
ROD_DISK = EXAMPLES / "seed_rod_disk_bearing.mom"
PY = [sys.executable, "-m", "momentum_cli"]


def cli(args, env=None):
    return runner.invoke(app, [str(a) for a in args], env=env, prog_name="momentum")


@pytest.mark.parametrize("flags", [["--json", "--plain"], ["--json", "--format", "rich"],
                                   ["--plain", "--format", "json"]])
def test_conflicting_output_flags_are_a_usage_error(flags):
    res = cli(["solve", *flags, GOOD])
    assert res.exit_code == ExitCode.USAGE
    assert "give one" in res.stderr


def test_strict_turns_warnings_into_errors():
    assert cli(["solve", "-q", WARNS]).exit_code == ExitCode.OK
    res = cli(["solve", "-q", "--strict", WARNS])
    assert res.exit_code == ExitCode.PROBLEM
    assert "--strict" in res.stderr and "error:" in res.stderr
    assert cli(["solve", "-q", "--strict", GOOD]).exit_code == ExitCode.OK  # no warning
    doc = json.loads(cli(["solve", "--json", "--strict", WARNS]).stdout)
    assert doc["results"][0]["status"] == "error"


def test_color_always_never_and_force_color():
    bad_env = {"NO_COLOR": ""}
    res = cli(["solve", "--color", "always", EXAMPLES / "hard" / "bad_double_pin.mom"],
              env=bad_env)
    assert "\x1b[1;31merror:" in res.stderr
    res = cli(["solve", "--color", "never", EXAMPLES / "hard" / "bad_double_pin.mom"],
              env={"NO_COLOR": "", "FORCE_COLOR": "1"})
    assert "\x1b[" not in res.stderr
    res = cli(["solve", EXAMPLES / "hard" / "bad_double_pin.mom"],
              env={"NO_COLOR": "", "FORCE_COLOR": "1"})
    assert "\x1b[1;31merror:" in res.stderr


def test_a_directory_means_its_mom_files_recursively(tmp_path):
    (tmp_path / "sub").mkdir()
    (tmp_path / "a.mom").write_text(GOOD.read_text())
    (tmp_path / "sub" / "b.mom").write_text(GOOD.read_text())
    (tmp_path / "notes.txt").write_text("not a problem")
    res = cli(["solve", "--json", tmp_path])
    assert res.exit_code == 0
    files = [r["file"] for r in json.loads(res.stdout)["results"]]
    assert files == [str(tmp_path / "a.mom"), str(tmp_path / "sub" / "b.mom")]


def test_json_of_a_file_with_errors_keeps_its_title(tmp_path):
    bad = tmp_path / "bad.mom"
    bad.write_text('problem "Two bounces"\nbody b: particle(mass = -1 kg)\n')
    for cmd in ("solve", "check", "simulate"):
        doc = json.loads(cli([cmd, "--json", bad]).stdout)
        key = "simulations" if cmd == "simulate" else "results"
        assert doc[key][0]["status"] == "error"
        assert doc[key][0]["title"] == "Two bounces"


def test_simulate_json_is_reproducible_without_timings():
    one, two = cli(["simulate", "--json", SIM]).stdout, cli(["simulate", "--json", SIM]).stdout
    assert one == two and '"seconds"' not in one
    assert '"seconds"' in cli(["simulate", "--json", "--timings", SIM]).stdout


@pytest.mark.parametrize("opt", [["--dt", "nan"], ["--dt", "inf"], ["--rtol", "nan"],
                                 ["--rtol", "inf"], ["--max-time", "nan"], ["--dt", "-1"]])
def test_non_finite_simulate_options_exit_2(opt):
    res = cli(["simulate", *opt, SIM])
    assert res.exit_code == ExitCode.USAGE


@pytest.mark.parametrize("opt", [["--dt", "1"], ["--dt", "1e6", "--integrate"]])
def test_a_step_longer_than_a_phase_is_clamped(opt):
    res = cli(["simulate", "--plain", *opt, ROD_DISK])
    assert res.exit_code == ExitCode.OK, res.output


def test_max_events_and_max_time_stop_with_a_located_error():
    res = cli(["simulate", "--plain", "--max-events", "3", SIM])
    assert res.exit_code == ExitCode.PROBLEM
    assert f"{SIM}:" in res.stderr and "3 events" in res.stderr and "--max-events" in res.stderr
    res = cli(["simulate", "--plain", "--integrate", "--max-time", "1e-9", SIM])
    assert res.exit_code == ExitCode.PROBLEM
    assert "--max-time" in res.stderr and f"{SIM}:" in res.stderr


def test_library_warnings_do_not_reach_stderr():
    proc = subprocess.run(PY + ["simulate", "--plain", "--rtol", "1e-14", str(SIM)],
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0
    assert proc.stderr == ""


def test_columns_zero_on_a_terminal_still_prints():
    import pty

    master, slave = pty.openpty()
    env = dict(os.environ, COLUMNS="0", TERM="xterm")
    env.pop("NO_COLOR", None)
    p = subprocess.Popen(PY + ["solve", str(GOOD)], stdout=slave, stderr=subprocess.PIPE,
                         env=env)
    os.close(slave)
    data = b""
    while True:
        try:
            chunk = os.read(master, 65536)
        except OSError:
            break
        if not chunk:
            break
        data += chunk
    os.close(master)
    assert p.wait(timeout=60) == 0
    assert b"rebound" in data


# ---- files written on request ----------------------------------------------------------
def _sim(tmp_path, *args):
    src = tmp_path / "ball.mom"
    if not src.exists():
        src.write_text(SIM.read_text())
    return cli(["simulate", "--plain", *args, src]), src


def test_csv_never_overwrites_the_input(tmp_path):
    src = tmp_path / "ball.mom"
    src.write_text(SIM.read_text())
    before = src.read_text()
    for extra in ([], ["--force"]):
        res = cli(["simulate", "--csv", src, *extra, src])
        assert res.exit_code == ExitCode.USAGE
        assert "input file" in res.stderr and len(res.stderr.splitlines()) == 1
    assert src.read_text() == before


def test_csv_never_overwrites_an_existing_file_without_force(tmp_path):
    out = tmp_path / "out.csv"
    out.write_text("keep me")
    res, _ = _sim(tmp_path, "--csv", out)
    assert res.exit_code == ExitCode.USAGE and "--force" in res.stderr
    assert out.read_text() == "keep me"
    assert "Events" not in res.stdout  # refused before the run
    res, _ = _sim(tmp_path, "--csv", out, "--force")
    assert res.exit_code == 0
    lines = out.read_text().splitlines()
    assert lines[0].startswith("t,") and len(lines) > 10
    assert sorted(p.name for p in tmp_path.iterdir()) == ["ball.mom", "out.csv"]  # no temp


@pytest.mark.parametrize("target", ["no/such/dir/x.csv", ".", "/dev/full"])
def test_unwritable_csv_paths_are_refused_before_the_run(tmp_path, target, monkeypatch):
    monkeypatch.chdir(tmp_path)
    res, _ = _sim(tmp_path, "--csv", target)
    assert res.exit_code == ExitCode.USAGE
    assert res.stderr.startswith("momentum: error: --csv") and len(res.stderr.splitlines()) == 1


def test_read_only_folder_is_refused(tmp_path):
    if os.geteuid() == 0:
        pytest.skip("root writes into read-only folders")
    ro = tmp_path / "ro"
    ro.mkdir()
    ro.chmod(0o500)
    res, _ = _sim(tmp_path, "--csv", ro / "x.csv")
    assert res.exit_code == ExitCode.USAGE


def test_csv_dash_is_standard_output(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    res, _ = _sim(tmp_path, "--csv", "-")
    assert res.exit_code == 0
    assert res.stdout.startswith("t,")
    assert not (tmp_path / "-").exists()


def test_plot_of_an_unknown_type_is_refused_before_the_run(tmp_path):
    pytest.importorskip("matplotlib")
    res, _ = _sim(tmp_path, "--plot", tmp_path / "x.xyz")
    assert res.exit_code == ExitCode.USAGE and "unknown file type" in res.stderr


def test_writer_is_atomic_and_refuses_a_file_that_appeared(tmp_path):
    from momentum_cli.outputs import OutputError, write_text

    target = tmp_path / "x.csv"
    write_text(str(target), "a\n", False, "--csv")
    assert target.read_text() == "a\n"
    with pytest.raises(OutputError):
        write_text(str(target), "b\n", False, "--csv")
    assert target.read_text() == "a\n"
    write_text(str(target), "c\n", True, "--csv")
    assert target.read_text() == "c\n"
    assert [p.name for p in tmp_path.iterdir()] == ["x.csv"]
