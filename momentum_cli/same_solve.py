"""Run stage, for a batch of files: a file whose statements are those of a file solved
before but for its `problem` title is not solved again.

In: a file of a batch (its text, name and options). Out: its FileResult, as
run.solve_source gives it. Copies of one problem under other titles (a class's set of
files) share every statement node but the `problem` line (statement_memo keeps one node
per statement and line); nothing but the report's file name and title depends on the
title, so such a file's report is the first one's with those two replaced. Only solved
results of small files are kept, and only when no diagnostic points at the `problem`
line; a file whose text statement_memo did not cut (loops) is always solved.
"""
from __future__ import annotations

LIMIT = 16  # results kept (least recently used dropped): a worker gets a family in chunks
MAX_CHARS = 20_000  # larger files are solved each time (their reports are large)
_table: dict = {}


class _Entry:
    __slots__ = ("kind", "others", "report", "diagnostics", "expects")

    def __init__(self, kind, others, report, diagnostics, expects):
        self.kind, self.others, self.report = kind, others, report
        self.diagnostics, self.expects = diagnostics, expects


def _key(doc, options):
    """(key, the statements but the `problem` one), or (None, None): no single
    `problem` statement."""
    from .syntax import Problem

    sts = doc.statements
    at = [i for i, s in enumerate(sts) if type(s) is Problem]
    if len(at) != 1:
        return None, None
    k = at[0]
    others = sts[:k] + sts[k + 1:]
    span = sts[k].span
    return (options, k, span.line, span.column, span.end_line,
            tuple(map(id, others))), others


def solved(solve_source, source, solve_all=False, sig=6, precision="float", overrides=(),
           units="file", sensitivity=False):
    """`solve_source(source, ...)` (run's), or its result made from that of a file solved
    before with the same statements but the title."""
    from .diagnostics import ProblemError
    from .syntax import parse

    options = (solve_all, sig, precision, overrides, units, sensitivity)
    if len(source.text) > MAX_CHARS:
        return solve_source(source, *options)
    try:
        doc = parse(source)
    except (ProblemError, RecursionError):
        return solve_source(source, *options)  # its errors, reported as alone
    key, others = _key(doc, options)
    hit = _table.get(key) if key is not None else None
    if hit is not None and len(hit.others) == len(others) and \
            all(a is b for a, b in zip(hit.others, others)):
        _table[key] = _table.pop(key)  # the last used is kept longest
        rep = hit.report
        title = doc.statements[key[1]].title
        rep = type(rep)(*[getattr(rep, f) for f in rep._fields])
        rep.file, rep.title = source.name, title
        return hit.kind(source.name, "solved", source, rep, list(hit.diagnostics),
                        expects=hit.expects)
    res = solve_source(source, *options, doc=doc)
    if key is not None and res.status == "solved" and res.report is not None:
        line = key[2]
        spans = [d.span for d in res.diagnostics] + [d.span for d in res.report.diagnostics]
        if all(sp is None or (sp.line != line and (sp.end_line or sp.line) != line)
               for sp in spans):
            if len(_table) >= LIMIT:  # the least recently used goes
                del _table[next(iter(_table))]
            _table[key] = _Entry(type(res), others, res.report, list(res.diagnostics),
                                 res.expects)
    return res


def clear() -> None:
    _table.clear()
