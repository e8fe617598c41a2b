"""The parser cache is a pickle, so it runs code when loaded: it is loaded only from a
private regular file of this user; anything else is rebuilt in memory with a note. The
same holds for the tables syntax_run parses with (a marshal file, read by the same
checks). A run whose tables are cached never opens lark's pickle, so the pickle's tests
run with MOMENTUM_LARK_ONLY=1 (lark parses, as it does to report a syntax error)."""
from __future__ import annotations

import os
import pickle
import stat
import subprocess
import sys
from pathlib import Path

import pytest

from conftest import EXAMPLES

PROBLEM = str(EXAMPLES / "ball_bounce_rebound.mom")


class _Marker:
    """Unpickling this creates the marker file (what an attacker's cache would do)."""

    def __init__(self, path: str):
        self.path = path

    def __reduce__(self):
        return (open, (self.path, "w"))


def _run(cache: Path, env_extra=None, lark_only=True) -> subprocess.CompletedProcess:
    env = dict(os.environ, MOMENTUM_CACHE_DIR=str(cache), **(env_extra or {}))
    env.pop("MOMENTUM_LARK_ONLY", None)
    if lark_only:
        env["MOMENTUM_LARK_ONLY"] = "1"
    return subprocess.run([sys.executable, "-m", "momentum_cli", "solve", "-q", PROBLEM],
                          capture_output=True, text=True, env=env, timeout=60)


def _cache_file(cache: Path) -> Path:
    """The cache file's name, made by a first (clean) run."""
    res = _run(cache)
    assert res.returncode == 0, res.stderr
    files = list(cache.glob("grammar-*.lark-cache"))
    assert len(files) == 1
    return files[0]


def test_cache_folder_is_private_and_file_is_reused(tmp_path):
    cache = tmp_path / "c"
    path = _cache_file(cache)
    assert stat.S_IMODE(cache.stat().st_mode) == 0o700
    assert not stat.S_IMODE(path.stat().st_mode) & 0o077
    res = _run(cache)
    assert res.returncode == 0 and res.stderr == ""
    assert "rebound = 1.28 m" in res.stdout  # h' = e^2 h = 0.64 * 2 m


@pytest.mark.parametrize("mode", [0o666, 0o620, 0o602])
def test_crafted_pickle_with_loose_permissions_is_not_loaded(tmp_path, mode):
    cache = tmp_path / "c"
    path = _cache_file(cache)
    marker = tmp_path / "pwned"
    path.write_bytes(pickle.dumps(_Marker(str(marker))))
    os.chmod(path, mode)
    res = _run(cache)
    assert res.returncode == 0, res.stderr
    assert not marker.exists()
    assert "not loaded" in res.stderr and len(res.stderr.splitlines()) == 1
    assert "rebound = 1.28 m" in res.stdout


@pytest.mark.skipif(not hasattr(os, "geteuid") or os.geteuid() != 0,
                    reason="giving a file to another user needs root")
def test_crafted_pickle_of_another_user_is_not_loaded(tmp_path):
    cache = tmp_path / "c"
    path = _cache_file(cache)
    marker = tmp_path / "pwned"
    path.write_bytes(pickle.dumps(_Marker(str(marker))))
    os.chmod(path, 0o600)
    os.chown(path, 12345, 12345)
    res = _run(cache)
    assert res.returncode == 0, res.stderr
    assert not marker.exists()
    assert "not loaded" in res.stderr


def test_crafted_pickle_of_this_user_is_what_the_checks_allow(tmp_path):
    """The control: the same file, private and ours, is loaded (so the tests above
    prove that the checks, not chance, kept it out). Loading fails (it is no parser),
    so the parser is rebuilt and the answer is still right."""
    cache = tmp_path / "c"
    path = _cache_file(cache)
    marker = tmp_path / "pwned"
    path.write_bytes(pickle.dumps(_Marker(str(marker))))
    os.chmod(path, 0o600)
    res = _run(cache)
    assert res.returncode == 0
    assert marker.exists()
    assert "rebound = 1.28 m" in res.stdout


