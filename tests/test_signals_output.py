"""Output that cannot be written and signals: never a traceback, never a process left.

A closed or full standard output is one line on stderr and exit 3; a reader that goes
away (`| head -1`) ends the run quietly (0, or 141 like other tools). SIGTERM, SIGHUP
and SIGINT end `momentum solve` of many files (worker processes) with 128 + signal,
and its workers with it, even when it is killed outright.
"""
from __future__ import annotations

import os
import signal
import subprocess
import sys
import time

import pytest

from conftest import EXAMPLES

PY = [sys.executable, "-m", "momentum_cli"]
SOLVED = str(EXAMPLES / "ball_bounce_rebound.mom")
SIMULATED = str(EXAMPLES / "simulate" / "ball_bounces.mom")
COMMANDS = [["solve", SOLVED], ["solve", "--json", SOLVED], ["simulate", SIMULATED],
            ["simulate", "--json", SIMULATED], ["check", SOLVED]]


def _env():
    return dict(os.environ, NO_COLOR="1")


@pytest.mark.parametrize("args", COMMANDS, ids=lambda a: "-".join(a[:-1]))
def test_full_disk_is_one_line_and_exit_3(args):
    with open("/dev/full", "w") as full:
        res = subprocess.run(PY + args, stdout=full, stderr=subprocess.PIPE, text=True,
                             env=_env(), timeout=120)
    assert res.returncode == 3
    assert "Traceback" not in res.stderr
    assert res.stderr.splitlines()[-1] == ("momentum: error: cannot write to standard "
                                           "output: No space left on device")


@pytest.mark.parametrize("args", COMMANDS, ids=lambda a: "-".join(a[:-1]))
def test_closed_stdout_is_one_line_and_exit_3(args):
    res = subprocess.run(PY + args, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                         text=True, env=_env(), timeout=120,
                         preexec_fn=lambda: os.close(1))
    assert res.returncode == 3
    assert res.stderr == "momentum: error: standard output is closed\n"


def test_broken_pipe_is_quiet():
    files = [str(p) for p in sorted(EXAMPLES.glob("*.mom"))]
    for extra in ([], ["--json"], ["-q"]):
        p = subprocess.Popen(PY + ["solve", *extra, *files], stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE, env=_env())
        p.stdout.readline()
        p.stdout.close()  # what `| head -1` does
        rc, err = _finish(p, 120)
        assert rc in (0, 141), (extra, rc, err)
        assert "Traceback" not in err and "BrokenPipe" not in err


def _finish(p: subprocess.Popen, seconds: float) -> tuple[int, str]:
    """The exit code and standard error of `p`, or a failure that says it hung: a
    process that never ends (or leaves a worker holding its stderr) must fail the test,
    not stall the run."""
    try:
        _, err = p.communicate(timeout=seconds)
    except subprocess.TimeoutExpired:
        children = _children(p.pid)
        p.kill()
        for child in children:
            try:
                os.kill(child, signal.SIGKILL)
            except OSError:
                pass
        p.communicate()
        pytest.fail(f"momentum did not end within {seconds} s (pid {p.pid})")
    return p.returncode, err.decode()


def _children(pid: int) -> list[int]:
    out = []
    for d in os.listdir("/proc"):
        if d.isdigit():
            try:
                with open(f"/proc/{d}/stat") as fh:
                    fields = fh.read().rsplit(")", 1)[1].split()
            except OSError:
                continue
            if int(fields[1]) == pid and fields[0] != "Z":
                out.append(int(d))
    return out


def _alive(pid: int) -> bool:
    try:
        with open(f"/proc/{pid}/stat") as fh:
            return fh.read().rsplit(")", 1)[1].split()[0] != "Z"
    except OSError:
        return False


@pytest.fixture(scope="module")
def many_files(tmp_path_factory):
    folder = tmp_path_factory.mktemp("many")
    text = (EXAMPLES / "disk_climbs_curb.mom").read_text(encoding="utf-8")
    paths = []
    for i in range(400):
        p = folder / f"f{i:03d}.mom"
        p.write_text(text, encoding="utf-8")
        paths.append(str(p))
    return paths


@pytest.mark.skipif(not sys.platform.startswith("linux") or (os.cpu_count() or 1) < 2,
                    reason="reads /proc; workers need two cores")
@pytest.mark.parametrize("sig", ["SIGTERM", "SIGHUP", "SIGINT", "SIGKILL"])
def test_signal_ends_parent_and_workers(many_files, sig):
    signum = getattr(signal, sig)
    p = subprocess.Popen(PY + ["solve", "-q", *many_files], stdout=subprocess.DEVNULL,
                         stderr=subprocess.PIPE, env=_env())
    workers: list[int] = []
    for _ in range(600):  # up to 60 s on a busy machine for the pool to start
        workers = _children(p.pid)
        if len(workers) >= 2 or p.poll() is not None:
            break
        time.sleep(0.1)
    if len(workers) < 2:
        p.kill()
        p.wait()
        pytest.skip("no worker processes were started here")
    p.send_signal(signum)
    rc, err = _finish(p, 30)
    assert rc in (128 + signum, -signum), (rc, err)
    assert "Traceback" not in err
    deadline = time.monotonic() + 2
    while any(_alive(w) for w in workers) and time.monotonic() < deadline:
        time.sleep(0.05)
    assert not [w for w in workers if _alive(w)]
