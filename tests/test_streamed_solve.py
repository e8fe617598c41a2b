"""One file's plain report written as it is made (text.iter_parts through
solve_cmd._write_text), and a one-shot process that keeps a big result to its end
(guard.keep_until_exit, left by os._exit): the same bytes and exit codes as the text
joined whole and a normal exit; a bug met half-way through the text is the same internal
error as anywhere else, after the text made before it."""
from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from momentum_cli import solve_cmd
from momentum_cli.bench import chain_text
from momentum_cli.report import text
from momentum_cli.run import read_source, solve_source

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tests"))
from test_hard import cradle_text  # noqa: E402

EXAMPLES = sorted((ROOT / "examples").glob("*.mom"))
BIG = 700  # balls: 2099 equations, over solve_cmd.KEEP_MIN_EQUATIONS


def _whole(path) -> str:
    """The general path: the report built whole (not lazy), its text joined."""
    res = solve_source(read_source(str(path)), False, 6, "float")
    return None if res.report is None else text.render(res.report, 6)


def _files(tmp_path) -> list:
    out = []
    for name, body in (("chain.mom", chain_text(60)), ("cradle.mom", cradle_text(40, "sequence"))):
        p = tmp_path / name
        p.write_text(body)
        out.append(p)
    return out


def test_pieces_in_short_runs_join_to_the_text(tmp_path, monkeypatch):
    """Long sections cut into runs of a few lines: the same text, and every piece is
    text (the writer joins them with newlines, nothing nested)."""
    monkeypatch.setattr(text, "RUN_LINES", 3)
    for path in EXAMPLES + _files(tmp_path):
        res = solve_source(read_source(str(path)), False, 6, "float", lazy=True)
        if res.report is None:
            continue
        parts = list(text.iter_parts(res.report, 6))
        assert all(type(p) is str for p in parts)
        monkeypatch.setattr(text, "RUN_LINES", 4096)
        assert "\n".join(parts) == _whole(path), path.name
        monkeypatch.setattr(text, "RUN_LINES", 3)


def _run(args, capsys, **kw):
    """run_solve in this process: (exit code, stdout, stderr)."""
    opts = dict(solve_cmd.SOLVE_DEFAULTS, plain=True, no_pager=True)
    opts.update(kw)
    with pytest.raises(solve_cmd.Exit) as done:  # typer's, once cli.py is loaded
        solve_cmd.run_solve(args, **opts)
    out, err = capsys.readouterr()
    return int(done.value.exit_code), out, err


@pytest.mark.parametrize("chunk", [64, 1 << 20])
def test_one_file_is_written_as_made(tmp_path, capsys, monkeypatch, chunk):
    """A single file's text comes from the lazy report piece by piece (render_parts,
    the batch's whole list, is never called), in writes of any size: the text of the
    report built whole."""
    monkeypatch.setattr(solve_cmd, "WRITE_CHUNK", chunk)

    def no_list(*_a, **_k):
        raise AssertionError("one file's text made as a list")

    monkeypatch.setattr(text, "render_parts", no_list)
    for path in EXAMPLES[:6] + _files(tmp_path):
        want = _whole(path)
        code, out, _err = _run([str(path)], capsys)
        if want is not None:
            assert (code, out) == (0, want), path.name
        else:
            assert code == 1 and out == ""


def _failing_after(n: int):
    """iter_parts that makes its first `n` pieces of a chain's text, then meets a bug."""
    real = text.iter_parts

    def parts(rep, sig=6, steps=True):
        for i, p in enumerate(real(rep, sig, steps)):
            if i == n and "chain" in rep.file:
                raise RuntimeError("boom")
            yield p
    return parts, real


def _internal_line(name: str) -> str:
    return (f"{name}: error: internal error: RuntimeError: boom (this is a bug in "
            "momentum; rerun with --traceback and report it)\n")


