"""Source text and spans: the only place that formats a caret under a location.

A `Source` is a file's name and text; a `Span` is a 1-based line:column range in it.
`render_snippet` prints the offending line with a caret, GNU style.
"""
from __future__ import annotations

from .records import record


@record(frozen=True)
class Span:
    """A 1-based range in a source file (end is inclusive of the last character)."""

    line: int
    column: int
    end_line: int | None = None
    end_column: int | None = None
    where: str | None = None  # a line written by a loop: "in loop iteration i = 17"

    def __str__(self) -> str:
        return f"{self.line}:{self.column}"


@record(frozen=True)
class Source:
    """A problem file's name (as the user gave it; `<stdin>` for `-`) and text."""

    name: str
    text: str

    def line_text(self, line: int) -> str:
        """Line `line` (1-based) without its end. Lines end at '\\n' only, as lark counts
        them (`str.splitlines` also splits at form feeds and U+2028, which would shift
        every line number after one)."""
        lines = self.text.split("\n")
        if 1 <= line <= len(lines):
            return lines[line - 1].removesuffix("\r")
        return ""


WINDOW = 100  # columns of a long line shown around the caret


def render_snippet(source: Source, span: Span) -> str:
    """The source line of `span` with a caret (and tildes) under the spot.

    Tabs are expanded the way lark counts columns, so the caret lines up. Control
    characters show as '?', and a long line is cut to a window around the caret.
    """
    raw = source.line_text(span.line)
    if not raw.strip():
        return ""
    before = raw[: max(span.column - 1, 0)].expandtabs()
    shown = "".join(c if c.isprintable() else "?" for c in raw.expandtabs())
    width = 1
    if span.end_line == span.line and span.end_column and span.end_column > span.column:
        width = max(len(raw[: span.end_column - 1].expandtabs()) - len(before), 1)
    start = len(before)
    prefix = suffix = ""
    if len(shown) > WINDOW:
        lo = max(0, min(start - WINDOW // 3, len(shown) - WINDOW))
        hi = min(len(shown), lo + WINDOW)
        prefix, suffix = ("..." if lo > 0 else ""), ("..." if hi < len(shown) else "")
        shown = prefix + shown[lo:hi] + suffix
        width = max(min(width, hi - start), 1)
        start = start - lo + len(prefix)
    gutter = f"{span.line:>5} | "
    marker = " " * start + "^" + "~" * (width - 1)
    return f"{gutter}{shown}\n{' ' * (len(gutter) - 2)}| {marker}"
