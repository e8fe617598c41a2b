"""Parse stage, for a batch of files: each statement parsed once per text and line.

In: a loop-free problem text and the parse of a whole text. Out: the statement nodes the
whole text's parse gives, from a table keyed by (first line, the statement's lines);
None where the text is not cut into statements here (the caller parses it whole).
Variants of a problem share most of their lines at the same line numbers, so a batch
parses only the lines that differ. Used by run.solve_many for each file of a batch.
"""
from __future__ import annotations

import re

from . import statement_template, syntax_lines  # imported before a batch forks its workers
from .unit_system import may_name

LIMIT = 8192  # statements kept; a batch of variants repeats a few hundred
_table: dict = {}
_may: dict = {}  # the table's key -> unit_system.may_name of its statement's text
_JOINS = re.compile(r".*\\[\t \f]*$").match  # a line the grammar joins to the next


def parse(text: str, parse_text, loops=None, by_lines: bool = False):
    """The statement nodes of `text` (the file, or with `loops` its loops written out),
    or None: parse it whole. `parse_text(text)`: the statement nodes of a text (it
    raises where it cannot). `by_lines`: a new statement of a loop-free text is read by
    syntax_lines (the common forms, 2-3x faster), parse_text parsing the others.

    A statement starts with a letter at column 1; every other line (indented, blank, a
    comment) belongs to the statement before it, as syntax_lines cuts a file. Each
    statement is parsed alone, with its line numbers (the newlines before it), and kept
    with its text and first line as the key: the nodes are frozen records, shared by
    every file that has the same statement at the same line. Any text this cut might
    not match (something before the first statement, a `\\` continuation at the end
    of a statement, a statement that does not parse alone) is left to the whole parse, which also reports errors.
    Written-out loops: a node's span is mapped to the file through the lines' origins
    (loops.Expansion.at), so their key holds those origins too; their templates hold the
    nodes with the expanded text's spans (parsed with no map), mapped for each file.
    """
    lines = text.split("\n")
    if lines[-1] == "":
        lines.pop()  # the "" after the final newline
    heads = [i for i, x in enumerate(lines) if x[:1].isalpha() and x[0].isascii()]
    if not heads:
        return None
    for i in range(heads[0]):
        s = lines[i].lstrip(" \t\f")
        if s and s[0] != "#":
            return None
    if "\r" in text or "\f" in text:
        return None  # other line ends: the whole parse decides
    heads.append(len(lines))
    if "\\" in text:  # a `\` continuation inside a statement stays in its chunk; one
        for h in heads:  # that ends a statement's last line joins the next: parse whole
            if h and _JOINS(lines[h - 1]):
                return None
    table = _table
    out = Statements()
    mays = _may
    may = "°" in text  # unit_system.may_name of the text: of its statements, or a `°`
    if by_lines:
        from . import syntax

        read = syntax_lines.read
    for k in range(len(heads) - 1):
        a, b = heads[k], heads[k + 1]
        chunk = "\n".join(lines[a:b]) + "\n"
        if loops is None:
            key = (a, chunk)
        else:
            key = (a, chunk, tuple([(o.line, o.text, o.where) for o in loops.origins[a:b]]))
        nodes = table.get(key)
        if nodes is None:
            shape, literals = statement_template.shape(a, chunk)
            raw = statement_template.made(shape, literals)  # new numbers, same nodes
            if raw is not None:
                nodes = raw if loops is None else statement_template.mapped(raw, loops.at)
                _same_units(nodes, statement_template.template(shape).nodes)
                out.extend(nodes)
                may = may or may_name(chunk)
                continue
            try:  # spans in the text read (the expanded one: mapped to the file)
                raw = read(lines, a, b, syntax) if by_lines else None
                raw = _raw_parse(parse_text, "\n" * a + chunk) if raw is None else (raw,)
                nodes = raw if loops is None else statement_template.mapped(raw, loops.at)
            except Exception:  # an error, or a cut that does not fit: the whole parse's
                return None
            if len(table) >= LIMIT:
                table.clear()
                mays.clear()
            table[key] = nodes
            mays[key] = may_name(chunk)
            statement_template.remember(shape, literals, raw)
        out.extend(nodes)
        may = may or mays[key]
    out.si_text = not may
    return out


class Statements(list):
    """parse's statement nodes, and the document's `si_text` (unit_system.may_name of
    the text, from its statements': a name starts after a line's start or a non-word
    character, so none spans two statements; the lines before the first are comments)."""

    __slots__ = ("si_text",)


def _raw_parse(parse_text, text: str) -> tuple:
    """The nodes of an expanded chunk with their spans in the expanded text: the parse
    with syntax's map to the file switched off (statement_template.mapped maps them, as
    the parser would have, span by span)."""
    from . import syntax

    spans = syntax._SPANS
    before = spans[0]
    if before is None:
        return tuple(parse_text(text))
    spans[0] = None
    try:
        return tuple(parse_text(text))
    finally:
        spans[0] = before


_units: dict = {}  # id(statement) -> (statement, its unit strings), for the table's


def _same_units(made, like) -> None:
    """Statements made from a template's (`like`) hold its units (only numbers, titles
    and columns differ): each takes that one's list in `units`' table, if walked."""
    memo = _units
    for n, o in zip(made, like):
        hit = memo.get(id(o))
        if hit is not None and hit[0] is o and len(memo) < LIMIT:
            memo[id(n)] = (n, hit[1])


def units(doc, walk) -> list:
    """`walk(doc)` (unit_system's list of every unit string in the document, in order),
    each statement of the table walked once: a statement's list is the walk of it alone,
    two levels down (the document, its statements' tuple), and the document's list is
    theirs one after another, as its walk visits them."""
    out: list = []
    memo = _units
    for stmt in doc.statements:
        hit = memo.get(id(stmt))  # the entry holds the statement: its id is not reused
        if hit is None or hit[0] is not stmt:
            if len(memo) >= LIMIT:
                memo.clear()
            hit = memo[id(stmt)] = (stmt, walk(stmt, 200 - 2))
        out.extend(hit[1])
    return out


class hooked:
    """While one file of a batch is solved: syntax's parse goes statement by statement
    through the table, and unit_system's walk of a document through each statement's
    list. The tables stay for the next file (`clear` empties them)."""

    def __enter__(self):
        from . import syntax, unit_system

        self.before = syntax.STATEMENTS[0], unit_system.UNITS[0]
        syntax.STATEMENTS[0] = parse
        unit_system.UNITS[0] = units
        return self

    def __exit__(self, *exc):
        from . import syntax, unit_system

        syntax.STATEMENTS[0], unit_system.UNITS[0] = self.before
        return False


def clear() -> None:
    _table.clear()
    _may.clear()
    statement_template.clear()
    _units.clear()


class enabled(hooked):
    """`hooked`, and the tables emptied at the end."""

    def __exit__(self, *exc):
        super().__exit__(*exc)
        clear()
        return False
