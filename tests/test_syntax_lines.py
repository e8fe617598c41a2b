"""syntax_lines (the common statement forms read a line at a time, the rest by syntax_run
from its line) gives the nodes of syntax_run's whole-file parse and of lark's, every span
included: on every example, on generated chains and cradles, on the fuzz corpus and on
character-level mutations of the examples; bad files still get lark's diagnostics."""
import copy
import pickle
import random
from pathlib import Path

import pytest

from momentum_cli import syntax, syntax_lines
from momentum_cli.diagnostics import ProblemError
from momentum_cli.source import Source
from momentum_cli.syntax_run import Fallback

ROOT = Path(__file__).resolve().parent.parent
FILES = sorted((ROOT / "examples").rglob("*.mom"))


def _whole(text: str) -> str:
    return text if text.endswith("\n") else text + "\n"


def _by_run(text: str):
    """syntax_run's whole-file statements, or None (it leaves the text to lark)."""
    try:
        return syntax._fast_parser().parse(_whole(text))
    except Fallback:
        return None


def _by_lines(text: str, counts=None):
    """syntax_lines' statements, None (not its layout), or "fallback" (a statement that
    syntax_run refuses). `counts`: [statements read here, statements left to syntax_run]."""
    fast = syntax._fast_parser()
    left = [0]

    def rest(chunk, line):
        left[0] += 1
        return fast.parse(chunk, line)

    try:
        got = syntax_lines.parse(_whole(text), rest, syntax)
    except Fallback:
        return "fallback"
    if counts is not None and got is not None:
        counts[0] += len(got) - left[0]
        counts[1] += left[0]
    return got


def _lark(text: str, monkeypatch):
    """syntax.parse's outcome (statements or diagnostics) with or without lark only."""
    with monkeypatch.context() as m:
        m.setattr(syntax, "_fast_parser", lambda: None)
        return _outcome(text)


def _outcome(text: str):
    """syntax.parse's outcome, syntax_lines used whatever the size (LINES_BYTES 0)."""
    with pytest.MonkeyPatch.context() as m:
        m.setattr(syntax, "LINES_BYTES", 0)
        try:
            return ("ok", syntax.parse(Source("f.mom", text)).statements)
        except ProblemError as exc:
            return ("error", [(d.code, d.message, d.span, d.notes) for d in exc.diagnostics])


def _same_as_run(text: str, name: str, counts=None) -> bool:
    """syntax_lines equals syntax_run wherever it answers; True when it answered."""
    got = _by_lines(text, counts)
    if got is None or got == "fallback":
        return False
    want = _by_run(text)
    assert want is not None, f"{name}: syntax_lines took a text syntax_run refuses"
    assert len(got) == len(want), name
    for i, (g, w) in enumerate(zip(got, want)):
        assert g == w, f"{name}: statement {i}: {g!r} != {w!r}"
    return True


def test_every_example_same_nodes_as_syntax_run_and_lark(monkeypatch):
    counts = [0, 0]
    for f in FILES:
        text = f.read_text(encoding="utf-8")
        if syntax._may_loop(text):
            continue  # loops are written out first and parsed whole by syntax_run
        assert _same_as_run(text, f.name, counts), f.name
        lark = _lark(text, monkeypatch)
        assert _outcome(text) == lark, f.name
    read, left = counts
    assert read > 4 * left  # most statements are of the forms read here


@pytest.mark.parametrize("n", [2, 9, 10, 11, 99, 100, 101, 1000])
def test_generated_chains_and_cradles(n, monkeypatch):
    from momentum_cli.bench import chain_text
    from test_hard import cradle_text

    texts = {"chain": chain_text(n), "sequence": cradle_text(n, "sequence"),
             "simultaneous": cradle_text(n, "simultaneous")}
    for kind, text in texts.items():
        counts = [0, 0]
        assert _same_as_run(text, f"{kind} {n}", counts)
        assert counts[1] <= 2  # (`let` of a quantity is read here too)
        if n <= 100:
            assert _outcome(text) == _lark(text, monkeypatch), f"{kind} {n}"


