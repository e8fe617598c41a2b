"""Compile helper: an impact's why-lines and system-law texts from per-kind format strings.

In: the impulse sources of an impact and the bodies it moves. Out: what compile._why and
system_laws.linear_head say, written once per kind (the sources' roles, directions, and
which points and names are equal, in which order they sort) with stand-in names, then
filled with the real names by str.format.
"""
from __future__ import annotations

import re

from .elements.base import ImpulseSource
from .system_laws import _words, linear_head

ENABLED = True  # tests switch it off to compare with the texts made directly
_PLANS: dict = {}  # kind -> format strings (a few kinds: bounded below)
_LIMIT = 512
_MANY = 16  # sources beyond which no plan is made (a kind key that long repeats rarely)
_STAND_IN = re.compile("\x00([0-9]+)\x00")


def _kind(sources, bodies):
    """The key of what the texts depend on, and the values the placeholders stand for
    (None when a direction is not plain floats: a sweep's traced numbers)."""
    index = {b: k for k, b in enumerate(bodies)}
    points: dict = {}
    whats: dict = {}
    parts = []
    for n, s in enumerate(sources):
        b0, b1 = s.bodies
        d = s.direction
        if d is not None and (type(d[0]) is not float or type(d[1]) is not float):
            return None
        parts.append((index.get(b0, -1), index.get(b1, -1), d, s.torque_only,
                      points.setdefault(s.point, n), whats.setdefault(s.what, n)))
    order = tuple(whats[w] for w in sorted(whats))  # the sorted names, as first indices
    return (len(bodies), tuple(parts), order), order


def _stand_ins(sources, bodies, order):
    """Sources and bodies named by stand-ins `\\x00k\\x00` (k: the placeholder), the what
    names numbered in their real sort order."""
    L, S = len(bodies), len(sources)
    sb = [f"\x00{k}\x00" for k in range(L)]
    index = {b: k for k, b in enumerate(bodies)}
    rank = {n: r for r, n in enumerate(order)}
    points: dict = {}
    whats: dict = {}
    out = []
    for n, s in enumerate(sources):
        b0, b1 = s.bodies
        p = points.setdefault(s.point, n)
        w = whats.setdefault(s.what, n)
        # a what's stand-in sorts by its rank: `\x00` + a fixed-width rank, then its index
        out.append(ImpulseSource(
            (sb[index[b0]] if b0 in index else None, sb[index[b1]] if b1 in index else None),
            f"\x00{L + p}\x00", s.direction, s.torque_only,
            f"\x00{rank[w]:06d}\x00\x00{L + S + w}\x00"))
    return out, sb


def _format(text: str) -> str:
    """A text with stand-ins as a format string: `{k}` for each, braces doubled; a what's
    stand-in (rank, then index) keeps the index only."""
    text = text.replace("{", "{{").replace("}", "}}")
    text = re.sub("\x00[0-9]{6}\x00\x00([0-9]+)\x00", r"{\1}", text)
    return _STAND_IN.sub(r"{\1}", text)


def kind(sources, bodies):
    """What why_lines and linear_texts key their plans on (None: no plan), computed once
    for both."""
    if not ENABLED or not bodies or len(sources) > _MANY or len(bodies) > _MANY:
        return None
    return _kind(sources, bodies)


def why_formats(comp, sources, bodies, got=False) -> list[str] | None:
    """compile._why's lines for this kind as format strings of `values` (None: no plan
    for this kind; `got`: `kind`'s answer)."""
    if got is False:
        got = kind(sources, bodies)
    if got is None:
        return None
    fake, sb = _stand_ins(sources, bodies, got[1])
    return [_format(line) for line in comp._why(fake, None, sb)]


def linear_formats(sources, moved, got=False):
    """(dirs, why, principles) of linear_texts as format strings of `values`; None when
    no direction is free, False when this kind has no plan."""
    if got is False:
        got = kind(sources, moved)
    if got is None:
        return False
    fake, sb = _stand_ins(sources, moved, got[1])
    head = linear_head(fake, sb)
    if head is None:
        return None
    names = ", ".join(sb)
    return (head[0], _format(head[1]),
            [_format(f"linear momentum of {{{names}}} along {_words(d)}: "
                     "sum of m v before = sum of m v after") for d in head[0]])


def compiled(formats: list[str]):
    """One function of `values` giving the texts of `formats` as a list: each an
    f-string, what str.format makes of it without parsing it again each time (None: a
    field other than a plain index)."""
    from string import Formatter

    parts = []
    for fmt in formats:
        pieces = []
        for lit, field, spec, conv in Formatter().parse(fmt):
            pieces.append(lit.replace("{", "{{").replace("}", "}}"))
            if field is not None:
                if not field.isdigit() or spec or conv:
                    return None
                pieces.append(f"{{v[{field}]}}")
        parts.append("f" + repr("".join(pieces)))
    return eval("lambda v: [" + ", ".join(parts) + "]")  # noqa: S307 (our own formats)


def values(sources, bodies) -> list:
    """What the formats' fields stand for: the bodies, each source's point, its name."""
    out = list(bodies)  # list displays, not generators: once per impact of a sequence
    out += [s.point for s in sources]
    out += [s.what for s in sources]
    return out


def why_lines(comp, sources, bodies, got=False) -> list[str]:
    """comp._why(sources, None, bodies), from a plan per kind (`got`: `kind`'s answer)."""
    if got is False:
        got = kind(sources, bodies)
    if got is None:
        return comp._why(sources, None, bodies)
    key = ("why",) + got[0]
    plan = _PLANS.get(key)
    if plan is None:
        plan = why_formats(comp, sources, bodies, got)
        if len(_PLANS) < _LIMIT:
            _PLANS[key] = plan
    vals = values(sources, bodies)
    return [f.format(*vals) for f in plan]


def linear_texts(sources, moved, got=False) -> tuple | None:
    """system_laws.linear_head with each direction's principle: (dirs, why, principles),
    or None (no direction free), from a plan per kind (`got`: `kind`'s answer)."""
    if got is False:
        got = kind(sources, moved)
    if got is None:
        head = linear_head(sources, moved)
        if head is None:
            return None
        names = ", ".join(moved)
        return head[0], head[1], [f"linear momentum of {{{names}}} along {_words(d)}: "
                                  "sum of m v before = sum of m v after" for d in head[0]]
    key = ("linear",) + got[0]
    plan = _PLANS.get(key, _PLANS)
    if plan is _PLANS:
        plan = linear_formats(sources, moved, got)
        if len(_PLANS) < _LIMIT:
            _PLANS[key] = plan
    if plan is None:
        return None
    vals = values(sources, moved)
    return plan[0], plan[1].format(*vals), [f.format(*vals) for f in plan[2]]
