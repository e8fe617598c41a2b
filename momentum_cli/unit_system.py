"""Scene stage: which unit system a file is written in, for the reader's units.

In: the parsed document (every `unit` a number, `unknown` or `find` item carries).
Out: `FileUnits`: "us" when US customary units outnumber SI ones, and whether angles
were typed in degrees. The solve stays in SI; only the report converts back.
"""
from __future__ import annotations

import re

from .records import record
from .source import Source, Span

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


_LEAF = (str, int, float, bool)
_NO_UNITS = (Span, Source)  # a source location, the file itself: most nodes of a tree


def _units(root, limit: int = 200):
    """Every `unit` string in the syntax tree (records, lists and tuples of them), nodes
    deeper than `limit` skipped; a walk with its own stack (a generator per node made a
    10^4-ball file's walk cost 0.45 s). What a value is (nothing to walk, a sequence, a
    record and its fields) is decided once per class."""
    out: list[str] = []
    stack = [(root, 0)]
    pop, push = stack.pop, stack.append
    kinds: dict[type, object] = {}  # class -> None (skip), SEQUENCE, or its fields reversed
    while stack:
        node, depth = pop()
        if depth < 0:
            out.append(node)
            continue
        if depth > limit:
            continue
        t = type(node)
        kind = kinds[t] if t in kinds else _kind(kinds, t)
        if kind is None:
            continue
        if kind is SEQUENCE:
            for x in reversed(node):
                if x is not None:
                    push((x, depth + 1))
            continue
        for f in kind:
            v = getattr(node, f, None)
            if v is None:
                continue
            if f == "unit" and isinstance(v, str):
                push((v, -1))  # a unit string: yielded in order when popped
                continue
            tv = type(v)
            if (kinds[tv] if tv in kinds else _kind(kinds, tv)) is not None:
                push((v, depth + 1))
    return out


SEQUENCE = object()  # the walk's mark for a list or tuple: walk its items


def _kind(kinds: dict, t: type):
    """What the walk does with a value of class t (remembered in `kinds`)."""
    if issubclass(t, _LEAF) or issubclass(t, _NO_UNITS) or t is type(None):
        k = None
    elif issubclass(t, (list, tuple)):
        k = SEQUENCE
    else:
        k = tuple(reversed(getattr(t, "_fields", None) or ())) or None
    kinds[t] = k
    return k
