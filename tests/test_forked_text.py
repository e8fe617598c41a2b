"""One big file's report made by two processes (forked_text, two_process): the plain
text in ranges between cuts (text.iter_parts' `start`, `stop`; report/text_cuts.py)
joins to the whole text, and `solve --plain` through the fork writes the same bytes,
exit code and errors as one process (MOMENTUM_SERIAL_REPORT=1): whatever share of the
ranges the child takes, when the child fails, dies or never runs, and when a piece meets
a bug half-way (in either process's part). `solve --json`'s report fields, shared out
the same way, are the same strings. No child is left behind."""
from __future__ import annotations

import os
import signal
import subprocess
import sys
from pathlib import Path

import pytest

from momentum_cli import forked_text, solve_cmd, two_process
from momentum_cli.bench import chain_text
from momentum_cli.report import text
from momentum_cli.report.text_cuts import cuts
from momentum_cli.run import read_source, solve_source

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tests"))
from test_hard import cradle_text  # noqa: E402

EXAMPLES = sorted((ROOT / "examples").glob("*.mom"))
SCENES = [("chain", lambda n: chain_text(n)), ("cradle", lambda n: cradle_text(n, "sequence")),
          ("simultaneous", lambda n: cradle_text(n, "simultaneous"))]


def _big(tmp_path, kind: str, n: int) -> Path:
    path = tmp_path / f"{kind}{n}.mom"
    path.write_text(dict(SCENES)[kind](n))
    return path


def _lazy(path):
    return solve_source(read_source(str(path)), False, 6, "float", lazy=True).report


def _whole(path) -> str:
    """The general path: the report built whole (not lazy), its text in one piece."""
    return text.render(solve_source(read_source(str(path)), False, 6, "float").report, 6)


def _ranges(rep, marks) -> str:
    bounds = [None] + marks + [None]
    return "\n".join("\n".join(text.iter_parts(rep, 6, True, bounds[k], bounds[k + 1]))
                     for k in range(len(bounds) - 1))


@pytest.mark.parametrize("kind", ["chain", "cradle", "simultaneous"])
@pytest.mark.parametrize("n", [2, 3, 17, 120])
def test_ranges_join_to_the_whole_text(tmp_path, kind, n):
    """Any number of ranges (one per row at most) joins to the text of the report built
    whole; every range has a piece."""
    path = _big(tmp_path, kind, n)
    want = _whole(path)
    rep = _lazy(path)
    for count in (2, 3, 7, 32, 10 ** 6):
        marks = cuts(rep.transitions, count)
        assert marks == sorted(set(marks)) and marks[-1] == (len(rep.transitions), 0)
        assert _ranges(rep, marks) == want, count
        bounds = [None] + marks + [None]
        for k in range(len(bounds) - 1):
            assert list(text.iter_parts(rep, 6, True, bounds[k], bounds[k + 1]))


def test_ranges_of_every_example_and_of_a_report_built_whole():
    """Cuts at every transition and inside its rows (at each row), on lazy reports and on
    reports built whole (plain lists): the same text."""
    for path in EXAMPLES:
        res = solve_source(read_source(str(path)), False, 6, "float")
        if res.report is None:
            continue
        want = text.render(res.report, 6)
        for rep in (res.report, _lazy(path)):
            marks = []
            for i, t in enumerate(rep.transitions):
                marks.append((i, 0))
                marks += [(i, r) for r in range(1, len(t["equations"]))]
            marks.append((len(rep.transitions), 0))
            marks = marks[1:]  # (0, 0): the head alone is a range too, but one is enough
            assert _ranges(rep, marks) == want, path.name


def _run(args, capsys, **kw):
    """run_solve in this process: (exit code, stdout, stderr)."""
    opts = dict(solve_cmd.SOLVE_DEFAULTS, plain=True, no_pager=True)
    opts.update(kw)
    with pytest.raises(solve_cmd.Exit) as done:
        solve_cmd.run_solve(args, **opts)
    out, err = capsys.readouterr()
    return int(done.value.exit_code), out, err