def test_fifo_and_symlink_are_never_opened(tmp_path):
    cache = tmp_path / "c"
    path = _cache_file(cache)
    path.unlink()
    os.mkfifo(path)  # opening it for reading without O_NONBLOCK would hang
    res = _run(cache)
    assert res.returncode == 0 and "rebound = 1.28 m" in res.stdout
    path.unlink(missing_ok=True)
    path.symlink_to("/dev/zero")
    res = _run(cache)
    assert res.returncode == 0 and "rebound = 1.28 m" in res.stdout
    assert "not a plain file" in res.stderr


def _tables_file(cache: Path) -> Path:
    res = _run(cache, lark_only=False)
    assert res.returncode == 0, res.stderr
    files = list(cache.glob("tables-*.marshal"))
    assert len(files) == 1
    return files[0]


def test_tables_are_reused_and_private(tmp_path):
    cache = tmp_path / "c"
    path = _tables_file(cache)
    assert not stat.S_IMODE(path.stat().st_mode) & 0o077
    before = path.stat().st_mtime_ns
    res = _run(cache, lark_only=False)
    assert res.returncode == 0 and res.stderr == ""
    assert "rebound = 1.28 m" in res.stdout
    assert path.stat().st_mtime_ns == before  # read, not written again


@pytest.mark.parametrize("mode", [0o666, 0o620])
def test_tables_with_loose_permissions_are_not_loaded(tmp_path, mode):
    cache = tmp_path / "c"
    path = _tables_file(cache)
    os.chmod(path, mode)
    res = _run(cache, lark_only=False)
    assert res.returncode == 0, res.stderr
    assert "not loaded" in res.stderr and len(res.stderr.splitlines()) == 1
    assert "rebound = 1.28 m" in res.stdout


@pytest.mark.parametrize("content", [b"", b"not marshal data", None])
def test_damaged_or_foreign_tables_are_rebuilt(tmp_path, content):
    """Tables that are damaged, or were built from another grammar (`None`: the same
    file with another grammar text in its identity), are not used: rebuilt, same answer."""
    import marshal

    cache = tmp_path / "c"
    path = _tables_file(cache)
    if content is None:
        stored = marshal.loads(path.read_bytes())
        stored["identity"]["grammar"] += "\n// another grammar\n"
        content = marshal.dumps(stored)
    path.write_bytes(content)
    res = _run(cache, lark_only=False)
    assert res.returncode == 0 and res.stderr == "", res.stderr
    assert "rebound = 1.28 m" in res.stdout
    assert path.read_bytes() != content  # written again


def test_tables_fifo_and_symlink_are_never_opened(tmp_path):
    cache = tmp_path / "c"
    path = _tables_file(cache)
    path.unlink()
    os.mkfifo(path)
    res = _run(cache, lark_only=False)
    assert res.returncode == 0 and "rebound = 1.28 m" in res.stdout
    path.unlink(missing_ok=True)
    path.symlink_to("/dev/zero")
    res = _run(cache, lark_only=False)
    assert res.returncode == 0 and "rebound = 1.28 m" in res.stdout
    assert "not a plain file" in res.stderr


def test_relative_xdg_cache_home_is_ignored(tmp_path):
    env = {k: v for k, v in os.environ.items() if k != "MOMENTUM_CACHE_DIR"}
    env.update(XDG_CACHE_HOME="relative-cache", HOME=str(tmp_path / "home"))
    work = tmp_path / "work"
    work.mkdir()
    res = subprocess.run([sys.executable, "-m", "momentum_cli", "solve", "-q", PROBLEM],
                         capture_output=True, text=True, env=env, cwd=work, timeout=60)
    assert res.returncode == 0, res.stderr
    assert not (work / "relative-cache").exists()
    assert list((tmp_path / "home" / ".cache" / "momentum").glob("grammar-*"))
