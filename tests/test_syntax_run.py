"""syntax_run (the parse without lark, from syntax_tables' tables) gives the nodes that
lark's parse and the transformer give, every span included; it takes every example lark
takes; it leaves every bad file to lark (the same diagnostics); its tables work built
fresh and loaded from the cache; and a one-shot solve never imports lark."""
import os
import subprocess
import sys
from pathlib import Path

import pytest

from momentum_cli import syntax
from momentum_cli.diagnostics import ProblemError
from momentum_cli.source import Source
from momentum_cli.syntax_run import Fallback

ROOT = Path(__file__).resolve().parent.parent
FILES = sorted(f for f in (ROOT / "examples").rglob("*.mom") if f.stat().st_size < 50_000)


def _text(text: str) -> str:
    return text if text.endswith("\n") else text + "\n"


def _outcome(text: str, fast: bool, monkeypatch):
    """syntax.parse's result (the statements) or its diagnostics, by syntax_run (fast)
    or by lark alone."""
    with monkeypatch.context() as m:
        if not fast:
            m.setattr(syntax, "_fast_parser", lambda: None)
        try:
            return ("ok", syntax.parse(Source("f.mom", text)).statements)
        except ProblemError as exc:
            return ("error", [(d.code, d.message, d.span, d.notes) for d in exc.diagnostics])


def _run_direct(text: str):
    """syntax_run's own answer: the statements, or None when it leaves the text to lark."""
    try:
        nodes = syntax._fast_parser().parse(_text(text))
    except Fallback:
        return None
    return tuple(syntax._plus_minus(s, text) for s in nodes)


def test_the_grammar_is_run_without_lark():
    """Else every parse would silently go back to lark (slow, but right)."""
    assert syntax._fast_parser() is not None


def test_every_example_same_nodes(monkeypatch):
    taken = 0
    for f in FILES:
        text = f.read_text(encoding="utf-8")
        lark = _outcome(text, False, monkeypatch)
        direct = _run_direct(text)
        if direct is not None:
            taken += 1
            assert lark[0] == "ok", f"{f.name}: syntax_run took a text lark refuses"
            assert direct == lark[1], f.name
        assert _outcome(text, True, monkeypatch) == lark, f.name
    assert taken >= len(FILES) * 3 // 4  # the rest: `for` loops (written out first)


def test_lark_only_for_errors(monkeypatch):
    """Every example that parses (loops written out included) is parsed without lark."""
    assert syntax._fast_parser() is not None  # its tables built or loaded first

    def no_lark():
        raise AssertionError("lark's parser was used")

    monkeypatch.setattr(syntax, "parser", no_lark)
    for f in FILES:
        if f.name.startswith("bad_"):
            continue
        try:
            syntax.parse(Source(f.name, f.read_text(encoding="utf-8")))
        except ProblemError:
            pass  # a bad value, found while building nodes: lark is not needed for it


def test_big_file_same_nodes(monkeypatch):
    from momentum_cli.bench import chain_text

    text = chain_text(400)
    direct = _run_direct(text)
    assert direct is not None and direct == _outcome(text, False, monkeypatch)[1]


def test_bad_files_same_diagnostics(monkeypatch):
    from fuzz_corpus import corpus

    taken = 0
    for name, data in corpus(200, seed=11):
        try:
            text = data.decode("utf-8")
        except UnicodeDecodeError:
            continue
        lark = _outcome(text, False, monkeypatch)
        assert _outcome(text, True, monkeypatch) == lark, name
        direct = _run_direct(text)
        if direct is not None:
            taken += 1
            assert lark[0] == "ok" and direct == lark[1], name
    assert taken > 30


