"""Build, compile and analyse give what they gave before their fast paths: every
equation node for node, the unknowns in column order, the transitions' info and the
structure (matching, blocks in order), on every example and on generated big scenes.

The digests in tests/data/structure_digests.json were recorded with the code before the
rewrite (tests/structure_dump.py; regenerate only for an intended change of output).
"""
from __future__ import annotations

import json
from pathlib import Path

import pytest

from momentum_cli.bench import chain_text
from structure_dump import digest
from test_hard import cradle_text

ROOT = Path(__file__).resolve().parent.parent
DIGESTS = json.loads((ROOT / "tests" / "data" / "structure_digests.json").read_text())
EXAMPLES = sorted(k for k in DIGESTS if k.startswith("examples/"))


@pytest.mark.parametrize("name", EXAMPLES)
def test_examples_compile_and_analyse_as_before(name):
    assert digest((ROOT / name).read_text(encoding="utf-8"), name) == DIGESTS[name]


@pytest.mark.parametrize("n", [2, 3, 40, 301])
def test_chain_compiles_as_before(n):
    assert digest(chain_text(n)) == DIGESTS[f"chain {n}"]


@pytest.mark.parametrize("kind", ["sequence", "simultaneous"])
@pytest.mark.parametrize("n", [2, 3, 25, 201])
def test_cradle_compiles_as_before(n, kind):
    assert digest(cradle_text(n, kind)) == DIGESTS[f"cradle {kind} {n}"]
