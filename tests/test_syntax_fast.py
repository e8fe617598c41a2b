"""The fast parse of big files (`syntax_fast`) gives the whole-file lark parse's tree,
token positions and node positions included, and the same diagnostics for bad files."""
from pathlib import Path

import pytest

from momentum_cli import syntax, syntax_fast
from momentum_cli.bench import chain_text
from momentum_cli.diagnostics import ProblemError
from momentum_cli.source import Source

ROOT = Path(__file__).resolve().parent.parent / "examples"
FILES = sorted(ROOT.rglob("*.mom"))


def _text(text: str) -> str:
    return text if text.endswith("\n") else text + "\n"


@pytest.fixture
def small(monkeypatch):
    """Split every block of 3 lines and every line of 2 commas (the examples are small)."""
    monkeypatch.setattr(syntax_fast, "MIN_ITEMS", 2)
    monkeypatch.setattr(syntax_fast, "LONG_LINE", 0)


def _check(text: str) -> bool:
    """True when the fast path took the text; its tree equals lark's in every position."""
    p = syntax.parser()
    text = _text(text)
    try:
        full = p.parse(text)
    except Exception:
        full = None
    try:
        fast = syntax_fast.fast_tree(text, p.parse)
    except Exception:
        fast = None
    if fast is None:
        return False
    assert full is not None, "the fast path accepted a text lark refuses"
    assert syntax_fast.same_tree(fast, full)
    return True


def test_every_example_same_tree(small):
    taken = sum(_check(f.read_text(encoding="utf-8")) for f in FILES)
    assert taken >= len(FILES) // 2  # most files take the fast path (the rest: whole parse)


def test_chain_same_tree():
    assert _check(chain_text(300))


@pytest.mark.parametrize("how", ["built", "loaded from the cache"])
def test_same_tree_whether_the_parser_is_built_or_loaded(how, tmp_path, monkeypatch):
    """A freshly built lark parser names rules by Token('RULE', ...), one loaded from the
    cache by str: the copies of a repeated shape must be right with both (a clean machine
    builds; CI once failed there while every warm machine passed)."""
    monkeypatch.setenv("MOMENTUM_CACHE_DIR", str(tmp_path))
    syntax.parser.cache_clear()
    try:
        if how != "built":
            syntax.parser()  # writes the cache
            syntax.parser.cache_clear()
        assert _check(chain_text(300))
    finally:
        syntax.parser.cache_clear()


def test_blocks_comments_and_long_lists_same_tree(small):
    text = ("# a leading comment\n\nproblem \"p\"\n" +
            "".join(f"body b{k}: particle(mass = {k}.5 kg)  # ball {k}\n" for k in range(1, 12)) +
            "state 1: " + ", ".join(f"b{k}.v = ({k} m/s, -{k}.25 m/s)" for k in range(1, 12)) +
            "\n\nstate 2\nimpact 1 -> 2:\n" +
            "".join(f"    contact b{k + 1} with b{k} normal (1, 0): restitution 0.{k}\n"
                    f"\n    # between\n" for k in range(1, 11)) +
            "\n# trailing\nfind b1.vx@2, " + ", ".join(f"b{k}.vy@2" for k in range(2, 12)) +
            "\n")
    assert _check(text)


def _outcome(text: str, fast: bool, monkeypatch):
    """The lark path (syntax_run off: test_syntax_run compares it with lark's) with or
    without syntax_fast."""
    monkeypatch.setattr(syntax, "_fast_parser", lambda: None)
    monkeypatch.setattr(syntax, "FAST_BYTES", 0 if fast else 10 ** 12)
    try:
        return ("ok", syntax.parse(Source("f.mom", text)))
    except ProblemError as exc:
        return ("error", [(d.code, d.message, d.span) for d in exc.diagnostics])


def test_bad_files_same_diagnostics(monkeypatch, small):
    from fuzz_corpus import corpus

    for name, data in corpus(120, seed=3):
        try:
            text = data.decode("utf-8")
        except UnicodeDecodeError:
            continue
        assert _outcome(text, True, monkeypatch) == _outcome(text, False, monkeypatch), name


def test_error_in_a_big_file_located_as_before(monkeypatch):
    lines = chain_text(200).split("\n")
    for k, bad in ((50, "body b50: particle(mass = 2 kg"),
                   (205, "    contact b3 with b2 normal (1, 0): restitution"),
                   (201, "state 1: b1.v = (1 m/s, 0), b2 at rest, b3 at"),
                   (150, "body b150 particle(mass = 1 kg)")):
        broken = "\n".join(lines[:k] + [bad] + lines[k + 1:])
        fast = _outcome(broken, True, monkeypatch)
        assert fast[0] == "error" and fast == _outcome(broken, False, monkeypatch)