def test_a_bug_mid_text_is_the_internal_error(tmp_path, capsys, monkeypatch):
    """The pieces made before the bug are written, then the internal error a worker
    gives for the same bug (exit 3); the next file of a batch goes on."""
    (chain, _cradle) = _files(tmp_path)
    failing, real = _failing_after(5)
    first = list(real(solve_source(read_source(str(chain)), lazy=True).report, 6))[:5]
    monkeypatch.setattr(text, "iter_parts", failing)
    code, out, err = _run([str(chain)], capsys)
    assert code == 3
    assert out == "\n".join(first)
    assert err.endswith(_internal_line(str(chain)))
    # a batch: the worker's render fails the same way (the file's text is not shown)
    code, out, err = _run([str(chain), str(EXAMPLES[0])], capsys)
    assert code == 3 and _internal_line(str(chain)) in err
    assert out.lstrip("\n") == _whole(EXAMPLES[0])


def test_a_bug_mid_text_with_traceback_is_raised(tmp_path, capsys, monkeypatch):
    (chain, _cradle) = _files(tmp_path)
    monkeypatch.setattr(text, "iter_parts", _failing_after(3)[0])
    with pytest.raises(RuntimeError, match="boom"):
        solve_cmd.run_solve([str(chain)], **dict(solve_cmd.SOLVE_DEFAULTS, plain=True,
                                                 no_pager=True, traceback_flag=True))


def test_in_process_keeps_nothing(tmp_path, capsys):
    """A caller of the package (no one-shot process) gets its memory back."""
    from momentum_cli import guard

    path = tmp_path / "big.mom"
    path.write_text(chain_text(BIG))
    assert _run([str(path)], capsys)[0] == 0
    assert guard._KEPT is None


# the one-shot process, as `momentum` runs it: an atexit line shows whether the
# interpreter was torn down (it is not after a big result was kept)
_MAIN = ("import atexit, sys\n"
         "atexit.register(lambda: sys.stderr.write('TEARDOWN\\n'))\n"
         "{patch}"
         "sys.argv = ['momentum'] + sys.argv[1:]\n"
         "from momentum_cli.__main__ import main\n"
         "main()\n")
_BUG = ("from momentum_cli.report import text\n"
        "real = text.iter_parts\n"
        "def parts(rep, sig=6, steps=True, *cuts):\n"  # a range of it: forked_text
        "    for i, p in enumerate(real(rep, sig, steps, *cuts)):\n"
        "        if i == 5:\n"
        "            raise RuntimeError('boom')\n"
        "        yield p\n"
        "text.iter_parts = parts\n")


def _process(args, patch: str = "", **kw):
    return subprocess.run([sys.executable, "-c", _MAIN.format(patch=patch)] + args, cwd=ROOT,
                          capture_output=True, text=True, timeout=300, **kw)


def test_one_shot_leaves_a_big_result_unfreed(tmp_path):
    """Exit codes and output of the one-shot process: a big file solved (0, no teardown),
    a small one (0, the usual exit), a bug half-way through a big text (3), a problem
    file with an error (1), a missing file (2), standard input."""
    big = tmp_path / "big.mom"
    big.write_text(chain_text(BIG))
    want = _whole(big)
    got = _process(["solve", "--plain", str(big)])
    assert (got.returncode, got.stdout, got.stderr) == (0, want, "")
    got = _process(["solve", "--plain", "-"], input=big.read_text())
    assert (got.returncode, got.stdout) == (0, want.replace(str(big), "<stdin>", 1))
    assert "TEARDOWN" not in got.stderr
    typer = _process(["solve", "--plain", str(big)], env=dict(__import__("os").environ,
                                                                MOMENTUM_NO_FASTPATH="1"))
    assert (typer.returncode, typer.stdout, typer.stderr) == (0, want, "")
    small = EXAMPLES[0]
    got = _process(["solve", "--plain", str(small)])
    assert (got.returncode, got.stdout) == (0, _whole(small))
    assert got.stderr == "TEARDOWN\n"
    got = _process(["solve", "--plain", str(big)], patch=_BUG)
    assert got.returncode == 3 and got.stderr.startswith(_internal_line(str(big)))
    assert want.startswith(got.stdout) and got.stdout.count("\n") >= 4
    bad = tmp_path / "bad.mom"
    bad.write_text(chain_text(BIG) + "\nfind nothing_here\n")
    got = _process(["solve", "--plain", str(bad)])
    assert got.returncode == 1 and "bad.mom:" in got.stderr and got.stdout == ""
    got = _process(["solve", "--plain", str(tmp_path / "missing.mom")])
    assert got.returncode == 2 and "no such file" in got.stderr
