"""Scene stage: which unit system a file is written in, for the reader's units.

In: the parsed document (every `unit` a number, `unknown` or `find` item carries).
Out: `FileUnits`: "us" when US customary units outnumber SI ones, and whether angles
were typed in degrees. The solve stays in SI; only the report converts back.
"""
from __future__ import annotations

import re

from .records import record

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
    for unit in _units(doc):
        for name in _NAME.findall(unit.removeprefix("in:")):
            us += name in US_NAMES
            si += name in SI_NAMES
            degrees |= name in DEGREE_NAMES
    return FileUnits("us" if us > si else "si", degrees)


def _units(node) -> list[str]:
    """Every `unit` string in the syntax tree (records, lists and tuples of them), in no
    particular order; a walk with its own stack (a generator per node cost a fifth of
    building a small scene), down to the same depth of 200."""
    scalar = (str, int, float, bool)
    out: list[str] = []
    stack = [(node, 0)]
    pop, push = stack.pop, stack.append
    while stack:
        node, depth = pop()
        if depth > 200 or node is None or isinstance(node, scalar):
            continue
        if isinstance(node, (list, tuple)):
            stack.extend((x, depth + 1) for x in node)
            continue
        fields = getattr(type(node), "_fields", None)
        if not fields:
            continue
        for f in fields:
            v = getattr(node, f, None)
            if f == "unit" and isinstance(v, str):
                out.append(v)
            elif v is not None and not isinstance(v, scalar):
                push((v, depth + 1))
    return out