@pytest.fixture
def forked(monkeypatch):
    """The fork for any report of 10 equations or more; whether each run (serial ones
    apart) forked."""
    monkeypatch.setattr(solve_cmd, "FORK_MIN_EQUATIONS", 10)
    monkeypatch.delenv("MOMENTUM_SERIAL_REPORT", raising=False)
    real = forked_text.write
    runs = []

    def counted(*a, **k):
        got = real(*a, **k)
        if not os.environ.get("MOMENTUM_SERIAL_REPORT"):  # the runs to compare with
            runs.append(got)
        return got
    monkeypatch.setattr(forked_text, "write", counted)
    return runs


def _serial(args, capsys, monkeypatch, **kw):
    monkeypatch.setenv("MOMENTUM_SERIAL_REPORT", "1")
    try:
        return _run(args, capsys, **kw)
    finally:
        monkeypatch.delenv("MOMENTUM_SERIAL_REPORT")


def _no_children() -> bool:
    try:
        os.waitpid(-1, os.WNOHANG)
    except ChildProcessError:
        return not two_process.CHILDREN
    return False


@pytest.mark.parametrize("kind,n", [("chain", 5), ("chain", 300), ("cradle", 4),
                                    ("cradle", 300), ("simultaneous", 150)])
def test_forked_text_is_the_text(tmp_path, capsys, monkeypatch, forked, kind, n):
    """Two processes write the bytes one process writes, whatever the ranges' count."""
    path = _big(tmp_path, kind, n)
    want = _serial([str(path)], capsys, monkeypatch)
    assert want[0] == 0 and want[1] == _whole(path)
    for count in (2, 5, 32):
        monkeypatch.setattr(forked_text, "RANGES", count)
        assert _run([str(path)], capsys) == want, count
    assert forked and all(forked)
    assert _no_children()


def test_examples_through_the_fork(capsys, monkeypatch, forked):
    for path in EXAMPLES:
        want = _serial([str(path)], capsys, monkeypatch)
        assert _run([str(path)], capsys) == want, path.name
    assert any(forked)
    assert _no_children()


def test_serial_asked_never_forks(tmp_path, capsys, monkeypatch, forked):
    path = _big(tmp_path, "cradle", 50)

    def no_fork():
        raise AssertionError("forked")
    monkeypatch.setattr(os, "fork", no_fork)
    monkeypatch.setenv("MOMENTUM_SERIAL_REPORT", "1")
    assert _run([str(path)], capsys)[:2] == (0, _whole(path))
    monkeypatch.delenv("MOMENTUM_SERIAL_REPORT")
    monkeypatch.setattr(solve_cmd, "FORK_MIN_EQUATIONS", 10 ** 9)  # small: one process
    assert _run([str(path)], capsys)[:2] == (0, _whole(path))
    assert not forked


def _in_child(action, parent: int):
    """text.iter_parts that does `action` in the forked child only (after its first
    pieces), and is the real one in this process."""
    real = text.iter_parts

    def parts(rep, sig=6, steps=True, *cuts):
        for i, p in enumerate(real(rep, sig, steps, *cuts)):
            if i == 3 and os.getpid() != parent:
                action()
            yield p
    return parts


def _boom():
    raise RuntimeError("the child's bug")


@pytest.mark.parametrize("action", [_boom, lambda: os.kill(os.getpid(), signal.SIGKILL),
                                    lambda: os._exit(0)])
def test_a_child_that_fails_or_dies_leaves_the_text_whole(tmp_path, capsys, monkeypatch,
                                                          forked, action):
    """The ranges the child did not finish are made here: the whole text, no error."""
    path = _big(tmp_path, "cradle", 200)
    want = _serial([str(path)], capsys, monkeypatch)
    monkeypatch.setattr(text, "iter_parts", _in_child(action, os.getpid()))
    assert _run([str(path)], capsys) == want
    assert forked == [True] and _no_children()


def test_a_child_that_never_runs(tmp_path, capsys, monkeypatch, forked):
    path = _big(tmp_path, "chain", 200)
    want = _serial([str(path)], capsys, monkeypatch)
    monkeypatch.setattr(two_process, "_child", lambda *a: os._exit(1))
    assert _run([str(path)], capsys) == want
    assert forked == [True] and _no_children()


