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


# while run.solve_many solves a batch: statement_memo.units(doc, _units), the same list
UNITS: list = [None]


_SI = FileUnits()
# where a name of US_NAMES or DEGREE_NAMES can start: each one begins with one of these
_ROOTS = ("slug", "lb", "ft", "in", "yd", "mi", "mph", "kip", "fps", "oz", "hp", "deg")
_WORD = frozenset("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz_")


def may_name(text: str) -> bool:
    """False only if no unit the grammar can read from `text` names a US customary or a
    degree unit. A unit (the grammar's UNIT, or `in`) starts after a number, a space or
    the keyword `in`, and each name in it after `*`, `/` or a digit: so every such name
    starts in the text where no letter or `_` comes before it. True at the first place
    one of _ROOTS starts so outside a comment, or at a `°`. A `#` with no `"` before it on
    its line starts a comment (one inside a string has a `"` before it: not skipped)."""
    if "°" in text:
        return True
    if len(text) >= SCAN_BYTES:
        return _may_name_scanned(text)
    word = _WORD
    for root in _ROOTS:
        i = text.find(root)
        while i >= 0:
            if i == 0 or text[i - 1] not in word:
                line = text[text.rfind("\n", 0, i) + 1:i]
                hash_ = line.find("#")
                if hash_ < 0 or '"' in line[:hash_]:
                    return True
            i = text.find(root, i + 1)
    return False


SCAN_BYTES = 1 << 16  # a longer text: each root found by a regex, not by str.find
_ROOT_AT: list = []  # per root: the root where no letter or `_` comes before it


def _may_name_scanned(text: str) -> bool:
    """may_name of a long text: the regex engine skips to each root (its first letter)
    and tests the letter before it itself (a lookbehind after the root), where str.find
    found every `ft` of `after` and Python tested each (the 10^4-impact cradle: 20 ->
    ~7 ms). No root overlaps itself, so the matches are the places str.find visits."""
    if not _ROOT_AT:
        _ROOT_AT.extend(re.compile(f"{r}(?<![A-Za-z_]{r})") for r in _ROOTS)
    for rx in _ROOT_AT:
        for m in rx.finditer(text):
            i = m.start()
            line = text[text.rfind("\n", 0, i) + 1:i]
            hash_ = line.find("#")
            if hash_ < 0 or '"' in line[:hash_]:
                return True
    return False


def detect(doc) -> FileUnits:
    """Count the unit names the file uses (each occurrence once). A document whose text
    names no US or degree unit (`si_text`, decided by the parse) is SI without a walk."""
    if getattr(doc, "si_text", False):
        return _SI
    us = si = 0
    degrees = False
    seen: dict[str, tuple[int, int, bool]] = {}  # a unit string's counts, found once
    walk = UNITS[0]  # a hook: statement_memo.units (each shared statement walked once)
    for unit in (_units(doc) if walk is None else walk(doc, _units)):
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
_SEQ = ("<seq>",)  # the plan of a list or tuple: its items
_PLANS: dict = {}  # type -> () (nothing inside), _SEQ, or its fields [(name, is unit)]


def _plan(t) -> tuple:
    """What the walk looks at in a node of type `t`, decided once per type as the walk
    always did per node: a leaf (str, int, float, bool and their subclasses, None)
    nothing; a list or tuple its items; a record its fields, in reverse for the stack.
    A Span (line and column numbers, half the nodes of a parsed file) never holds a
    unit: nothing."""
    from .source import Span

    if t is type(None) or issubclass(t, _LEAF):
        plan: tuple = ()
    elif issubclass(t, (list, tuple)):
        plan = _SEQ
    else:
        fields = getattr(t, "_fields", None)
        plan = () if not fields or issubclass(t, Span) else \
            tuple((f, f == "unit") for f in reversed(fields))
    _PLANS[t] = plan
    return plan


def _units(root, limit: int = 200):
    """Every `unit` string in the syntax tree (records, lists and tuples of them), nodes
    deeper than `limit` skipped; a walk with its own stack (a generator per node made a
    10^4-ball file's walk cost 0.45 s), one plan lookup per node."""
    out: list[str] = []
    stack = [(root, 0)]
    pop, push = stack.pop, stack.append
    plans = _PLANS
    while stack:
        node, depth = pop()
        if depth < 0:
            out.append(node)
            continue
        if depth > limit:
            continue
        t = type(node)
        plan = plans.get(t)
        if plan is None:
            plan = _plan(t)
        if not plan:
            continue
        depth += 1
        if plan is _SEQ:
            for x in reversed(node):
                child = plans.get(type(x))
                if child is None:
                    child = _plan(type(x))
                if child:
                    push((x, depth))
            continue
        for f, is_unit in plan:
            v = getattr(node, f, None)
            if is_unit and isinstance(v, str):
                push((v, -1))  # a unit string: yielded in order when popped
            elif v is not None:
                # a child with nothing inside (a leaf, a Span) is not pushed at all
                child = plans.get(type(v))
                if child is None:
                    child = _plan(type(v))
                if child:
                    push((v, depth))
    return out
