"""syntax_lines' regular expressions come from code kept in the cache folder
(regex_store): they must be the patterns `re.compile` makes, match alike, and any file
that does not belong to these patterns and this Python must be ignored."""
from __future__ import annotations

import os
import re

import pytest

from momentum_cli import regex_store, syntax_lines

PATTERNS = {
    "WORD": r"(?>[A-Za-z_][A-Za-z_0-9]*(?:\[[0-9]+\])*)",
    "STATE": r'state *(?P<id>(?>[0-9]+)) *(?P<s>"[^"\n]*")? *(?P<c>:)? *',
    "NUM": r"(?>(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)",
}
TEXTS = ["state 12 \"b1 meets b2\": b1 at rest", "b17[3].vx", "1.5e-3 m/s", "", "state x",
         "contact c9: b10 with b9 normal (1, 0): restitution 1, smooth"]


def _same(made: dict, patterns: dict) -> None:
    assert made.keys() == patterns.keys()
    for k, p in patterns.items():
        ref = re.compile(p)
        got = made[k]
        assert type(got) is type(ref)
        assert (got.pattern, got.flags, got.groups, dict(got.groupindex)) == \
            (ref.pattern, ref.flags, ref.groups, dict(ref.groupindex))
        for t in TEXTS:
            for at in range(len(t) + 1):
                a, b = got.match(t, at), ref.match(t, at)
                assert (a and (a.regs, a.groups())) == (b and (b.regs, b.groups()))
            assert got.findall(t) == ref.findall(t)


def _file(folder, patterns=PATTERNS) -> str:
    return os.path.join(folder, regex_store.cache_name("test", patterns))


def test_first_run_compiles_and_writes_the_code_the_next_run_loads(tmp_path, monkeypatch):
    monkeypatch.setenv("MOMENTUM_CACHE_DIR", str(tmp_path))
    first = regex_store.compiled("test", PATTERNS)
    _same(first, PATTERNS)
    assert os.path.isfile(_file(tmp_path))
    with open(_file(tmp_path), "rb") as fh:
        loaded = regex_store._load(fh.read(), PATTERNS)
    assert loaded is not None  # the next process uses the stored code
    _same(loaded, PATTERNS)
    _same(regex_store.compiled("test", PATTERNS), PATTERNS)


def test_syntax_lines_patterns_equal_what_re_compile_makes():
    names = {k: v for k, v in vars(syntax_lines).items() if isinstance(v, re.Pattern)}
    assert len(names) >= 20
    for k, v in names.items():
        ref = re.compile(v.pattern)
        assert (v.flags, v.groups, dict(v.groupindex)) == \
            (ref.flags, ref.groups, dict(ref.groupindex)), k


def test_stored_code_of_other_patterns_is_not_used(tmp_path, monkeypatch):
    monkeypatch.setenv("MOMENTUM_CACHE_DIR", str(tmp_path))
    regex_store.compiled("test", PATTERNS)
    with open(_file(tmp_path), "rb") as fh:
        data = fh.read()
    changed = dict(PATTERNS, NUM=r"\d+")
    assert regex_store._load(data, changed) is None
    assert regex_store._load(data, {k: PATTERNS[k] for k in ("WORD", "NUM")}) is None
    # the same file under the other patterns' name: compiled afresh, right
    os.replace(_file(tmp_path), _file(tmp_path, changed))
    _same(regex_store.compiled("test", changed), changed)


@pytest.mark.parametrize("damage", [b"", b"\x00garbage", None])
def test_a_damaged_or_foreign_file_is_ignored(tmp_path, monkeypatch, damage):
    import marshal
    import sys

    monkeypatch.setenv("MOMENTUM_CACHE_DIR", str(tmp_path))
    if damage is None:  # well formed, but code for another Python
        ident = dict(regex_store._identity(PATTERNS), python=sys.version + " other")
        damage = marshal.dumps({"identity": ident, "codes": {}})
    path = _file(tmp_path)
    fd = os.open(path, os.O_WRONLY | os.O_CREAT, 0o600)
    os.write(fd, damage)
    os.close(fd)
    _same(regex_store.compiled("test", PATTERNS), PATTERNS)


def test_code_that_sre_refuses_falls_back_to_the_compiler(tmp_path, monkeypatch):
    import marshal

    monkeypatch.setenv("MOMENTUM_CACHE_DIR", str(tmp_path))
    regex_store.compiled("test", PATTERNS)
    with open(_file(tmp_path), "rb") as fh:
        stored = marshal.loads(fh.read())
    args = list(stored["codes"]["NUM"])
    args[2] = [99999] * 5  # not regex code
    stored["codes"]["NUM"] = tuple(args)
    os.replace(_file(tmp_path), _file(tmp_path) + ".old")
    fd = os.open(_file(tmp_path), os.O_WRONLY | os.O_CREAT, 0o600)
    os.write(fd, marshal.dumps(stored))
    os.close(fd)
    _same(regex_store.compiled("test", PATTERNS), PATTERNS)


def test_without_a_cache_folder_the_patterns_are_compiled(monkeypatch):
    from momentum_cli import cache_files

    monkeypatch.setattr(cache_files, "cache_dir", lambda: None)
    _same(regex_store.compiled("test", PATTERNS), PATTERNS)