def _bug_at(row: int):
    """text._equation_texts that meets a bug at equation `row` (1-based), whichever
    process makes it."""
    real = text._equation_texts

    def texts(rows):
        for t in real(rows):
            if t.startswith(f"  ({row}) "):
                raise RuntimeError("boom")
            yield t
    return texts


@pytest.mark.parametrize("where", [0.02, 0.5, 0.98])
def test_a_bug_half_way_is_the_same_error(tmp_path, capsys, monkeypatch, forked, where):
    """A bug met at a row early (this process's part), in the middle, or late (the
    child's part): the same text before it, the same internal error and exit code 3."""
    path = _big(tmp_path, "cradle", 300)
    rows = solve_source(read_source(str(path)), lazy=True).report.counts["equations"]
    whole = _whole(path)
    monkeypatch.setattr(text, "_equation_texts", _bug_at(max(1, int(rows * where))))
    want = _serial([str(path)], capsys, monkeypatch)
    assert want[0] == 3 and "internal error: RuntimeError: boom" in want[2]
    assert whole.startswith(want[1]) and want[1]
    assert _run([str(path)], capsys) == want
    assert _no_children()


def _accented(real):
    """text._equation_texts with a non-ASCII mark on every row (in every range)."""
    def texts(rows):
        for t in real(rows):
            yield t + " \u2019"
    return texts


def test_non_ascii_rows_into_bytes_and_into_text(tmp_path, capsys, monkeypatch, forked):
    """The child's bytes are the stream's encoding of its text: copied as bytes after a
    UTF-8 stream's text, decoded into --output's capture (text only)."""
    path = _big(tmp_path, "cradle", 100)
    monkeypatch.setattr(text, "_equation_texts", _accented(text._equation_texts))
    want = _serial([str(path)], capsys, monkeypatch)
    assert want[0] == 0 and "\u2019" in want[1]
    assert _run([str(path)], capsys) == want
    out = tmp_path / "out.txt"
    assert _run([str(path)], capsys, output=str(out))[0] == 0
    assert out.read_text(encoding="utf-8") == want[1]
    assert forked == [True, True]


_MAIN = ("import sys\n"
         "sys.path.insert(0, 'tests')\n"
         "from momentum_cli.report import text\n"
         "from test_forked_text import _accented\n"
         "text._equation_texts = _accented(text._equation_texts)\n"
         "sys.argv = ['momentum'] + sys.argv[1:]\n"
         "from momentum_cli.__main__ import main\n"
         "main()\n")


def _process(args, **kw):
    return subprocess.run([sys.executable, "-c", _MAIN] + args, cwd=ROOT,
                          capture_output=True, timeout=300, **kw)


def test_one_shot_process_and_a_closed_pipe(tmp_path):
    """`momentum solve --plain` of a big file (over the threshold), its rows marked with
    a non-ASCII character: the bytes of one process, also under an ASCII encoding (an
    escape, as the stream writes it); a reader that leaves early (`| head`) ends it
    quietly (141), as before."""
    path = tmp_path / "big.mom"
    path.write_text(cradle_text(700, "sequence"))
    env = dict(os.environ)
    env.pop("MOMENTUM_SERIAL_REPORT", None)
    serial = dict(env, MOMENTUM_SERIAL_REPORT="1")
    for extra, mark in (({}, "\u2019".encode()), ({"PYTHONIOENCODING": "ascii"}, b"\\u2019")):
        want = _process(["solve", "--plain", str(path)], env=dict(serial, **extra))
        got = _process(["solve", "--plain", str(path)], env=dict(env, **extra))
        assert want.returncode == 0 and want.stdout.count(mark) > 2000
        assert (got.returncode, got.stdout, got.stderr) == (0, want.stdout, want.stderr)
    head = subprocess.run(f"{sys.executable} -m momentum_cli solve --plain {path} | head -c 300; "
                          "echo \"status ${PIPESTATUS[0]}\"", shell=True, cwd=ROOT, env=env,
                          capture_output=True, text=True, timeout=300, executable="/bin/bash")
    assert head.stdout.endswith("status 141\n") and head.stderr == ""


