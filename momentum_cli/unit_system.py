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
_SEQ = "seq"
_PLAN: dict[type, object] = {type(None): ()}  # a node type -> the fields to walk (or _SEQ)


def _plan(t: type):
    """What to walk in a node of type t: nothing (a leaf), its items, or its fields."""
    if issubclass(t, _LEAF):
        return ()
    if issubclass(t, (list, tuple)):
        return _SEQ
    return tuple(reversed(getattr(t, "_fields", None) or ()))  # pushed last-first


def _units(root, limit: int = 200):
    """Every `unit` string in the syntax tree (records, lists and tuples of them), in
    pre-order, nodes deeper than `limit` skipped; a walk with its own stack and a plan
    per node type (the walk of a 10^4-ball file: 0.45 s -> 0.2 s)."""
    out: list[str] = []
    stack = [(root, 0)]
    pop, push = stack.pop, stack.append
    plan = _PLAN
    while stack:
        node, depth = pop()
        if depth < 0:  # a unit string, in its place
            out.append(node)
            continue
        if depth > limit:
            continue
        what = plan.get(type(node))
        if what is None:
            what = plan[type(node)] = _plan(type(node))
        if not what:
            continue
        depth += 1
        if what is _SEQ:
            for x in reversed(node):
                w = plan.get(type(x))
                if w is None or w:
                    push((x, depth))
            continue
        for f in what:
            v = getattr(node, f, None)
            if f == "unit" and isinstance(v, str):
                push((v, -1))
                continue
            w = plan.get(type(v))
            if w is None or w:
                push((v, depth))
    return out
