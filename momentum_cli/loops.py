"""Parse, before the grammar: loops written in the text, expanded into plain lines.

In: a problem's text. Out: the text with every `for i in A..B:` block repeated once per
index (its body dedented to the `for` line, `i` replaced by the index) and every
`body b[A..B]: ...` written once per body, plus a map from each expanded line back to
the line, column and loop index it came from. The grammar and every later stage see
ordinary statements; spans are mapped back when the nodes are built (syntax.py).
"""
from __future__ import annotations

import functools
import re

from .diagnostics import ProblemError
from .source import Span

MAX_LINES = 2_000_000  # an expansion larger than this is refused (a typo in a bound)
_FOR = re.compile(r"^([ \t]*)for[ \t]+([A-Za-z_][A-Za-z_0-9]*)[ \t]+in[ \t]+(.+?)[ \t]*:"
                  r"[ \t]*(#.*)?$")
_BODY_RANGE = re.compile(r"^([ \t]*body[ \t]+[A-Za-z_][A-Za-z_0-9]*)\[([^\[\]]*?)\.\.([^\[\]]*?)\]")
_INT_EXPR = re.compile(r"^[A-Za-z_0-9+\-*/%() \t]+$")
_WORD = re.compile(r"[A-Za-z_][A-Za-z_0-9]*")
_MAYBE = re.compile(r"^[ \t]*for[ \t]|^[ \t]*body[ \t]+[A-Za-z_][A-Za-z_0-9]*\[[^\]]*\.\.",
                    re.M)
# a chunk of integer arithmetic in a state position: after `@`, `state`, `from`, a
# transition keyword or `->`, or before `->`
_STATE_AT = re.compile(r"(@|->|\b(?:state|from|impact|interval|energy|over|burn|gain|lose|"
                       r"instant|simulate)\b)([ \t]*)([A-Za-z_0-9+*/%()-]+?)(?=[ \t]*(?:->|:|,|"
                       r"[ \t]|\"|#|$))")
_BEFORE_ARROW = re.compile(r"([A-Za-z_0-9+*/%()]+(?:-(?!>)[A-Za-z_0-9+*/%()]+)*)(?=[ \t]*->)")
_BRACKET = re.compile(r"\[([^\[\]]*)\]")
_DIGIT = re.compile(r"[0-9]")
_LET_INT = re.compile(r"^let[ \t]+([A-Za-z_][A-Za-z_0-9]*)[ \t]*=[ \t]*([0-9]+)[ \t]*(?:#.*)?$",
                      re.M)
_STRING_OR_COMMENT = re.compile(r"\"[^\"\n]*\"|#.*")


class Origin:
    """Where an expanded line came from: its source line and text, and the loop indices."""

    __slots__ = ("line", "text", "where")

    def __init__(self, line: int, text: str, where: str | None):
        self.line, self.text, self.where = line, text, where


class Expansion:
    """The expanded text and, for each of its lines, the line it came from."""

    def __init__(self, text: str, origins: list[Origin], lines: list[str]):
        self.text = text
        self.origins = origins
        self._lines = lines
        self._blocks: dict[tuple, list] = {}
        self._by_line: dict[int, list] = {}
        self.chunks: list[tuple[int, int]] = [(0, len(lines))]  # runs of whole statements

    def span(self, span: Span | None) -> Span | None:
        """A span in the expanded text, as a span in the file (with the loop index)."""
        if span is None:
            return span
        return self.at(span.line, span.column, span.end_line, span.end_column)

    def at(self, line: int, column: int, end_line: int | None, end_column: int | None) -> Span:
        """The file's span of a range in the expanded text (the parser's nodes call this)."""
        if not 1 <= line <= len(self.origins):
            return Span(line, column, end_line, end_column)
        o = self.origins[line - 1]
        if o.where is None and o.text == self._lines[line - 1]:
            if end_line in (None, line):
                return Span(o.line, column, end_line and o.line, end_column)
            end = self.origins[end_line - 1] if end_line <= len(self.origins) else o
            return Span(o.line, column, end.line, end_column)
        col = self._column(line, column)
        end_col = self._column(line, end_column) if end_line == line and end_column else None
        return Span(o.line, col, o.line if end_col else None, end_col, o.where)

    def _column(self, line: int, column: int) -> int:
        """The column in the source line that column `column` of expanded line `line`
        was written from (the closest one, where the text was rewritten)."""
        blocks = self._by_line.get(line)
        if blocks is None:
            o = self.origins[line - 1]
            # the alignment depends on where the numbers are, not on their digits:
            # computed once per source line and number lengths (b[7] and b[8] align alike)
            key = (o.line, _DIGIT.sub("0", self._lines[line - 1]))
            blocks = self._blocks.get(key)
            if blocks is None:
                import difflib  # (here: only a loop's error is placed so)

                blocks = difflib.SequenceMatcher(None, _DIGIT.sub("0", o.text), key[1],
                                                 autojunk=False).get_matching_blocks()
                self._blocks[key] = blocks
            self._by_line[line] = blocks
        k = column - 1
        for a, b, n in blocks:
            if b <= k < b + n:
                return a + (k - b) + 1
            if b > k:
                return a + 1
        return len(self.origins[line - 1].text) + 1


