"""The front of a batch remembers what depends only on a file's literals and structure,
across files: the same scenes (scene._LITERALS: the SI value of a literal number, vector
or direction) as building each file with nothing remembered, on every example and on
variants with their numbers changed (zeros and signs too)."""
from __future__ import annotations

import random
import re
from pathlib import Path

from momentum_cli import scene
from momentum_cli.diagnostics import ProblemError
from momentum_cli.source import Source
from momentum_cli.syntax import parse

ROOT = Path(__file__).resolve().parent.parent / "examples"
EXAMPLES = sorted(p for p in list(ROOT.glob("*.mom")) + list(ROOT.glob("simulate/*.mom")) +
                  list(ROOT.glob("hard/*.mom")) if "cradle_1000" not in p.name)
NUMBER = re.compile(r"(?<=[=(,] )(-?\d+\.?\d*)(?=[ ,)\n])")
TEXTS = ["0", "-0", "0.0", "1", "-1", "2.5", "-2.5", "1e-3", "450", "0.045"]


def variant(text: str, rng: random.Random) -> str:
    return NUMBER.sub(lambda m: rng.choice(TEXTS) if rng.random() < 0.4 else m.group(1), text)


class _Forgets(dict):
    def __setitem__(self, key, value):
        pass


def built(doc):
    try:
        return repr(scene.build(doc))  # repr: -0.0 and 0.0 differ, Const by its value
    except ProblemError as exc:
        return [(d.code, d.message, d.span) for d in exc.diagnostics]


def test_scenes_with_literals_remembered_equal_scenes_built_afresh():
    rng = random.Random(5)
    docs = []
    for p in EXAMPLES:
        text = p.read_text(encoding="utf-8")
        for t in [text] + [variant(text, rng) for _ in range(3)]:
            try:
                docs.append((p.name, parse(Source(p.name, t))))
            except ProblemError:
                pass
    for k, (a, b) in enumerate([("pos = (1 m, 0)", "v = (1 m, 0)"), ("x = 2 m", "vx = 2 m"),
                                ("v = (0, 3 m/s)", "v = (0, -3 m/s)")]):
        # one literal in two places: a dimension (or a sign) apart, an error or not
        text = (f'body ball: particle(mass = 1 kg)\nstate 1: ball.{a}\nstate 2: ball.{b}\n'
                'find ball.vx@2\n')
        docs.append((f"two places {k}", parse(Source("t.mom", text))))
    scene._LITERALS.clear()
    warm = [built(d) for _, d in docs]  # each file meets what the files before left
    assert len(scene._LITERALS) > 50
    kept = scene._LITERALS
    scene._LITERALS = _Forgets()  # nothing remembered: each literal evaluated where it is
    try:
        fresh = [built(d) for _, d in docs]
    finally:
        scene._LITERALS = kept
        kept.clear()
    for (name, _), w, f in zip(docs, warm, fresh):
        assert w == f, name
    assert sum(isinstance(w, str) for w in warm) > len(EXAMPLES)


def test_si_text_from_the_statements_equals_the_texts():
    """A batch's documents take `si_text` from their statements' (statement_memo keeps
    unit_system.may_name of each): the same as of the whole text, on every example, its
    variants and texts where a unit name sits at a statement's edge, in a title, in a
    comment, or a `°` before the first statement."""
    from momentum_cli import statement_memo
    from momentum_cli.unit_system import may_name

    base = "body a: particle(mass = 1 kg)\nstate 1: a.vx = 2 m/s\nfind a.vx@1\n"
    texts = [base, "# 30° tilt\n" + base, 'problem "ft lb"\n' + base,
             base.replace("find a.vx@1", "find a.vx@1 in ft/s"),
             base + "# in ft\n", base.replace("2 m/s", "2 ft/s"),
             base.replace("state 1: a.vx = 2 m/s", "state 1: a.vx = 2 m/s  # 2 mph"),
             base.replace("1 kg", "1 slug"), "\n\n" + base + "find a.vx@1 in mph\n"]
    rng = random.Random(9)
    for p in EXAMPLES:
        text = p.read_text(encoding="utf-8")
        texts += [text, variant(text, rng)]
    sources = [Source(f"f{k}.mom", t) for k, t in enumerate(texts)]
    with statement_memo.enabled():
        batch = []
        for s in sources + sources:  # twice: the second time from the table
            try:
                batch.append(parse(s).si_text)
            except ProblemError:
                batch.append(None)
    whole = []
    for s in sources + sources:
        try:
            d = parse(s)
        except ProblemError:
            whole.append(None)
            continue
        from momentum_cli.loops import expand

        e = expand(s.text)
        assert d.si_text == (not may_name(e.text if e else s.text))
        whole.append(d.si_text)
    assert batch == whole
    assert False in whole and True in whole


def test_chronological_in_file_order_equals_kahns_sort():
    """compile._chronological returns file order without sorting when no phase starts
    where it or a later one ends: the same order as Kahn's sort, on random phase lists
    (chains, branches, cycles, self-loops, repeats)."""
    from types import SimpleNamespace

    from momentum_cli.compile import _chronological, _kahn

    rng = random.Random(3)
    seen_fast = 0
    for _ in range(3000):
        n = rng.randint(0, 7)
        states = [str(k) for k in range(rng.randint(1, 6))]
        phases = [SimpleNamespace(before=rng.choice(states), after=rng.choice(states))
                  for _ in range(n)]
        if rng.random() < 0.5:  # a chain in order, as most files write one
            phases = [SimpleNamespace(before=str(k), after=str(k + 1)) for k in range(n)]
        got, want = _chronological(phases), _kahn(phases)
        assert [id(p) for p in got] == [id(p) for p in want]
        seen_fast += all(p.before not in {q.after for q in phases[k:]}
                         for k, p in enumerate(phases))
    assert seen_fast > 1000