@pytest.mark.parametrize("text", [
    "let a = 1 m\nlet b = ((a))\n",
    "let a = (1 m, 2 m)\n",
    "let a = (1 m,\n   2 m)\n",  # a line break inside brackets
    "let x = -(1 + 2) * 3 ^ 2 / +4 in mm\n",
    "body b: composite\n    rod(mass = 1 kg, length = 1 m) at (0, 0) rotated 90 deg\n"
    "    disk(mass = 1 kg, radius = 1 m)\n\nfind b.vx@1\n",
    "state 1 \"a\": b.v = (1 m/s, 0) # c\n    b.omega = 0  # d\n\n# e\n",
    "impact 1 -> 2:\n    contact b.end(+) with ground: restitution 0.6 poisson, friction 0.3 "
    "static 0.4\n    b stops\n",
    "expect b.vx@2 = 1 m/s +- 0.1 m/s\nexpect error inconsistent\n",
    "problem \"p\"\\\n\n",  # a continuation line
    "let a = 1\n\tlet b = 2\n",  # an unexpected indent: lark's error
    "let a = " + " + ".join(["1"] * 240) + "\n",  # too deep: lark's error
    "let a = " + "(" * 150 + "1" + ")" * 150 + "\n",
    "body b: composite\n    rod(mass = 1 kg)\n  disk(mass = 1 kg)\n",  # bad dedent
    "let a = 1 $ 2\n",
    "",
    "# only a comment",
])
def test_corner_cases_same_outcome(text, monkeypatch):
    assert _outcome(text, True, monkeypatch) == _outcome(text, False, monkeypatch)
    direct = _run_direct(text) if text.strip() else None
    if direct is not None:
        assert direct == _outcome(text, False, monkeypatch)[1]


@pytest.mark.parametrize("how", ["built", "loaded from the cache"])
def test_tables_built_or_loaded(how, tmp_path, monkeypatch):
    """A clean machine builds the tables from a freshly built lark parser (rule names
    are then lark Tokens); a warm one loads them: both give lark's nodes."""
    monkeypatch.setenv("MOMENTUM_CACHE_DIR", str(tmp_path))
    monkeypatch.delenv("MOMENTUM_LARK_ONLY", raising=False)
    syntax.parser.cache_clear()
    syntax._fast_parser.cache_clear()
    try:
        if how != "built":
            assert syntax._fast_parser() is not None  # writes the cache
            assert list(tmp_path.glob("tables-*"))
            syntax.parser.cache_clear()
            syntax._fast_parser.cache_clear()
        for f in FILES[:40]:
            text = f.read_text(encoding="utf-8")
            direct = _run_direct(text)
            if direct is not None:
                assert direct == _outcome(text, False, monkeypatch)[1], f.name
    finally:
        syntax.parser.cache_clear()
        syntax._fast_parser.cache_clear()


def test_one_shot_solve_imports_no_lark(tmp_path):
    """With the tables cached, `solve` of a good file never imports lark (its import and
    parser load were most of a one-shot run's time)."""
    env = dict(os.environ, MOMENTUM_CACHE_DIR=str(tmp_path))
    env.pop("MOMENTUM_LARK_ONLY", None)
    code = ("import runpy, sys\n"
            "sys.argv = ['momentum', 'solve', '--plain', sys.argv[1]]\n"
            "try:\n    runpy.run_module('momentum_cli', run_name='__main__')\n"
            "except SystemExit as e:\n    assert not e.code, e.code\n"
            "sys.stderr.write('LARK=%s' % any(m.split('.')[0] == 'lark' for m in sys.modules))\n")
    seed = str(ROOT / "examples" / "seed_rod_drop_smooth.mom")
    first = subprocess.run([sys.executable, "-c", code, seed], env=env, capture_output=True,
                           text=True, timeout=120)
    assert "LARK=True" in first.stderr  # the first run builds the tables with lark
    again = subprocess.run([sys.executable, "-c", code, seed], env=env, capture_output=True,
                           text=True, timeout=120)
    assert again.stderr.endswith("LARK=False"), again.stderr
    lark = subprocess.run([sys.executable, "-c", code, seed], capture_output=True, text=True,
                          env=dict(env, MOMENTUM_LARK_ONLY="1"), timeout=120)
    assert again.stdout == first.stdout == lark.stdout and "rod.omega@3" in again.stdout