def test_fuzz_corpus_same_outcome(monkeypatch):
    from fuzz_corpus import corpus

    taken = 0
    for name, data in corpus(200, seed=11):
        try:
            text = data.decode("utf-8")
        except UnicodeDecodeError:
            continue
        if not text.strip():
            continue
        taken += _same_as_run(text, name)
        assert _outcome(text) == _lark(text, monkeypatch), name
    assert taken > 30


_PIECES = [" ", "  ", "\t", "\\\n", "\r", "\n", "\n    ", "#", ",", ":", "(", ")", "-", "+",
           "=", "@", "->", ".", "[", "]", "{", "}", "1", "0.5", "e", "e-3", "x", "in", "at",
           "rest", "end", "ground", "normal", "with", "contact", "smooth", "static", "m",
           "m/s", "kg", "°", '"', "?", "poisson", "b1", "b[2]", "composite", "of", "é"]


def _mutate(text: str, rng: random.Random) -> str:
    """One to three edits at random places: a piece of the grammar inserted, a character
    deleted, or a span of a line replaced."""
    for _ in range(rng.randint(1, 3)):
        i = rng.randrange(len(text) + 1)
        how = rng.random()
        if how < 0.5:
            text = text[:i] + rng.choice(_PIECES) + text[i:]
        elif how < 0.8:
            text = text[:i] + text[i + 1:]
        else:
            text = text[:i] + rng.choice(_PIECES) + text[i + rng.randint(1, 6):]
    return text


@pytest.mark.parametrize("seed", range(4))
def test_mutated_examples_same_as_syntax_run(seed):
    """Edits where the line forms are strict (keywords as prefixes, units after numbers,
    continuation lines, tabs, brackets across lines): syntax_lines agrees with syntax_run
    or hands the statement over. (The diagnostics: test_mutated_examples_same_outcome.)"""
    rng = random.Random(seed)
    bases = [f.read_text(encoding="utf-8") for f in FILES if f.stat().st_size < 20_000]
    bases = [t for t in bases if not syntax._may_loop(t)]
    answered = 0
    for k in range(600):
        text = _mutate(rng.choice(bases), rng)
        answered += _same_as_run(text, f"seed {seed} mutation {k}: {text!r}")
    assert answered > 200


def test_mutated_examples_same_outcome(monkeypatch):
    """Through syntax.parse, mutated files give lark's statements or lark's diagnostics."""
    rng = random.Random(99)
    bases = [f.read_text(encoding="utf-8") for f in FILES if f.stat().st_size < 5_000]
    for k in range(150):
        text = _mutate(rng.choice(bases), rng)
        if not text.strip():
            continue
        assert _outcome(text) == _lark(text, monkeypatch), f"mutation {k}: {text!r}"