SCAN_BYTES = 1 << 16  # a longer text is searched only around its `for`s and `..`s
_FOR_WORD = re.compile(r"for[ \t]")  # (literal first: the regex engine skips to each)
_DOTS = re.compile(r"\.\.")


def may_loop(text: str) -> bool:
    """Whether `_MAYBE` finds a loop in `text`. A long text is searched only in windows
    that end at a `for` or a `..` (a big file has few): any match of _MAYBE ends at one,
    and starts at the start of its line, or for a body range, at the start of the line of
    a `[` after the last `]` before its `..`. Searching every line start of the 10^4-impact
    cradle's 1.9 MB cost 13 ms; more windows than the text is long: the whole search."""
    if len(text) < SCAN_BYTES:
        return _MAYBE.search(text) is not None
    budget = len(text)
    for m in _FOR_WORD.finditer(text):
        i = m.start()
        a = text.rfind("\n", 0, i) + 1
        budget -= i + 4 - a
        if budget < 0:
            return _MAYBE.search(text) is not None
        if _MAYBE.search(text, a, i + 4):
            return True
    for m in _DOTS.finditer(text):
        i = m.start()
        a = text.rfind("\n", 0, text.rfind("]", 0, i) + 1) + 1
        budget -= i + 2 - a
        if budget < 0:
            return _MAYBE.search(text) is not None
        if _MAYBE.search(text, a, i + 2):
            return True
    return False


def expand(text: str) -> Expansion | None:
    """The text with its loops expanded, or None when it has none (the common case)."""
    if not may_loop(text):
        return None
    lines = text.split("\n")
    out: list[str] = []
    origins: list[Origin] = []
    repeats: list[tuple[int, int]] = []
    # `let N = 1000`: whole numbers a loop's bounds may name
    lets = {m.group(1): int(m.group(2)) for m in _LET_INT.finditer(text)}
    _block(lines, 0, len(lines), {}, "", out, origins, repeats, lets)
    exp = Expansion("\n".join(out), origins, out)
    exp.chunks = _chunks(repeats, out)
    return exp


def _chunks(repeats: list[tuple[int, int]], lines: list[str]) -> list[tuple[int, int]]:
    """The expanded lines cut into runs of whole top-level statements: each iteration of
    a top-level loop, and the lines between (the parser reuses the parse of a run that
    differs from an earlier one only in its digits). A cut never falls before a blank or
    comment line: those end the statement before it, as in one parse of the whole."""
    n = len(lines)
    cuts = {0, n}
    for a, b in repeats:
        cuts.update((a, b))
    moved = set()
    for c in cuts:
        while 0 < c < n and (not lines[c].strip() or lines[c].lstrip().startswith("#")):
            c += 1
        moved.add(c)
    cuts = sorted(moved)
    return [(a, b) for a, b in zip(cuts, cuts[1:]) if b > a]


def _indent(s: str) -> int:
    return len(s.expandtabs(8)) - len(s.expandtabs(8).lstrip())


def _block(lines, lo, hi, env, dedent: str, out, origins, repeats=None, lets=None) -> None:
    """Lines lo..hi of the file, with the loop indices `env`, each dedented by `dedent`."""
    k = lo
    while k < hi:
        raw = lines[k]
        m = _FOR.match(raw)
        if m:
            end = k + 1
            base = _indent(raw)
            while end < hi and (not lines[end].strip() or lines[end].lstrip().startswith("#")
                                or _indent(lines[end]) > base):
                end += 1
            while end > k + 1 and not lines[end - 1].strip():
                end -= 1  # trailing blank lines belong after the loop
            body = [x for x in lines[k + 1:end] if x.strip() and not x.lstrip().startswith("#")]
            if not body:
                raise ProblemError("syntax error: a `for` line needs an indented block of "
                                   "statements under it", Span(k + 1, 1), code="syntax")
            first = body[0]
            inner = first[:len(first) - len(first.lstrip())]
            var = m.group(2)
            a, b = _range(m.group(3), {**(lets or {}), **env}, k + 1, raw.index(m.group(3)) + 1)
            if (b - a + 1) * (end - k - 1) + len(out) > MAX_LINES:
                raise ProblemError(f"the loop over {var} = {a}..{b} would write more than "
                                   f"{MAX_LINES} lines", Span(k + 1, 1), code="too-large")
            outer = m.group(1)
            for i in range(a, b + 1):
                start = len(out)
                _block(lines, k + 1, end, {**env, var: i},
                       dedent + inner[len(outer):] if inner.startswith(outer) else dedent,
                       out, origins, None, lets)
                if repeats is not None and not outer:
                    repeats.append((start, len(out)))
            k = end
            continue
        if raw.lstrip().startswith("for ") or raw.lstrip().startswith("for\t"):
            raise ProblemError("syntax error: a loop is written `for NAME in A..B:` with its "
                               "statements indented under it", Span(k + 1, _indent(raw) + 1),
                               code="syntax", notes=["e.g. `for i in 1..999:`"])
        line = raw[len(dedent):] if dedent and raw.startswith(dedent) else raw.lstrip() \
            if dedent and raw.strip() else raw
        r = _BODY_RANGE.match(line)
        if r:
            a, b = _range(f"{r.group(2)}..{r.group(3)}", {**(lets or {}), **env}, k + 1,
                          len(r.group(1)) + 2)
            rest = line[r.end():]
            for i in range(a, b + 1):
                new = _substitute(f"{r.group(1)}[{i}]{rest}", env)
                if repeats is not None and not r.group(1)[0].isspace():
                    repeats.append((len(out), len(out) + 1))
                out.append(new)
                name = r.group(1).split()[-1]
                origins.append(Origin(k + 1, raw, _where(env, f"{name}[{i}]")))
            k += 1
            continue
        out.append(_substitute(line, env) if env else line)
        origins.append(Origin(k + 1, raw, _where(env, None)))
        k += 1


