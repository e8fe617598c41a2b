"""Diagnostics: what went wrong (or is worth a warning), where, and the exit codes.

Library code raises `ProblemError` (one diagnostic) or `ProblemErrors` (several);
only `cli.py` turns them into exit codes.
"""
from __future__ import annotations

from enum import IntEnum

from .records import field, record
from .source import Source, Span, render_snippet


class ExitCode(IntEnum):
    OK = 0  # solved / checked clean
    PROBLEM = 1  # the problem file is wrong: syntax, units, names, under-/over-determined
    USAGE = 2  # bad flags or arguments, unreadable input file
    INTERNAL = 3  # a bug in momentum
    INTERRUPTED = 130  # Ctrl-C


@record(frozen=True)
class Diagnostic:
    """One message about a problem file, with an optional location and notes."""

    severity: str  # "error" | "warning" | "note"
    code: str  # a short stable identifier, e.g. "syntax", "units", "under-determined"
    message: str
    span: Span | None = None
    notes: tuple[str, ...] = ()
    caret: bool = True

    def format(self, source: Source | None) -> str:
        """GNU style: `file:line:col: severity: message`, then the snippet and notes."""
        name = source.name if source else "<input>"
        where = f"{name}:{self.span.line}:{self.span.column}" if self.span else name
        loop = f" ({self.span.where})" if self.span and self.span.where else ""
        out = [f"{where}: {self.severity}: {self.message}{loop}"]
        if self.span and source and self.caret:
            snippet = render_snippet(source, self.span)
            if snippet:
                out.append(snippet)
        out.extend(f"    note: {n}" for n in self.notes)
        return "\n".join(out)

    def to_json(self) -> dict:
        d: dict = {"severity": self.severity, "code": self.code, "message": self.message}
        if self.span:
            d["line"] = self.span.line
            d["column"] = self.span.column
            if self.span.where:
                d["loop"] = self.span.where
            if self.span.end_line is not None:
                d["end_line"] = self.span.end_line
                d["end_column"] = self.span.end_column
        if self.notes:
            d["notes"] = list(self.notes)
        return d


class ProblemError(Exception):
    """The problem file is wrong; carries one or more diagnostics."""

    def __init__(self, message: str, span: Span | None = None, code: str = "error",
                 notes: tuple[str, ...] | list[str] = (), caret: bool = True,
                 diagnostics: list[Diagnostic] | None = None):
        super().__init__(message)
        if diagnostics is None:
            diagnostics = [Diagnostic("error", code, message, span, tuple(notes), caret)]
        self.diagnostics = diagnostics

    @classmethod
    def many(cls, diagnostics: list[Diagnostic]) -> "ProblemError":
        return cls(diagnostics[0].message, diagnostics=diagnostics)


def did_you_mean(name: str, candidates) -> str:
    """A ' (did you mean X?)' suffix for a misspelt name, or ''."""
    import difflib  # only for a misspelt name

    close = difflib.get_close_matches(name, sorted(set(candidates)), n=1, cutoff=0.6)
    return f"; did you mean '{close[0]}'?" if close else ""


@record
class Collector:
    """Collects warnings and notes while a stage runs (errors are raised)."""

    items: list[Diagnostic] = field(default_factory=list)

    def warn(self, message: str, span: Span | None = None, code: str = "warning", notes=()):
        self.items.append(Diagnostic("warning", code, message, span, tuple(notes)))

    def note(self, message: str, span: Span | None = None, code: str = "note", notes=()):
        self.items.append(Diagnostic("note", code, message, span, tuple(notes)))