# ---- JSON: the report's fields made by two processes ------------------------------------
def test_json_fields_of_two_processes_are_the_fields(tmp_path, monkeypatch):
    """Each field's JSON text made by whichever process takes it: the same strings as
    one process makes, in the same key order, ASCII-only or not; the checks are this
    process's (read again by the caller)."""
    from momentum_cli.report import json_out

    monkeypatch.delenv("MOMENTUM_SERIAL_REPORT", raising=False)
    paths = [_big(tmp_path, kind, n) for kind, n in (("chain", 150), ("cradle", 150),
                                                     ("simultaneous", 60))]
    for path in paths + EXAMPLES[::7]:
        res = solve_source(read_source(str(path)), False, 6, "float", lazy=True)
        if res.report is None:
            continue
        for ascii_only in (False, True):
            want = json_out.encoded_fields(_lazy(path), ascii_only)
            rep = _lazy(path)
            got = forked_text.encoded_fields(rep, ascii_only, 0)
            assert list(got) == list(want) and got == want, path.name
            assert all(type(v) is json_out.Encoded for k, v in got.items() if k != "title")
            assert rep.checks._items is not None  # made here
    assert _no_children()


def test_json_fields_when_the_child_fails_or_a_field_has_a_bug(tmp_path, monkeypatch):
    from momentum_cli.report import json_out

    monkeypatch.delenv("MOMENTUM_SERIAL_REPORT", raising=False)
    path = _big(tmp_path, "cradle", 150)
    want = json_out.encoded_fields(_lazy(path))
    parent = os.getpid()
    real = json_out._diagrams

    def broken_in_child(rep):
        if os.getpid() != parent:
            os.kill(os.getpid(), signal.SIGKILL)
        return real(rep)
    monkeypatch.setattr(json_out, "_diagrams", broken_in_child)
    assert forked_text.encoded_fields(_lazy(path), False, 0) == want

    def bug(rep):
        raise RuntimeError("boom")
    monkeypatch.setattr(json_out, "_diagrams", bug)
    with pytest.raises(RuntimeError, match="boom"):
        forked_text.encoded_fields(_lazy(path), False, 0)
    assert _no_children()


def test_json_of_one_big_file_through_the_fork(tmp_path, capsys, monkeypatch, forked):
    """`solve --json` of one file: the same document as one process (the fork is for a
    single file: a batch's workers use both cores already)."""
    calls = []
    real = forked_text.encoded_fields

    def counted(*a, **k):
        if not os.environ.get("MOMENTUM_SERIAL_REPORT"):
            calls.append(1)
        return real(*a, **k)
    monkeypatch.setattr(forked_text, "encoded_fields", counted)
    for path in (_big(tmp_path, "cradle", 120), _big(tmp_path, "chain", 120)):
        want = _serial([str(path)], capsys, monkeypatch, json_flag=True, plain=False)
        assert want[0] == 0 and want[1].startswith("{")
        assert _run([str(path)], capsys, json_flag=True, plain=False) == want
    assert len(calls) == 2
    both = [str(p) for p in tmp_path.glob("*.mom")]
    _run(both, capsys, json_flag=True, plain=False)
    assert len(calls) == 2
    assert _no_children()


def test_deferred_checks_are_the_checks_of_a_whole_report():
    """A lazy report's checks, made when first read (model.Deferred), with `expect`
    lines appended before: the checks of the report built whole, in the same order;
    dropped trees (`release`) are made again the same."""
    import pickle

    from momentum_cli.report.model import Deferred

    for path in EXAMPLES:
        whole = solve_source(read_source(str(path)), False, 6, "float")
        if whole.report is None:
            continue
        lazy = solve_source(read_source(str(path)), False, 6, "float", lazy=True).report
        assert type(lazy.checks) is Deferred
        lazy.checks.release()
        want = [(c.name, c.status, c.detail, c.value) for c in whole.report.checks]
        assert [(c.name, c.status, c.detail, c.value) for c in lazy.checks] == want, path.name
        assert len(pickle.loads(pickle.dumps(lazy.checks))) == len(want)
    late = Deferred(lambda: [1, 2])
    late.append(3)
    assert list(late) == [1, 2, 3] and late == [1, 2, 3] and len(late) == 3 and late[-1] == 3