def test_loop_precheck_misses_no_loop():
    """syntax._may_loop (which spares importing loops) is true wherever loops.expand's
    own test finds a loop."""
    import random

    from momentum_cli import loops

    rng = random.Random(5)
    pieces = ["for", " ", "\t", "\n", "x", ".", "..", "body b[1", "]", "#", "f", "or", "\r"]
    texts = [f.read_text(encoding="utf-8") for f in FILES]
    texts += ["".join(rng.choice(pieces) for _ in range(rng.randint(1, 12)))
              for _ in range(5000)]
    for text in texts:
        if loops._MAYBE.search(text):
            assert syntax._may_loop(text), repr(text)


def test_walk_is_lark_transformer():
    """syntax._walk (the lark path's tree -> nodes) equals lark's Transformer with the
    same rules, on every example without loops and on a big file."""
    from momentum_cli.bench import chain_text

    p = syntax.parser()
    texts = [f.read_text(encoding="utf-8") for f in FILES]
    for text in texts + [chain_text(100)]:
        if syntax._may_loop(text):
            continue
        try:
            tree = p.parse(_text(text))
        except Exception:
            continue
        try:
            want = ("ok", syntax._ToNodes().transform(tree).children)
        except Exception as exc:
            want = ("error", type(exc).__name__)
        try:
            got = ("ok", syntax._walk(tree))
        except Exception as exc:
            got = ("error", "VisitError")
        if want[0] == "ok":
            assert got == want


@pytest.mark.parametrize("text", [
    "let a = " + " + ".join(["1"] * 240) + "\n",
    "gain b 1 -> 2:\n    rate 1 kg/s\n    rate 2 kg/s\nlet a = " + " + ".join(["1"] * 240) + "\n",
    "gain b 1 -> 2:\n    rate 1 kg/s\n    rate 2 kg/s\n",
    "let a = " + " - ".join(["2"] * 150) + "\nlet b = 1\n",
])
def test_lark_path_errors_as_before(text, monkeypatch):
    """The lark path (depth measured during the walk) reports what it reported when the
    whole tree was checked first and then transformed: a too-deep tree before any
    callback's error."""
    def before():
        tree = syntax.parser().parse(_text(text))
        try:
            syntax._check_tree_depth(tree)
            return ("ok", syntax._ToNodes().transform(tree).children)
        except ProblemError as exc:
            return ("error", [(d.code, d.message, d.span) for d in exc.diagnostics])
        except Exception as exc:  # lark's VisitError around a callback's ProblemError
            orig = exc.orig_exc
            return ("error", [(d.code, d.message, d.span) for d in orig.diagnostics])

    got = _outcome(text, False, monkeypatch)
    if got[0] == "error":
        got = ("error", [d[:3] for d in got[1]])
    else:
        got = ("ok", list(got[1]))
    want = before()
    if want[0] == "ok":
        want = ("ok", [syntax._plus_minus(s, text) for s in want[1]])
    assert got == want


def test_parsed_documents_pickle_and_tokens_copy():
    """Worker processes send results back pickled: a document parsed by syntax_run (and
    any token it might hold) survives pickle and copy."""
    import copy
    import pickle

    from momentum_cli.syntax_run import Tok

    text = (ROOT / "examples" / "seed_rod_drop_smooth.mom").read_text(encoding="utf-8")
    doc = syntax.parse(Source("seed.mom", text))
    assert pickle.loads(pickle.dumps(doc)).statements == doc.statements
    t = Tok("NAME", "rod", 1, 2, 1, 5)
    for u in (pickle.loads(pickle.dumps(t)), copy.copy(t), copy.deepcopy(t)):
        assert u == "rod" and (u.type, u.line, u.column, u.end_line, u.end_column) == \
            ("NAME", 1, 2, 1, 5)
