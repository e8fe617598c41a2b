"""Parse stage, for a batch of files: a statement that differs from one parsed before only
in its numbers (and a `problem` title) is made from that one's nodes, not parsed.

In: a statement's text (one chunk of statement_memo's cut, at its first line) and the
nodes of a chunk parsed before. Out: the nodes the parse of the new text gives, or None.
Variants of a problem change a mass or a speed: the statement's nodes are the same but
for the numbers' values and the columns after each changed number on its line. This
holds while syntax.Rules keeps a number only as a Num's value and never looks at it
(tests/test_statement_template.py checks every example against the whole parse).
"""
from __future__ import annotations

import re

from .source import Span

# a number as the grammar's NUMBER reads it (not inside a name: `b12`), or a string
_LITERAL = re.compile(r'"[^"\n]*"|(?<![A-Za-z_0-9.])(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?')
_RUNS = re.compile(r"[0-9]+").sub
LIMIT = 4096
_shapes: dict = {}  # (first line, the chunk with its literals blanked) -> Template


class Template:
    """A parsed chunk: its nodes, its literals' (line, start column, text), and which of
    them the nodes hold as a number (a `Num` starts there) or as the `problem` title."""

    __slots__ = ("nodes", "literals", "kinds")

    def __init__(self, nodes, literals, kinds):
        self.nodes, self.literals, self.kinds = nodes, literals, kinds


def shape(a: int, chunk: str):
    """(key, literals): the chunk with every literal blanked (numbers `\\0` and their
    form, strings `\\1`), and each literal as (line, 1-based column, text)."""
    lits = []
    parts = []
    pos = 0
    line, line_start = a + 1, 0
    for m in _LITERAL.finditer(chunk):
        s = m.start()
        nl = chunk.count("\n", pos, s)
        if nl:
            line += nl
            line_start = chunk.rfind("\n", 0, s) + 1
        text = m.group()
        lits.append((line, s - line_start + 1, text))
        parts.append(chunk[pos:s])
        # a number keeps its form (digit runs as 0: `2`, `2.5`, `.5`, `1e-7` differ): in
        # `m/s^2` the 2 is the unit's, in `m/s^.5` a number, which a template would hold
        parts.append("\1" if text[0] == '"' else "\0" + _RUNS("0", text) + "\0")
        pos = m.end()
    parts.append(chunk[pos:])
    return (a, "".join(parts)), lits


def remember(key, literals, nodes) -> None:
    """Keep a freshly parsed chunk as the template of its shape."""
    from .syntax import Num, Problem

    starts = set()
    titles = set()
    _scan(nodes, Num, Problem, starts, titles)
    kinds = []
    for line, col, text in literals:
        if text[0] == '"':
            kinds.append("title" if (line, text[1:-1]) in titles and
                         _first_string(literals, line) == col else "fixed")
        else:
            kinds.append("num" if (line, col) in starts else "fixed")
    if len(_shapes) >= LIMIT:
        _shapes.clear()
    _shapes[key] = Template(nodes, literals, tuple(kinds))


def _first_string(literals, line):
    return next(c for ln, c, t in literals if ln == line and t[0] == '"')


def _scan(node, Num, Problem, starts, titles) -> None:
    t = type(node)
    if t in _LEAVES:
        return
    if t is tuple or t is list:
        for x in node:
            _scan(x, Num, Problem, starts, titles)
        return
    fields = _FIELDS.get(t)
    if fields is None:
        fields = _FIELDS[t] = getattr(t, "_fields", None) or ()
    if not fields:
        return
    if t is Num:
        starts.add((node.span.line, node.span.column))
    elif t is Problem:
        titles.add((node.span.line, node.title))
    for f in fields:
        _scan(getattr(node, f), Num, Problem, starts, titles)


def clear() -> None:
    _shapes.clear()


def template(key) -> Template | None:
    return _shapes.get(key)


def made(key, literals):
    """The nodes of a chunk of shape `key` with these literals, from the template of its
    shape, or None (no template; a literal the nodes do not hold as a number or title
    differs; a node starts or ends inside a changed literal)."""
    tpl = _shapes.get(key)
    if tpl is None:
        return None
    shifts: dict = {}  # line -> [(old end column, exclusive; old start; delta)]
    values: dict = {}  # (line, old start column) -> new float
    title = None
    for (line, col, old), (_, _, new), kind in zip(tpl.literals, literals, tpl.kinds):
        if old == new:
            continue
        if kind == "fixed":
            return None
        if kind == "num":
            values[(line, col)] = float(new)
        else:
            title = (line, new[1:-1])
        if len(new) != len(old):
            shifts.setdefault(line, []).append((col + len(old), col, len(new) - len(old)))
    if not values and title is None:
        return None  # the same text (never: the exact table has it)
    from .syntax import Num, Problem

    def col(line, c):
        d = 0
        for end, start, delta in shifts.get(line, ()):
            if end <= c:
                d += delta
            elif start < c:
                raise _Inside
        return c + d

    leaves, fields_of = _LEAVES, _FIELDS

    def conv(node):
        t = type(node)
        if t in leaves:
            return node
        if t is Span:
            if node.line not in shifts and node.end_line not in shifts:
                return node
            end = node.end_column
            if end is not None and node.end_line is not None:
                end = col(node.end_line, end)
            return Span(node.line, col(node.line, node.column), node.end_line, end,
                        node.where)
        if t is tuple or t is list:
            items = None
            for k, x in enumerate(node):
                y = conv(x)
                if y is not x:
                    if items is None:
                        items = list(node)
                    items[k] = y
            return node if items is None else t(items)
        fields = fields_of.get(t)
        if fields is None:
            fields = fields_of[t] = getattr(t, "_fields", None) or ()
        if not fields:
            return node
        vals = None
        for k, f in enumerate(fields):
            x = getattr(node, f)
            y = conv(x)
            if y is not x:
                if vals is None:
                    vals = [getattr(node, g) for g in fields]
                vals[k] = y
        if t is Num:
            v = values.get((node.span.line, node.span.column))
            if v is not None:
                if vals is None:
                    vals = [getattr(node, g) for g in fields]
                vals[fields.index("value")] = v
        elif t is Problem and title is not None and node.span.line == title[0]:
            if vals is None:
                vals = [getattr(node, g) for g in fields]
            vals[fields.index("title")] = title[1]
        return node if vals is None else t(*vals)

    try:
        return tuple(conv(n) for n in tpl.nodes)
    except _Inside:
        return None


def mapped(nodes, at) -> tuple:
    """Nodes parsed from expanded loops with their spans in the expanded text, with each
    span mapped to the file by `at` (loops.Expansion.at, which the parser calls for each
    span it makes while the map is on): the nodes that parse gives."""
    leaves, fields_of = _LEAVES, _FIELDS

    def conv(node):
        t = type(node)
        if t in leaves:
            return node
        if t is Span:
            return at(node.line, node.column, node.end_line, node.end_column)
        if t is tuple or t is list:
            return t([conv(x) for x in node])
        fields = fields_of.get(t)
        if fields is None:
            fields = fields_of[t] = getattr(t, "_fields", None) or ()
        if not fields:
            return node
        return t(*[conv(getattr(node, f)) for f in fields])

    return tuple([conv(n) for n in nodes])


_LEAVES = frozenset((str, float, int, bool, type(None)))  # never a node: returned as they are
_FIELDS: dict = {Span: ()}  # node type -> its fields to walk (() for a leaf, a Span:
# its own fields are numbers; made and mapped meet a Span before they look here)


class _Inside(Exception):
    """A node's column falls inside a literal whose length changed."""