@pytest.mark.parametrize("text", [
    "let a = 1 m\n",
    "let a = -b.vx@1->2 # c\n",
    "let a = (1 m, -2 m/s^2)\n",
    "let a = 1 in\n",  # a unit that is a keyword: syntax_run's
    "let a = 5 inch\n",  # `in` then `ch` (a keyword is tried before a unit)
    "let a = 1 + 2\n",
    "body b: particle(mass = 1 kg, radius = r)\n",
    "body b: particle()\n",
    "body b: composite\n    rod(mass = 1 kg, length = 1 m) at (0, 0)\n",
    "body b: particle(mass = 1 kg,)\n",
    "state 1 \"a\": b.v = (1 m/s, 0), c at rest, d rolls on floor, b.vy < 0\n",
    "state 1:\n    b at rest\n    c.v = (0, 0)  # c\n\n# d\nstate 2\n",
    "state 1\n    b at rest\n",
    "state 1: b at  rest,c at rest\n",
    "state 1: b atrest\n",
    "state1: b at rest\n",
    "impact 1 -> 2:\n    contact c1: b2 with b1 normal (1, 0): restitution 1, smooth\n",
    "impact 1 -> 2:\n    contact A with ground normal (0, 1): restitution 0.6 poisson\n"
    "    contact rod.end(+) with B.tip: friction 0.3 static 0.4, restitution ?\n"
    "    b stops\n    b rolls on floor\n    free c\n",
    "impact 1 -> 2:\n    contact A with ground.x\n",
    "impact 1 -> 2:\n    contact A with rod.end\n",
    "impact 1 -> 2:\n    contact A with B: smooth 1\n",
    "impact 1 -> 2\n    contact A with B\n",
    "impact 1 -> 2:\n",
    "interval 1 -> 2\nenergy 2 -> 3 of {a}\n",
    "impact 1 -> 2:\n    contact A with B\n  contact C with D\n",
    "find b1.vx@2, x = J_n[c9]@9->10 in N*s, T_lost@1->2, T[b[3]]@1\n",
    "find 2 in mm\n",
    "find x in in\n",
    "problem \"a # b\"  # c\n",
    "gravity 9.81 m/s^2 down\ngravity -g up\ngravity 9.81 down\n",
    "let a = (1,\n2)\nlet b = 2\n",
    "let a = 1 \\\n  + 2\n",
    "let a = 1\r\nlet b = 2\r\n",
    "let a = 1\n\tlet b = 2\n",
    "  let a = 1\nlet b = 2\n",
    "# c\n\n   # d\nlet a = 1\n   \n# e\n",
    "let a = 1 $ 2\n",
    "let é = 1\n",
])
def test_corner_cases(text, monkeypatch):
    _same_as_run(text, repr(text))
    assert _outcome(text) == _lark(text, monkeypatch)


