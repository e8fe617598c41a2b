"""syntax_lines' builders (one function per shape of line) are kept in the cache folder
(builder_store): a later run reads every line of a stored shape with the stored builder,
makes none itself, and gets syntax_run's nodes, every span included; a file written from
other modules or another grammar, or a damaged one, is ignored."""
from __future__ import annotations

import os

import pytest

from momentum_cli import builder_store, syntax, syntax_lines
from momentum_cli.bench import chain_text
from test_hard import cradle_text
from test_syntax_lines import _by_run, _whole

TEXTS = [chain_text(300), cradle_text(200, "sequence"), cradle_text(60, "simultaneous")]


@pytest.fixture
def store(tmp_path, monkeypatch):
    """A fresh cache folder and a run that has met no shape yet; texts of every size
    keep their builders."""
    monkeypatch.setenv("MOMENTUM_CACHE_DIR", str(tmp_path))
    monkeypatch.setattr(syntax_lines, "STORE_BYTES", 0)
    builder_store.forget()
    syntax_lines._SETUP[0] = None  # setup() again: configures the store
    syntax_lines._SHAPES.clear()
    yield tmp_path
    builder_store.forget()
    syntax_lines._SETUP[0] = None
    syntax_lines._SHAPES.clear()


def _new_run() -> None:
    """What a new process starts from: no builder in memory, the file not loaded."""
    builder_store.forget()
    syntax_lines._SETUP[0] = None
    syntax_lines._SHAPES.clear()


def _parse(text: str, made: list):
    fast = syntax._fast_parser()
    real = syntax_lines._builder

    def counted(*a):
        fn = real(*a)
        made.append(fn)
        return fn

    syntax_lines._builder = counted
    try:
        return syntax_lines.parse(_whole(text), lambda c, line: fast.parse(c, line), syntax)
    finally:
        syntax_lines._builder = real


def _files(folder) -> list[str]:
    return sorted(f for f in os.listdir(folder) if f.startswith("builders-"))


@pytest.mark.parametrize("text", TEXTS, ids=["chain", "cradle-seq", "cradle-sim"])
def test_a_later_run_reads_with_the_stored_builders(store, text):
    made: list = []
    first = _parse(text, made)
    assert made and any(made) and len(_files(store)) == 1
    _new_run()
    made2: list = []
    again = _parse(text, made2)
    assert made2 == []  # every shape's builder came from the file
    assert again == first == _by_run(text)


def test_stored_builders_read_other_numbers_of_the_same_shapes(store):
    _parse(chain_text(300), [])
    _new_run()
    other = chain_text(300).replace("restitution 0.5", "restitution 0.7")
    assert other != chain_text(300)
    assert _parse(other, []) == _by_run(other)


def test_a_file_from_another_grammar_is_not_used(store, monkeypatch):
    _parse(TEXTS[1], [])
    (name,) = _files(store)
    _new_run()
    real = syntax.grammar_text
    monkeypatch.setattr(syntax, "grammar_text", lambda: real() + "\n// changed\n")
    made: list = []
    assert _parse(TEXTS[1], made) == _by_run(TEXTS[1])
    assert made  # made afresh
    assert name in _files(store) and len(_files(store)) == 2


@pytest.mark.parametrize("damage", [b"", b"\x00not marshal", None])
def test_a_damaged_or_foreign_file_is_ignored(store, damage):
    import marshal

    _parse(TEXTS[1], [])
    (name,) = _files(store)
    path = os.path.join(store, name)
    if damage is None:  # well formed, its code not a builder's
        ident = marshal.loads(open(path, "rb").read())["identity"]
        damage = marshal.dumps({"identity": ident,
                                "codes": {k: compile("x = 1", "<x>", "exec") for k in
                                          marshal.loads(open(path, "rb").read())["codes"]}})
    os.unlink(path)
    fd = os.open(path, os.O_WRONLY | os.O_CREAT, 0o600)
    os.write(fd, damage)
    os.close(fd)
    _new_run()
    assert _parse(TEXTS[1], []) == _by_run(TEXTS[1])


def test_switched_off_nothing_is_stored(store, monkeypatch):
    monkeypatch.setattr(syntax_lines, "STORE", False)
    assert _parse(TEXTS[0], []) == _by_run(TEXTS[0])
    assert _files(store) == []


def test_a_small_text_neither_reads_nor_writes_the_file(store, monkeypatch):
    """A batch's files are small: they make their few builders (no file to load, none
    written after each file)."""
    _parse(TEXTS[1], [])
    (name,) = _files(store)
    before = os.path.getmtime(os.path.join(store, name))
    _new_run()
    monkeypatch.setattr(syntax_lines, "STORE_BYTES", len(TEXTS[0]) + 1)
    made: list = []
    assert _parse(TEXTS[1], made) == _by_run(TEXTS[1]) and made  # not read from the file
    assert _parse(TEXTS[0], []) == _by_run(TEXTS[0])
    assert _files(store) == [name] and os.path.getmtime(os.path.join(store, name)) == before
    assert not builder_store._STORED  # never loaded