def _where(env: dict, body: str | None) -> str | None:
    parts = [f"{v} = {i}" for v, i in env.items()]
    if body:
        parts.append(body)
    if not parts:
        return None
    return "in loop iteration " + ", ".join(parts)


def _range(text: str, env: dict, line: int, column: int) -> tuple[int, int]:
    """`A..B` with A and B integer expressions of the enclosing loops' indices."""
    if ".." not in text:
        raise ProblemError(f"syntax error: a loop range is written `A..B` (got `{text}`)",
                           Span(line, column), code="syntax", notes=["e.g. `for i in 1..10:`"])
    lo, hi = text.split("..", 1)
    a, b = _int(lo, env), _int(hi, env)
    if a is None or b is None:
        bad = lo if a is None else hi
        raise ProblemError(f"syntax error: the loop bound `{bad.strip()}` is not a whole "
                           "number (bounds are integers, `let N = 1000` names, or integer "
                           "arithmetic of them and of an enclosing loop's index)",
                           Span(line, column), code="syntax")
    if b < a:
        raise ProblemError(f"the loop range {a}..{b} is empty", Span(line, column),
                           code="syntax", notes=["the first index is written first: `1..10`"])
    return a, b


def _int(expr: str, env: dict) -> int | None:
    """An integer expression of the loop indices (+ - * / % and parentheses), or None."""
    code = _compiled(expr.strip())
    if code is None or not code[1] <= env.keys():
        return None
    try:
        v = eval(code[0], {"__builtins__": {}}, env)
    except Exception:
        return None
    if isinstance(v, float):
        if not v.is_integer():
            return None
        v = int(v)
    return v if isinstance(v, int) else None


@functools.lru_cache(maxsize=4096)
def _compiled(expr: str):
    """(code, names) of an integer expression, compiled once for every index (or None)."""
    if not expr or not _INT_EXPR.match(expr) or "**" in expr:
        return None  # no powers: a bound must not take forever to compute
    try:
        return compile(expr, "<loop>", "eval"), frozenset(_WORD.findall(expr))
    except SyntaxError:
        return None


def _substitute(line: str, env: dict) -> str:
    """A loop body line for one index: integer arithmetic of the indices in brackets and
    in state positions becomes its value (`b[i+1]`, `impact i -> i+1`), and the index
    elsewhere becomes its number (`0.1*i m/s`). Strings and comments are left alone."""
    if not env:
        return line
    pieces = []
    last = 0
    for m in _STRING_OR_COMMENT.finditer(line):
        pieces.append((line[last:m.start()], True))
        pieces.append((m.group(0), False))
        last = m.end()
    pieces.append((line[last:], True))
    return "".join(_code(p, env) if code else p for p, code in pieces)


def _code(s: str, env: dict) -> str:
    def value(expr: str) -> str | None:
        if not set(_WORD.findall(expr)) & set(env):
            return None
        v = _int(expr, env)
        return None if v is None else str(v)

    def bracket(m):
        v = value(m.group(1))
        return f"[{v}]" if v is not None else m.group(0)

    s = _BRACKET.sub(bracket, s)

    def state(m):
        v = value(m.group(3))
        return m.group(1) + m.group(2) + v if v is not None else m.group(0)

    s = _STATE_AT.sub(state, s)
    s = _BEFORE_ARROW.sub(lambda m: value(m.group(1)) or m.group(0), s)
    return _WORD.sub(lambda m: str(env[m.group(0)]) if m.group(0) in env else m.group(0), s)