def test_used_once_enough_text_is_read(monkeypatch):
    """A one-shot parse of a small file does not pay for syntax_lines' set-up (regexes,
    makers): syntax_run parses it; a big file, or the files after enough text was read
    in this process, are read by syntax_lines."""
    text = (ROOT / "examples" / "seed_rod_drop_smooth.mom").read_text(encoding="utf-8")
    used = []
    real = syntax_lines.parse

    def counting(*a):
        used.append(1)
        return real(*a)

    monkeypatch.setattr(syntax_lines, "parse", counting)
    monkeypatch.setattr(syntax, "_READ", [0])
    want = syntax.parse(Source("f.mom", text)).statements
    assert not used
    for _ in range(syntax.LINES_BYTES // len(text) + 1):
        assert syntax.parse(Source("f.mom", text)).statements == want
    assert used


def test_one_shot_small_solve_does_not_import_syntax_lines(tmp_path):
    import os
    import subprocess
    import sys

    env = dict(os.environ, MOMENTUM_CACHE_DIR=str(tmp_path))
    env.pop("MOMENTUM_LARK_ONLY", None)
    code = ("import sys\nfrom momentum_cli import syntax\nfrom momentum_cli.source import "
            "Source\nsyntax.parse(Source('f', open(sys.argv[1]).read()))\n"
            "print('momentum_cli.syntax_lines' in sys.modules)\n")
    seed = str(ROOT / "examples" / "seed_rod_drop_smooth.mom")
    for _ in range(2):  # (the first run builds the tables)
        out = subprocess.run([sys.executable, "-c", code, seed], env=env, capture_output=True,
                             text=True, timeout=120)
    assert out.stdout.strip() == "False", out.stderr


def test_lark_only_means_lark_only(monkeypatch):
    """MOMENTUM_LARK_ONLY=1: neither syntax_run nor syntax_lines parses."""
    monkeypatch.setenv("MOMENTUM_LARK_ONLY", "1")
    syntax._fast_parser.cache_clear()

    def refuse(*a, **k):
        raise AssertionError("syntax_lines was used")

    monkeypatch.setattr(syntax_lines, "parse", refuse)
    monkeypatch.setattr(syntax, "LINES_BYTES", 0)
    try:
        text = (ROOT / "examples" / "seed_rod_drop_smooth.mom").read_text(encoding="utf-8")
        assert syntax.parse(Source("f.mom", text)).statements
    finally:
        syntax._fast_parser.cache_clear()


def test_records_built_by_the_makers_are_the_records():
    """The makers' records are of the class, equal, hashed, frozen and pickled as the
    constructor's."""
    from dataclasses import FrozenInstanceError

    from momentum_cli.source import Span

    syntax_lines.setup(syntax)
    made = syntax_lines.Span(1, 2, 3, 4)
    want = Span(1, 2, 3, 4)
    assert type(made) is Span and made == want and hash(made) == hash(want)
    assert repr(made) == repr(want) and made.where is None
    with pytest.raises(FrozenInstanceError):
        made.line = 5
    assert pickle.loads(pickle.dumps(made)) == want and copy.deepcopy(made) == want
    num = syntax_lines.Num(made, 1.5)
    assert type(num) is syntax.Num and num == syntax.Num(want, 1.5)
    ref = syntax_lines.PointRef(made, "rod", end="+")
    assert ref == syntax.PointRef(want, "rod", None, "+")


def test_depth_check_shortcut_is_the_scan():
    """_check_depth's pass over paired brackets reports what the bracket scan reports."""
    import re

    def scan(text):
        depth = best = 0
        for m in re.finditer(r"[()\[\]{}]", text):
            if m.group() in "([{":
                depth += 1
                best = max(best, depth)
                if best > syntax.MAX_DEPTH:
                    i = m.start()
                    return (text.count("\n", 0, i) + 1, i - text.rfind("\n", 0, i))
            else:
                depth = max(depth - 1, 0)
        return None

    rng = random.Random(3)
    for _ in range(400):
        parts = []
        for _ in range(rng.randint(1, 4)):
            d = rng.choice([1, 5, 150, 199, 200, 201, 230])
            o, c = rng.choice(["()", "[]", "{}", "(]"])
            parts.append(o * d + rng.choice(["x", "\n", "é", ""]) + c * rng.choice([d, d - 1,
                                                                                   d + 1]))
        text = "".join(rng.sample(parts, len(parts)))
        try:
            syntax._check_depth(Source("f", text))
            got = None
        except ProblemError as exc:
            got = (exc.diagnostics[0].span.line, exc.diagnostics[0].span.column)
        assert got == scan(text)


def test_shape_builders_same_nodes(monkeypatch):
    """With a builder written for every shape of line at its first use, the examples,
    their mutations, chains and cradles (whose lines differ in their digits: b9/b10,
    masses of every length) still give syntax_run's nodes."""
    from momentum_cli.bench import chain_text
    from test_hard import cradle_text

    monkeypatch.setattr(syntax_lines, "BUILD_AFTER", 1)
    monkeypatch.setattr(syntax_lines, "STORE", False)  # (stored ones: test_builder_store)
    syntax_lines.setup(syntax)
    monkeypatch.setattr(syntax_lines, "_SHAPES", {})
    rng = random.Random(7)
    bases = [f.read_text(encoding="utf-8") for f in FILES if f.stat().st_size < 20_000]
    bases = [t for t in bases if not syntax._may_loop(t)]
    texts = bases + [_mutate(rng.choice(bases), rng) for _ in range(300)]
    texts += [chain_text(150), cradle_text(150, "sequence"), cradle_text(150, "simultaneous")]
    for i, text in enumerate(texts):
        _same_as_run(text, f"text {i}: {text[:200]!r}")
    built = [v for v in syntax_lines._SHAPES.values() if callable(v)]
    assert len(built) > 50
