"""Scene stage: which unit system a file is written in, for the reader's units.

In: the parsed document (every `unit` a number, `unknown` or `find` item carries).
Out: `FileUnits`: "us" when US customary units outnumber SI ones, and whether angles
were typed in degrees. The solve stays in SI; only the report converts back.
"""
from __future__ import annotations

import re

from .records import record
from .source import Span

# names that decide the system; s, rad, rev, rpm, Hz, min, h belong to both
US_NAMES = {"slug", "lb", "lbs", "lbf", "lbm", "ft", "in", "inch", "yd", "mi", "mph", "kip",
            "fps", "oz", "hp"}
SI_NAMES = {"kg", "gram", "t", "tonne", "m", "mm", "cm", "km", "N", "kN", "J", "kJ", "W", "kW",
            "MW", "kph", "kmh"}
DEGREE_NAMES = {"deg", "degree", "°"}
_NAME = re.compile(r"[A-Za-z_][A-Za-z_0-9]*|°")


@record(frozen=True)
class FileUnits:
    system: str = "si"  # "si" | "us"
    degrees: bool = False  # an angle was typed in degrees


def detect(doc) -> FileUnits:
    """Count the unit names the file uses (each occurrence once)."""
    us = si = 0
    degrees = False
    seen: dict[str, tuple[int, int, bool]] = {}  # a unit string's counts, found once
    for unit in _units(doc):
        hit = seen.get(unit)
        if hit is None:
            u = s = 0
            d = False
            for name in _NAME.findall(unit.removeprefix("in:")):
                u += name in US_NAMES
                s += name in SI_NAMES
                d |= name in DEGREE_NAMES
            hit = seen[unit] = (u, s, d)
        us += hit[0]
        si += hit[1]
        degrees |= hit[2]
    return FileUnits("us" if us > si else "si", degrees)


_LEAF = (str, int, float, bool, Span)  # a Span holds numbers only: not walked (~40 % of nodes)


def _units(root, limit: int = 200):
    """Every `unit` string in the syntax tree (records, lists and tuples of them), nodes
    deeper than `limit` skipped; a walk with its own stack (a generator per node made a
    10^4-ball file's walk cost 0.45 s)."""
    out: list[str] = []
    stack = [(root, 0)]
    pop, push = stack.pop, stack.append
    while stack:
        node, depth = pop()
        if depth < 0:
            out.append(node)
            continue
        if depth > limit or node is None or isinstance(node, _LEAF):
            continue
        if isinstance(node, (list, tuple)):
            for x in reversed(node):
                push((x, depth + 1))
            continue
        fields = getattr(type(node), "_fields", None)
        if not fields:
            continue
        for f in reversed(fields):
            v = getattr(node, f, None)
            if f == "unit" and isinstance(v, str):
                push((v, -1))  # a unit string: yielded in order when popped
            elif v is not None and not isinstance(v, _LEAF):
                push((v, depth + 1))
    return out
