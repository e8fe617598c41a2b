"""The hostile corpus (tests/fuzz_corpus.py) through solve and simulate: no traceback,
no hang, no silent nonsense, no non-finite answer.

CI runs a fixed budget (CI_COUNT files, a few seconds); the large run is on demand:
    python -m pytest -m fuzz --fuzz-count 100000 -s
and prints its figures (the README's "Robustness" section quotes one).
"""
from __future__ import annotations

import pytest
from fuzz_corpus import Tally, corpus, run

CI_COUNT = 200


def _check(tally: Tally) -> None:
    print("\n" + tally.line())
    for what in ("tracebacks", "hangs", "nonsense", "non_finite"):
        found = getattr(tally, what)
        assert not found, f"{what}: {len(found)}, e.g. " + "; ".join(found[:5])


def test_fixed_corpus_gives_answers_or_located_errors():
    tally = Tally()
    for name, data in corpus(CI_COUNT, seed=14):
        run(name, data, tally)
    assert tally.inputs == CI_COUNT and tally.solved and tally.errors
    _check(tally)


def test_corpus_is_deterministic():
    assert list(corpus(20, seed=3)) == list(corpus(20, seed=3))
    assert list(corpus(20, seed=3)) != list(corpus(20, seed=4))


@pytest.mark.fuzz
def test_large_corpus(request):
    count = request.config.getoption("--fuzz-count")
    seed = request.config.getoption("--fuzz-seed")
    tally = Tally()
    for name, data in corpus(count, seed=seed):
        run(name, data, tally)
    _check(tally)
