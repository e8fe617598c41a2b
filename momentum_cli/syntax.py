"""Parse: problem text -> frozen syntax nodes that keep their line:column.

The grammar is `grammar/momentum.lark` (shipped inside the package). Lark types stop
here: nodes hold our `Span`, never lark's `Token` or `Meta`. The LALR parser is built
once and cached on disk, outside the package; good files are parsed without importing
lark: the common statement forms a line at a time (syntax_lines.py), the others from
the parser's tables (syntax_run.py); whatever they refuse (errors) by lark itself.
"""
from __future__ import annotations

import functools
import os

from .cache_files import cache_dir as _cache_dir
from .cache_files import read as _read_cache
from .cache_files import write as _write_cache
from .diagnostics import ProblemError
from .records import record
from .source import Source, Span

MAX_BYTES = 20_000_000  # larger problem files are refused with a clear error
MAX_DEPTH = 200  # expression nesting bound (keeps recursion far from Python's limit)


# ---- expression nodes ---------------------------------------------------------------
@record(frozen=True)
class Num:
    span: Span
    value: float
    unit: str | None = None
    unit_span: Span | None = None


@record(frozen=True)
class Ref:
    """A name, maybe indexed, with a member and states: `rod.omega@3`, `J_n[A]@2->3`."""

    span: Span
    name: str
    index: str | None = None
    member: str | None = None
    at: tuple[str, ...] = ()
    about: object = None  # a PointRef: `H[{rod, ball}]@2 about O`

    @property
    def text(self) -> str:
        """One word (answers print as `NAME = VALUE UNIT`): `H[{rod, ball}]@2 about O` is
        `H_O[{rod,ball}]@2`."""
        s = self.name if self.about is None else f"{self.name}_{self.about.text}"
        if self.index:
            s += f"[{self.index}]"
        if self.member:
            s += f".{self.member}"
        if self.at:
            s += "@" + "->".join(self.at)
        return s

    @property
    def bodies(self) -> tuple[str, ...]:
        """The bodies an index names: `T[rod]` -> (rod,), `p[{A, B}]` -> (A, B)."""
        if not self.index:
            return ()
        return tuple(n.strip() for n in self.index.strip("{}").split(","))


@record(frozen=True)
class BinOp:
    span: Span
    op: str  # + - * / ^
    left: object
    right: object


@record(frozen=True)
class Neg:
    span: Span
    arg: object


@record(frozen=True)
class Call:
    span: Span
    fn: str
    args: tuple
    fn_span: Span


@record(frozen=True)
class VecLit:
    span: Span
    x: object
    y: object


@record(frozen=True)
class Mag:
    span: Span
    arg: object


# ---- statements -------------------------------------------------------------------------
@record(frozen=True)
class Problem:
    span: Span
    title: str


@record(frozen=True)
class Gravity:
    span: Span
    magnitude: object
    direction: str  # down | up | left | right | plane | vector
    vector: object = None


@record(frozen=True)
class Let:
    span: Span
    name: str
    value: object


@record(frozen=True)
class UnknownDecl:
    span: Span
    name: str
    unit: str | None
    unit_span: Span | None


@record(frozen=True)
class Arg:
    span: Span
    name: str
    value: object


@record(frozen=True)
class Shape:
    span: Span
    kind: str
    args: tuple[Arg, ...]
    at: object = None  # offset in the composite frame (composite parts)
    rotated: object = None


@record(frozen=True)
class BodyDecl:
    span: Span
    name: str
    shapes: tuple[Shape, ...]
    composite: bool


@record(frozen=True)
class PointRef:
    span: Span
    name: str
    member: str | None = None  # `rod.A`, `rod.center`
    end: str | None = None  # "+" or "-" for `rod.end(+)`

    @property
    def text(self) -> str:
        if self.end:
            return f"{self.name}.end({self.end})"
        return f"{self.name}.{self.member}" if self.member else self.name


@record(frozen=True)
class PointDecl:
    span: Span
    name: str
    body: str | None  # `point A = rod at (...)`
    offset: object = None
    alias: PointRef | None = None  # `point A = rod.end(-)`


@record(frozen=True)
class SurfaceDecl:
    span: Span
    name: str
    normal: object
    at: object


@record(frozen=True)
class Joint:
    """`pin`, `weld`, `link` (a two-force strut) and `spring` between two points."""

    span: Span
    kind: str
    label: str | None
    a: PointRef
    b: PointRef
    at: object = None  # pin to ground: where the ground point is
    along: object = None  # link: direction of the strut
    stiffness: object = None  # spring
    length: object = None  # spring free length
    from_state: str | None = None  # holds only from this state on
    from_span: Span | None = None


@record(frozen=True)
class Given:
    span: Span
    body: str
    qty: str
    qty_span: Span
    value: object
    relation: str = "="  # "=" given, "<" / ">" branch hints


@record(frozen=True)
class AtRest:
    span: Span
    body: str


@record(frozen=True)
class RollsIn:
    span: Span
    body: str
    surface: str


@record(frozen=True)
class StateDecl:
    span: Span
    id: str
    label: str | None
    items: tuple


@record(frozen=True)
class Contact:
    span: Span
    label: str | None
    a: PointRef
    b: PointRef | None  # None: the ground
    normal: object
    props: tuple  # of Prop


IMPACT_LAWS = ("newton", "poisson", "energetic")  # how a contact's restitution ends an impact


@record(frozen=True)
class Prop:
    span: Span
    kind: str  # restitution | restitution? | smooth | rough | friction | slip
    value: object = None
    law: str | None = None  # restitution: one of IMPACT_LAWS


@record(frozen=True)
class Clause:
    """A non-contact clause in a transition: stops, rolls, force, moment, duration..."""

    span: Span
    kind: str
    names: tuple[str, ...] = ()
    value: object = None
    point: PointRef | None = None


@record(frozen=True)
class Transition:
    span: Span
    kind: str  # impact | interval | energy
    before: str
    after: str
    clauses: tuple
    before_span: Span
    after_span: Span
    groups: tuple = ()  # `energy 2 -> 3 of {rod}, {ball}`: tuples of body names


@record(frozen=True)
class ConserveMomentum:
    span: Span
    axis: object  # "x" | "y" | vector expression
    bodies: tuple[str, ...]
    before: str
    after: str


@record(frozen=True)
class ConserveAngular:
    span: Span
    bodies: tuple[str, ...]
    about: PointRef
    before: str
    after: str


@record(frozen=True)
class RestitutionLaw:
    span: Span
    value: object
    a: PointRef
    b: PointRef | None
    along: object
    before: str
    after: str


@record(frozen=True)
class UserEquation:
    span: Span
    left: object
    right: object


@record(frozen=True)
class FindItem:
    span: Span
    name: str | None
    expr: object
    unit: str | None
    unit_span: Span | None


@record(frozen=True)
class Find:
    span: Span
    items: tuple[FindItem, ...]


@record(frozen=True)
class Flow:
    """One inflow or outflow of a control volume (or a known force on it)."""

    span: Span
    kind: str  # inflow | outflow | force
    rate: object = None
    velocity: object = None
    relative: bool = False
    at: object = None


@record(frozen=True)
class SteadyDecl:
    """A control volume: steady (`steady`), or at one instant of unsteady flow
    (`instant`, with its contents' mass, velocity and acceleration)."""

    span: Span
    name: str
    flows: tuple
    supports: tuple[str, ...]
    moving: object = None
    instant: bool = False
    mass: object = None
    velocity: object = None
    acceleration: object = None


@record(frozen=True)
class BurnDecl:
    span: Span
    body: str
    before: str
    after: str
    exhaust: object
    direction: object
    rate: object
    burned: object
    duration: object
    clause_spans: tuple = ()


@record(frozen=True)
class Until:
    """A stop condition of a simulation: `until t = 5 s`, `until rod.omega = 0`,
    `until apex`, `until 3 impacts` (the last two have no right-hand side)."""

    span: Span
    left: object
    right: object = None


@record(frozen=True)
class SimulateDecl:
    """`simulate from 1:` with its stop conditions, watched contacts and effects."""

    span: Span
    start: str
    start_span: Span
    clauses: tuple  # Until | Contact | Clause (force, moment, bearing-torque) | Joint (damper)


@record(frozen=True)
class GainDecl:
    """A particle gaining (`gain`) or losing (`lose`) mass over an interval."""

    span: Span
    body: str
    before: str
    after: str
    is_loss: bool
    rate: object = None
    velocity: object = None
    is_relative: bool = False
    force: object = None
    duration: object = None


@record(frozen=True)
class Expect:
    """`expect QUANTITY = VALUE [± TOL | within P %]` or `expect error CODE`."""
    span: Span
    quantity: object = None  # the expression expected (None for `expect error`)
    value: object = None  # the expected value's expression
    tolerance: object = None  # `± TOL`: an expression; None: from the digits written
    percent: object = None  # `within P %`: an expression (dimensionless)
    error: str | None = None  # `expect error CODE`: the diagnostic code


@record(frozen=True)
class Document:
    source: Source
    statements: tuple
    # True when the text parsed names no US customary or degree unit (unit_system's
    # may_name: a superset test on the text), so the file's units are SI without degrees
    # whatever its statements hold; False (walk the statements) for a document made
    # otherwise (`--set`, sweeps: their values' units are not in the text)
    si_text: bool = False


# ---- the parser ---------------------------------------------------------------------------
def grammar_text() -> str:
    """The grammar, from inside the installed package or from the repository (a plain
    file beside this module is read directly: importlib.resources costs start-up)."""
    here = os.path.dirname(os.path.realpath(__file__))
    for path in (os.path.join(here, "momentum.lark"),
                 os.path.join(os.path.dirname(here), "grammar", "momentum.lark")):
        if os.path.isfile(path):
            with open(path, encoding="utf-8") as fh:
                return fh.read()
    try:
        from importlib.resources import files

        res = files("momentum_cli").joinpath("momentum.lark")
        if res.is_file():
            return res.read_text(encoding="utf-8")
    except (ModuleNotFoundError, FileNotFoundError, OSError):
        pass
    raise FileNotFoundError("momentum.lark: the grammar is missing from the installation")


def _cache_key(text: str) -> str:
    import hashlib  # here: its import (OpenSSL) costs a one-shot run that never needs lark
    import sys

    import lark

    return hashlib.sha256((text + lark.__version__ + sys.version).encode()).hexdigest()[:16]


@functools.lru_cache(maxsize=1)
def parser():
    """The LALR parser, built once and cached on disk (lark's `cache=`)."""
    from lark import Lark
    from lark.indenter import Indenter

    class _Indenter(Indenter):
        NL_type = "_NL"
        OPEN_PAREN_types = ["LPAR", "LSQB", "LBRACE"]
        CLOSE_PAREN_types = ["RPAR", "RSQB", "RBRACE"]
        INDENT_type = "_INDENT"
        DEDENT_type = "_DEDENT"
        tab_len = 8

        def handle_NL(self, token):
            from lark.indenter import DedentError

            levels = " or ".join(str(n) for n in self.indent_level)
            try:
                yield from Indenter.handle_NL(self, token)
            except DedentError:
                # the NL token ends where the badly indented line's text starts
                raise ProblemError("syntax error: the indentation of this line matches no "
                                   f"enclosing block (indent it by {levels} columns)",
                                   Span(token.end_line, token.end_column), code="syntax") \
                    from None

    text = grammar_text()
    kw = dict(parser="lalr", postlex=_Indenter(), propagate_positions=True,
              maybe_placeholders=False)
    folder = _cache_dir()
    path = os.path.join(folder, f"grammar-{_cache_key(text)}.lark-cache") if folder else None
    data = _read_cache(path) if path else None
    if data:
        import io

        try:
            inst = Lark.__new__(Lark)
            return inst._load(io.BytesIO(data), postlex=kw["postlex"],
                              propagate_positions=True)
        except Exception:  # a stale or damaged cache must not stop the user: rebuild
            pass
    built = Lark(text, **kw)
    if path:
        import io

        buf = io.BytesIO()
        try:
            built.save(buf, exclude_options=("postlex",))
        except Exception:
            return built
        _write_cache(path, buf.getvalue())
    return built


@functools.lru_cache(maxsize=1)
def _fast_parser():
    """syntax_run's parser for this grammar, its tables read from the cache (else built
    from lark's parser and cached); None when it does not reproduce this grammar, there
    is no cache folder, or $MOMENTUM_LARK_ONLY is set (the tests compare the two): then
    lark parses everything."""
    if os.environ.get("MOMENTUM_LARK_ONLY"):
        return None
    from . import syntax_run, syntax_tables

    text = grammar_text()
    folder = _cache_dir()
    path = syntax_tables.cache_path(folder, text)
    if path is None:
        return None  # nowhere to keep them: building them (0.1 s) would not pay off
    data = _read_cache(path)
    found, tables = syntax_tables.load(data, text) if data else (False, None)
    if not found:
        p = parser()
        tables = syntax_tables.build(p, p.options.postlex)
        _write_cache(path, syntax_tables.dump(tables, text))
    if tables is None:
        return None
    try:
        run = syntax_run.Parser(tables, Rules(), MAX_DEPTH)
    except Exception:  # tables of another shape (never written so): lark parses
        return None
    return run if run.ok else None


def parse(source: Source) -> Document:
    """Parse a problem file into a `Document`, or raise `ProblemError` at a location."""
    text = source.text
    nul = text.find("\x00")
    if nul >= 0:  # before the size check: a large binary file is a binary file
        raise ProblemError("not a text file (it contains NUL bytes)", _span_at(text, nul),
                           code="binary", caret=False,
                           notes=["a problem file is UTF-8 text"])
    if len(text) > MAX_BYTES:
        raise ProblemError(f"file too large ({len(text)} characters; the limit is {MAX_BYTES})",
                           code="too-large")
    if not text.strip():
        raise ProblemError("empty problem file: nothing to solve", Span(1, 1), code="empty",
                           notes=["a problem needs at least a body, a state and a `find` line"])
    _check_depth(source)
    loops = None
    if _may_loop(text):  # else loops.expand finds none (and is not even imported)
        from .loops import expand

        loops = expand(text)  # `for` blocks and `body b[1..N]` written out (None: no loops)
    return _parse(source, Source(source.name, loops.text) if loops else source, loops)


def _may_loop(text: str) -> bool:
    """False when the text has no line starting `for ` and no `..` (so no loop for
    loops.expand, whose regex looks for exactly those)."""
    if ".." in text:
        return True
    i = text.find("for")
    while i >= 0:
        j = i
        while j > 0 and text[j - 1] in " \t":
            j -= 1
        if (j == 0 or text[j - 1] == "\n") and text[i + 3:i + 4] in (" ", "\t"):
            return True
        i = text.find("for", i + 3)
    return False


_DIGITS = None
_LINE_KEYS = ("line", "end_line", "container_line", "container_end_line")
_POS_KEYS = ("start_pos", "end_pos", "container_start_pos", "container_end_pos")


def _parse_runs(loops):
    """The parse tree of expanded loops, parsing each run of statements whose text differs
    from an earlier run only in its digits once (the 999 iterations of `impact i -> i+1`
    are a few parses, not 999), and moving copies of it into place. None (parse the whole
    text instead) when a run does not parse on its own: the whole parse locates the error."""
    import re

    from lark import Token, Tree
    from lark.exceptions import LarkError
    from lark.tree import Meta

    global _DIGITS
    _DIGITS = _DIGITS or re.compile(r"[0-9]")
    lines, p = loops.text.split("\n"), parser()
    starts, pos = [], 0
    for x in lines:
        starts.append(pos)
        pos += len(x) + 1
    cache: dict[str, object] = {}

    def moved(node, text, dl, dc):
        if isinstance(node, Token):
            return Token(node.type, text[node.start_pos:node.end_pos], node.start_pos + dc,
                         node.line + dl, node.column, node.end_line + dl, node.end_column,
                         node.end_pos + dc)
        meta = None
        if node._meta is not None:
            meta = Meta()
            d = meta.__dict__
            d.update(node._meta.__dict__)
            for k in _LINE_KEYS:
                if k in d:
                    d[k] += dl
            for k in _POS_KEYS:
                if k in d:
                    d[k] += dc
        return Tree(node.data, [moved(c, text, dl, dc) for c in node.children], meta)

    children = []
    try:
        for a, b in loops.chunks:
            text = "\n".join(lines[a:b])
            if b < len(lines) or not text.endswith("\n"):
                text += "\n"  # as the whole text reads (one newline at its end)
            key = _DIGITS.sub("0", text)
            tpl = cache.get(key)
            if tpl is None:
                tpl = cache[key] = p.parse(text)
                _same_tokens(tpl, text)
            children.extend(moved(c, text, a, starts[a]) for c in tpl.children)
    except (LarkError, ProblemError, ValueError):
        return None
    return Tree("start", children)


def _same_tokens(tree, text: str) -> None:
    """Every token is the text at its place (what moving a copy relies on)."""
    from lark import Token

    for t in tree.scan_values(lambda v: isinstance(v, Token)):
        if text[t.start_pos:t.end_pos] != t.value:
            raise ValueError(t)


def _in_file(exc: ProblemError, loops) -> ProblemError:
    """An error the grammar found in the expanded text, located in the file."""
    from .diagnostics import Diagnostic

    if loops is None:
        return exc
    return ProblemError.many([Diagnostic(d.severity, d.code, d.message, loops.span(d.span),
                                         d.notes, d.caret) if d.span else d
                              for d in exc.diagnostics])


FAST_BYTES = 20_000  # files this large parse each repeated statement shape once
# syntax_run parses every file it takes, big ones too: on a big loop-free file lark plus
# syntax_fast's copies cost ~25 % less CPU but hold the whole lark tree at once (measured
# on the 10^5-ball chain, 12 MB: 13.4 s and 2.3 GB resident, against 16.8 s and 0.3 GB)


def _fast_tree(text: str):
    """The tree of a big file from one parse per repeated shape (`syntax_fast`), or
    None; any error there means: parse the whole text, which reports it exactly."""
    from lark.exceptions import LarkError

    from .syntax_fast import fast_tree

    try:
        return fast_tree(text, parser().parse)
    except (LarkError, ProblemError, ValueError, RecursionError):
        return None


def _parse(source: Source, expanded: Source, loops) -> Document:
    """Parse `expanded` (the file, or its loops written out) into the file's Document;
    the nodes' spans point into the file. A big file is parsed with the cyclic garbage
    collector paused: its 10^5 new nodes hold no cycles, and the collector's repeated
    passes over them cost more than the parse (restored on every exit)."""
    import gc

    if len(expanded.text) < FAST_BYTES or not gc.isenabled():
        return _parse_nodes(source, expanded, loops)
    gc.disable()
    try:
        return _parse_nodes(source, expanded, loops)
    finally:
        gc.enable()


LINES_BYTES = 32_000  # characters parsed in this process before syntax_lines is used:
# its regexes and record makers cost ~30 ms to set up, and it saves ~1 ms per 1,000
# characters (one small file alone is parsed faster by syntax_run)
_READ = [0]
# a hook: while run.solve_many solves a batch, statement_memo.parse(text, parse, loops,
# by_lines)
# (the nodes of a text, or of a small file's loops written out, parsed statement by
# statement through a table, or None)
STATEMENTS: list = [None]


def _parse_nodes(source: Source, expanded: Source, loops) -> Document:
    """`_parse` itself: syntax_run where it can (no lark import once its tables are
    cached), else lark's parse and the transformer (which also report every error)."""
    text = expanded.text
    fast = _fast_parser()
    if fast is not None:
        from .syntax_run import Fallback

        _SPANS[0] = loops  # the nodes' spans point into the file, not the expanded text
        whole = text if text.endswith("\n") else text + "\n"
        nodes = None
        deferred = False  # syntax_lines kept lines as their text
        _READ[0] += len(whole)
        hook = STATEMENTS[0] if loops is None or len(text) < FAST_BYTES else None
        try:
            if hook is not None:  # a batch: each distinct statement parsed once
                nodes = hook(text, fast.parse, loops, True)
            elif loops is None and _READ[0] >= LINES_BYTES:  # the common statement forms
                import sys  # a line at a time, the rest by syntax_run

                from .syntax_lines import DEFERRED
                from .syntax_lines import parse as by_lines

                nodes = by_lines(whole, fast.parse, sys.modules[__name__], True)
                deferred = nodes is not None and DEFERRED[0]
        except Exception:  # Fallback (a bracket open across lines, an error): parse whole
            nodes = None
        try:
            if nodes is None:
                nodes = fast.parse(whole)
        except Fallback:
            nodes = None
        finally:
            _SPANS[0] = None
        if nodes is not None:
            si = getattr(nodes, "si_text", None)  # the batch's table has it per statement
            statements = tuple([s if type(s) is not Expect else _plus_minus(s, source.text)
                                for s in nodes])
            si = _si_text(text) if si is None else si
            if deferred:  # lines kept as their text: their nodes are made when read
                from .statement_deferred import document

                return document(Document, source, statements, si)
            return Document(source, statements, si)
    from lark.exceptions import LarkError, UnexpectedInput, VisitError

    try:
        tree = _parse_runs(loops) if loops is not None else None
        if tree is None and loops is None and len(text) >= FAST_BYTES:
            tree = _fast_tree(text if text.endswith("\n") else text + "\n")
        if tree is None:
            tree = parser().parse(text if text.endswith("\n") else text + "\n")
    except UnexpectedInput as exc:
        raise _in_file(_syntax_error(expanded, exc), loops) from None
    except ProblemError as exc:  # the indenter's
        raise _in_file(exc, loops) from None
    except LarkError as exc:  # anything else lark reports is still the file's syntax
        raise ProblemError(f"syntax error: {_first_line(exc)}", Span(1, 1), code="syntax") \
            from None
    _SPANS[0] = loops
    try:
        statements = _walk(tree)
    except Exception as exc:
        # a tree too deep is refused before any node is built (_check_tree_depth, on
        # this error path only: the walk measures the depth as it goes)
        _check_tree_depth(tree)
        if isinstance(exc, ProblemError):
            raise
        try:  # as lark's transformer says it (its VisitError)
            statements = _ToNodes(len(text) >= FAST_BYTES).transform(tree).children
        except VisitError as exc:
            if isinstance(exc.orig_exc, ProblemError):
                raise exc.orig_exc from None
            raise
    finally:
        _SPANS[0] = None
    # `expect V +- T` is read from the text the spans point into: the file's
    return Document(source, tuple(_plus_minus(s, source.text) for s in statements),
                    _si_text(text))


def _si_text(text: str) -> bool:
    """Document.si_text of a document parsed from `text` (the file, loops written out)."""
    from .unit_system import may_name

    return not may_name(text)


class _TooDeep(Exception):
    """The walk went deeper than _check_tree_depth allows (which then says where)."""


def _walk(tree) -> list:
    """The start tree's children as nodes: lark's transformer with syntax.Rules (what
    _make_transformer makes), without its per-node dispatch; _TooDeep past the depth
    _check_tree_depth allows (so the recursion stays bounded)."""
    from lark import Tree

    rules = Rules()
    limit = MAX_DEPTH + 8

    def walk(node, depth):
        if depth > limit:
            raise _TooDeep
        ch = [walk(c, depth + 1) if isinstance(c, Tree) else c for c in node.children]
        return getattr(rules, node.data)(node.meta, ch)

    return [walk(c, 1) if isinstance(c, Tree) else c for c in tree.children]


def _plus_minus(stmt, text: str):
    """`expect Q = V +- T` parses as the sum `V + (-T)`: split it into value and tolerance
    when the `+` and `-` touch."""
    if not (isinstance(stmt, Expect) and stmt.value is not None and stmt.tolerance is None
            and stmt.percent is None and isinstance(stmt.value, BinOp)
            and stmt.value.op == "+"):
        return stmt
    right = stmt.value.right
    lead, path = right, []
    while isinstance(lead, BinOp):
        path.append(lead)
        lead = lead.left
    if not isinstance(lead, Neg):
        return stmt
    start = _offset(text, lead.span.line, lead.span.column)
    if start < 1 or text[start - 1] != "+" or text[start] != "-":
        return stmt
    tol = lead.arg
    for node in reversed(path):
        tol = BinOp(node.span, node.op, tol, node.right)
    return Expect(stmt.span, stmt.quantity, stmt.value.left, tol, None, None)


def _offset(text: str, line: int, column: int) -> int:
    """The character offset of a 1-based line:column."""
    pos = 0
    for _ in range(line - 1):
        pos = text.index("\n", pos) + 1
    return pos + column - 1


def _span_at(text: str, index: int) -> Span:
    """The 1-based line:column of a character offset (lark counts lines by '\\n')."""
    line = text.count("\n", 0, index) + 1
    return Span(line, index - text.rfind("\n", 0, index))


def _check_tree_depth(tree) -> None:
    """Refuse parse trees deeper than MAX_DEPTH, iteratively, before anything recurses.

    `1 + 1 + ... + 1` with thousands of terms has no brackets but is as deep as it
    is long; transforming, evaluating and printing it recurse once per level.
    """
    from lark import Tree

    stack = [(tree, 0, None)]  # node, depth, the outermost expression around it
    while stack:
        node, depth, top = stack.pop()
        if top is None and node.data in _EXPRESSION_RULES:
            top = node
        if depth > MAX_DEPTH + 8:  # a few levels of statement structure above expressions
            meta = (top or node).meta
            span = None if meta.empty else Span(meta.line, meta.column, meta.end_line,
                                                 meta.end_column)
            raise ProblemError(f"expression too long or nested too deeply (more than "
                               f"{MAX_DEPTH} operations in one expression)", span,
                               code="too-deep", notes=["split it into parts with `let`"])
        stack.extend((c, depth + 1, top) for c in node.children if isinstance(c, Tree))


_EXPRESSION_RULES = {"add", "sub", "mul", "div", "pow", "neg", "unary", "call", "vec_lit",
                     "magnitude"}


def _first_line(exc: Exception) -> str:
    return (str(exc).strip().splitlines() or ["invalid input"])[0]


_BRACKETS_ONLY = {c: None for c in range(128) if chr(c) not in "()[]{}"}
_BRACKETS_ONLY.update({ord("["): "(", ord("{"): "(", ord("]"): ")", ord("}"): ")"})


def _check_depth(source: Source) -> None:
    text = source.text
    if text.count("(") + text.count("[") + text.count("{") <= MAX_DEPTH:
        return  # too few brackets to nest that deep (the scan below costs per character)
    import re

    # each pass drops the innermost pairs: a text whose brackets all pair up within
    # MAX_DEPTH passes nests no deeper (the scan below then finds nothing)
    only = text.translate(_BRACKETS_ONLY)  # (other characters than ASCII stay: exact scan)
    for _ in range(MAX_DEPTH):
        if not only:
            return
        shorter = only.replace("()", "")
        if len(shorter) == len(only):
            break  # unpaired brackets: the exact scan decides
        only = shorter

    depth = best = 0
    for m in re.finditer(r"[()\[\]{}]", text):  # only the brackets, not every character
        i, ch = m.start(), m.group()
        if ch in "([{":
            depth += 1
            if depth > best:
                best = depth
                if best > MAX_DEPTH:
                    line = source.text.count("\n", 0, i) + 1
                    col = i - source.text.rfind("\n", 0, i)
                    raise ProblemError(f"expression nested too deeply (more than {MAX_DEPTH} "
                                       "brackets)", Span(line, col), code="too-deep")
        elif ch in ")]}":
            depth = max(depth - 1, 0)


_READABLE = {
    "_NL": "end of line", "_INDENT": "an indented block", "_DEDENT": "end of block",
    "NAME": "a name", "NUMBER": "a number", "STATE_ID": "a state number", "UNIT": "a unit",
    "STRING": "a quoted string", "LPAR": "'('", "RPAR": "')'", "COMMA": "','",
    "COLON": "':'", "EQUAL": "'='", "SIGN": "'+' or '-'", "MORETHAN": "'>'", "LESSTHAN": "'<'",
    "LBRACE": "'{'", "RBRACE": "'}'", "LSQB": "'['", "RSQB": "']'", "AT": "'@'", "DOT": "'.'",
    "STAR": "'*'", "SLASH": "'/'", "PLUS": "'+'", "MINUS": "'-'", "QMARK": "'?'",
    "VBAR": "'|'", "CIRCUMFLEX": "'^'", "__ANON_0": "'->'", "$END": "end of file",
}


def _readable(name: str) -> str:
    if name in _READABLE:
        return _READABLE[name]
    if name.startswith("__ANON"):
        return "'->'" if name else name
    return f"'{name.lower()}'"


def _syntax_error(source: Source, exc) -> ProblemError:
    from lark.exceptions import UnexpectedCharacters, UnexpectedEOF, UnexpectedToken

    expected = sorted(getattr(exc, "expected", None) or getattr(exc, "allowed", None) or [])
    words = sorted({_readable(e) for e in expected})
    hint = ""
    if words:
        shown = ", ".join(words[:8]) + (", ..." if len(words) > 8 else "")
        hint = f"; expected {shown}"
    if isinstance(exc, UnexpectedEOF) or getattr(getattr(exc, "token", None), "type", "") == "$END":
        # just past the last character that is not white space
        text = source.text.rstrip()
        return ProblemError("syntax error: unexpected end of file" + hint,
                            _span_at(text, len(text)), code="syntax")
    line, col = getattr(exc, "line", 1), getattr(exc, "column", 1)
    if line is None or line < 1 or col is None or col < 1:
        line, col = 1, 1
    if isinstance(exc, UnexpectedCharacters):
        ch = source.line_text(line)[col - 1 : col]
        return ProblemError(f"syntax error: unexpected character {_show_char(ch)}" + hint,
                            Span(line, col), code="syntax")
    if isinstance(exc, UnexpectedToken):
        tok = exc.token
        if tok.type == "_INDENT":
            # the indent token sits where the previous line ended
            return ProblemError("syntax error: unexpected indented block after this line; is a "
                                "':' missing here?", Span(line, col), code="syntax")
        opener = _block_opener(source, line, col)
        if opener is not None:
            return ProblemError(f"syntax error: expected an indented block after the ':' on "
                                f"line {opener}", Span(line, col, line, col + len(str(tok))),
                                code="syntax")
        if tok.type == "_NL":
            what = "end of line"
        elif tok.type == "_DEDENT":
            what = "end of the indented block"
        else:
            what = f"'{tok}'"
        end = Span(line, col, line, col + len(str(tok))) if tok.type not in (
            "_NL", "_INDENT", "_DEDENT") else Span(line, col)
        keyword = _keyword_hint(str(tok), words)
        return ProblemError(f"syntax error: unexpected {what}" + (keyword or hint), end,
                            code="syntax")
    return ProblemError(f"syntax error: {_first_line(exc)}", Span(line, col), code="syntax")


def _keyword_hint(word: str, expected_words) -> str:
    """"; did you mean 'impact'?" when a misspelt word is close to a keyword expected here."""
    from .diagnostics import did_you_mean

    keywords = [w.strip("'") for w in expected_words if w.startswith("'") and
                w.strip("'").isalpha()]
    return did_you_mean(word, keywords) if word.isidentifier() else ""


def _block_opener(source: Source, line: int, col: int) -> int | None:
    """The line before `line` if it ends with ':' and `line` starts unindented at `col`."""
    if col != 1 or line < 2:
        return None
    for n in range(line - 1, 0, -1):
        prev = source.line_text(n).split("#", 1)[0].rstrip()
        if prev:
            return n if prev.endswith(":") else None
    return None


def _show_char(ch: str) -> str:
    """A character for a message: quoted if printable, else its code point."""
    import unicodedata

    if not ch:
        return "(end of line)"
    if ch.isprintable() and not ch.isspace():
        return f"'{ch}'"
    name = unicodedata.name(ch, "") or {"\r": "CARRIAGE RETURN", "\x0b": "LINE TABULATION",
                                        "\x1b": "ESCAPE"}.get(ch, "control character")
    return f"U+{ord(ch):04X} ({name.lower()})"


# ---- tree -> nodes ------------------------------------------------------------------------
_SPANS: list = [None]  # while building nodes from expanded loops: the map to the file


def _span(meta) -> Span:
    if _SPANS[0] is not None:
        return _SPANS[0].at(meta.line, meta.column, meta.end_line, meta.end_column)
    return Span(meta.line, meta.column, meta.end_line, meta.end_column)


def _tspan(tok) -> Span:
    if _SPANS[0] is not None:
        return _SPANS[0].at(tok.line, tok.column, tok.end_line, tok.end_column)
    return Span(tok.line, tok.column, tok.end_line, tok.end_column)


IN_UNIT = "in:"  # Num.unit of `2 in mm` (a bare 2 whose find item is shown in mm)


def _split_in_unit(expr):
    """`L/2 in mm` parses as L/(2 "in mm"): (the expression with a bare 2, "mm", its
    span), or None when the expression does not end that way."""
    if isinstance(expr, Num):
        if expr.unit and expr.unit.startswith(IN_UNIT):
            return Num(expr.span, expr.value), expr.unit[len(IN_UNIT):], expr.unit_span
        return None
    if isinstance(expr, BinOp):
        r = _split_in_unit(expr.right)
        return r and (BinOp(expr.span, expr.op, expr.left, r[0]), r[1], r[2])
    if isinstance(expr, Neg):
        r = _split_in_unit(expr.arg)
        return r and (Neg(expr.span, r[0]), r[1], r[2])
    return None


class Rules:
    """The rule callbacks: (meta, children) -> node for each rule and alias of the
    grammar. Lark's transformer (_make_transformer) calls them on its tree; syntax_run
    calls them as it reduces (no lark import, no tree)."""

    # -- expressions
    def quantity(self, meta, ch):
        num = ch[0]
        try:
            value = float(num)
        except ValueError:
            raise ProblemError(f"cannot read number '{num}'", _tspan(num), code="syntax")
        if len(ch) > 1:
            u = ch[1]
            return Num(_span(meta), value, str(u[0]), u[1])
        return Num(_span(meta), value)

    def unit(self, meta, ch):
        return (str(ch[0]), _tspan(ch[0]))

    def quantity_in(self, meta, ch):
        value = float(ch[0])
        return Num(_span(meta), value, IN_UNIT + str(ch[1]), _tspan(ch[1]))

    def unit_inch(self, meta, ch):
        return ("in", _span(meta))

    def ref(self, meta, ch):
        name = str(ch[0])
        index = member = None
        at: tuple[str, ...] = ()
        for c in ch[1:]:
            kind, val = c
            if kind == "index":
                index = val
            elif kind == "member":
                member = val
            else:
                at = val
        return Ref(_span(meta), name, index, member, at)

    def ref_index(self, meta, ch):
        return ("index", "-".join(str(c) for c in ch))

    def ref_index_set(self, meta, ch):
        return ("index", "{" + ",".join(ch[0]) + "}")

    def ref_about(self, meta, ch):
        r = ch[0]
        return Ref(_span(meta), r.name, r.index, r.member, r.at, ch[1])

    def ref_member(self, meta, ch):
        return ("member", str(ch[0]))

    def ref_at(self, meta, ch):
        return ("at", tuple(str(c) for c in ch))

    def _bin(op):
        def f(self, meta, ch):
            return BinOp(_span(meta), op, ch[0], ch[-1])
        return f

    add, sub, mul, div, pow = _bin("+"), _bin("-"), _bin("*"), _bin("/"), _bin("^")

    def neg(self, meta, ch):
        return Neg(_span(meta), ch[0])

    def unary(self, meta, ch):  # unary plus
        return ch[-1]

    def call(self, meta, ch):
        return Call(_span(meta), str(ch[0]), tuple(ch[1:]), _tspan(ch[0]))

    def vec_lit(self, meta, ch):
        return VecLit(_span(meta), ch[0], ch[1])

    def magnitude(self, meta, ch):
        return Mag(_span(meta), ch[0])

    def vector(self, meta, ch):
        return ch[0]

    # -- header
    def problem_stmt(self, meta, ch):
        return Problem(_span(meta), str(ch[0])[1:-1])

    def gravity_stmt(self, meta, ch):
        d = ch[1]
        return Gravity(_span(meta), ch[0], d[0], d[1])

    def dir_down(self, meta, ch):
        return ("down", None)

    def dir_up(self, meta, ch):
        return ("up", None)

    def dir_left(self, meta, ch):
        return ("left", None)

    def dir_right(self, meta, ch):
        return ("right", None)

    def dir_plane(self, meta, ch):
        return ("plane", None)

    def dir_vector(self, meta, ch):
        return ("vector", ch[0])

    def let_stmt(self, meta, ch):
        return Let(_span(meta), str(ch[0]), ch[1])

    def unknown_stmt(self, meta, ch):
        unit = ch[1] if len(ch) > 1 else (None, None)
        return UnknownDecl(_span(meta), str(ch[0]), unit[0], unit[1])

    # -- bodies and points
    def arg(self, meta, ch):
        return Arg(_span(meta), str(ch[0]), ch[1])

    def shape(self, meta, ch):
        return Shape(_span(meta), str(ch[0]), tuple(c for c in ch[1:] if c is not None))

    def part(self, meta, ch):
        shape, at, rot = ch[0], None, None
        for kind, val in ch[1:]:
            if kind == "at":
                at = val
            else:
                rot = val
        return Shape(shape.span, shape.kind, shape.args, at, rot)

    def place_at(self, meta, ch):
        return ("at", ch[0])

    def place_rotated(self, meta, ch):
        return ("rotated", ch[0])

    def body_simple(self, meta, ch):
        return BodyDecl(_span(meta), str(ch[0]), (ch[1],), False)

    def body_composite(self, meta, ch):
        return BodyDecl(_span(meta), str(ch[0]), tuple(ch[1:]), True)

    def point_stmt(self, meta, ch):
        name, d = str(ch[0]), ch[1]
        if isinstance(d, PointRef):
            return PointDecl(_span(meta), name, None, None, d)
        return PointDecl(_span(meta), name, d[0], d[1])

    def point_at(self, meta, ch):
        return (str(ch[0]), ch[1])

    def point_alias(self, meta, ch):
        return ch[0]

    def pref_name(self, meta, ch):
        return PointRef(_span(meta), str(ch[0]))

    def pref_member(self, meta, ch):
        return PointRef(_span(meta), str(ch[0]), member=str(ch[1]))

    def pref_end(self, meta, ch):
        return PointRef(_span(meta), str(ch[0]), end=str(ch[1]))

    def surface_stmt(self, meta, ch):
        found = dict(c for c in ch[1:])
        return SurfaceDecl(_span(meta), str(ch[0]), found.get("normal"), found.get("at"))

    def surface_normal(self, meta, ch):
        return ("normal", ch[0])

    def surface_at(self, meta, ch):
        return ("at", ch[0])

    def joint_from(self, meta, ch):
        return ("from", str(ch[0]), _tspan(ch[0]))

    # -- open systems
    def fp_rate(self, meta, ch):
        return ("rate", ch[0])

    def fp_velocity(self, meta, ch):
        return ("velocity", ch[0])

    def fp_relative(self, meta, ch):
        return ("relative", True)

    def fp_at(self, meta, ch):
        return ("at", ch[0])

    def flow_props(self, meta, ch):
        return dict(ch)

    def _flow(kind):
        def f(self, meta, ch):
            p = ch[0]
            return Flow(_span(meta), kind, p.get("rate"), p.get("velocity"),
                        bool(p.get("relative")), p.get("at"))
        return f

    cv_inflow, cv_outflow = _flow("inflow"), _flow("outflow")

    def cv_at(self, meta, ch):
        return ch[0]

    def cv_force(self, meta, ch):
        return Flow(_span(meta), "force", None, ch[0], False, ch[1] if len(ch) > 1 else None)

    def cv_support(self, meta, ch):
        return ("support", str(ch[0]))

    def cv_moving(self, meta, ch):
        return ("moving", ch[0])

    def steady_stmt(self, meta, ch):
        flows, supports, moving = [], [], None
        for c in ch[1:]:
            if isinstance(c, Flow):
                flows.append(c)
            elif c[0] == "support":
                supports.append(c[1])
            else:
                moving = c[1]
        return SteadyDecl(_span(meta), str(ch[0]), tuple(flows), tuple(supports), moving)

    def ct_mass(self, meta, ch):
        return ("mass", ch[0])

    def ct_velocity(self, meta, ch):
        return ("velocity", ch[0])

    def ct_acceleration(self, meta, ch):
        return ("acceleration", ch[0])

    def contents_props(self, meta, ch):
        return dict(ch)

    def cv_contents(self, meta, ch):
        return ("contents", ch[0])

    def instant_stmt(self, meta, ch):
        contents = {}
        rest = []
        for c in ch[1:]:
            if isinstance(c, tuple) and c[0] == "contents":
                contents.update(c[1])
            else:
                rest.append(c)
        cv = self.steady_stmt(meta, [ch[0]] + rest)
        return SteadyDecl(cv.span, cv.name, cv.flows, cv.supports, cv.moving, True,
                          contents.get("mass"), contents.get("velocity"),
                          contents.get("acceleration"))

    def burn_exhaust(self, meta, ch):
        return ("exhaust", (ch[0], ch[1]), _span(meta))

    def burn_rate(self, meta, ch):
        return ("rate", ch[0], _span(meta))

    def burn_mass(self, meta, ch):
        return ("burned", ch[0], _span(meta))

    def burn_duration(self, meta, ch):
        return ("duration", ch[0], _span(meta))

    def burn_stmt(self, meta, ch):
        d = {c[0]: c[1] for c in ch[3:]}
        exhaust = d.get("exhaust", (None, None))
        return BurnDecl(_span(meta), str(ch[0]), str(ch[1]), str(ch[2]), exhaust[0],
                        exhaust[1], d.get("rate"), d.get("burned"), d.get("duration"),
                        tuple((c[0], c[2]) for c in ch[3:]))

    def kind_gain(self, meta, ch):
        return False

    def kind_lose(self, meta, ch):
        return True

    def gain_rate(self, meta, ch):
        return ("rate", ch[0])

    def gain_velocity(self, meta, ch):
        return ("velocity", ch[0])

    def gain_velocity_relative(self, meta, ch):
        return ("relative", ch[0])

    def gain_force(self, meta, ch):
        return ("force", ch[0])

    def gain_duration(self, meta, ch):
        return ("duration", ch[0])

    def gain_stmt(self, meta, ch):
        d = {}
        for key, node in ch[4:]:
            if key in d or (key in ("velocity", "relative") and
                            ("velocity" in d or "relative" in d)):
                raise ProblemError(f"`{'velocity' if key == 'relative' else key}` is given "
                                   "twice", node.span, code="name")
            d[key] = node
        velocity = d.get("velocity", d.get("relative"))
        return GainDecl(_span(meta), str(ch[1]), str(ch[2]), str(ch[3]), ch[0],
                        d.get("rate"), velocity, "relative" in d, d.get("force"),
                        d.get("duration"))

    def label(self, meta, ch):
        return ("label", str(ch[0]))

    # -- simulation
    def sim_until(self, meta, ch):
        return Until(_span(meta), ch[0], ch[1] if len(ch) > 1 else None)

    def sim_damper(self, meta, ch):
        label = None
        if isinstance(ch[0], tuple) and ch[0][0] == "label":
            label, ch = ch[0][1], ch[1:]
        return Joint(_span(meta), "damper", label, ch[0], ch[1], stiffness=ch[2])

    def sim_bearing(self, meta, ch):
        return Clause(_span(meta), "bearing-torque", (str(ch[0]),), value=ch[1])

    def simulate_stmt(self, meta, ch):
        return SimulateDecl(_span(meta), str(ch[0]), _tspan(ch[0]), tuple(ch[1:]))

    def _joint(kind):
        def f(self, meta, ch):
            label = None
            if ch and isinstance(ch[0], tuple) and ch[0][0] == "label":
                label, ch = ch[0][1], ch[1:]
            a, b, rest = ch[0], ch[1], ch[2:]
            kw = {}
            if rest and isinstance(rest[-1], tuple) and rest[-1][0] == "from":
                kw["from_state"], kw["from_span"] = rest[-1][1], rest[-1][2]
                rest = rest[:-1]
            if kind == "pin" and rest:
                kw["at"] = rest[0]
            elif kind in ("link", "slider"):
                kw["along"] = rest[0]
            elif kind == "spring":
                kw["stiffness"] = rest[0]
                if len(rest) > 1:
                    kw["length"] = rest[1]
            return Joint(_span(meta), kind, label, a, b, **kw)
        return f

    pin_stmt, weld_stmt = _joint("pin"), _joint("weld")
    link_stmt, spring_stmt = _joint("link"), _joint("spring")
    slider_stmt = _joint("slider")

    # -- states
    def qty_ref(self, meta, ch):
        return (str(ch[0]), str(ch[1]), _span(meta))

    def _given(rel):
        def f(self, meta, ch):
            body, qty, qspan = ch[0]
            return Given(_span(meta), body, qty, qspan, ch[1], rel)
        return f

    given, hint_below, hint_above = _given("="), _given("<"), _given(">")

    def at_rest(self, meta, ch):
        return AtRest(_span(meta), str(ch[0]))

    def state_rolls(self, meta, ch):
        return RollsIn(_span(meta), str(ch[0]), str(ch[1]))

    def state_items(self, meta, ch):
        return list(ch)

    def state_stmt(self, meta, ch):
        sid = str(ch[0])
        label = None
        items = []
        for c in ch[1:]:
            if isinstance(c, str) and getattr(c, "type", None) == "STRING":
                label = str(c)[1:-1]
            elif isinstance(c, list):
                items.extend(c)
        return StateDecl(_span(meta), sid, label, tuple(items))

    # -- transitions
    def kind_impact(self, meta, ch):
        return "impact"

    def kind_interval(self, meta, ch):
        return "interval"

    def kind_energy(self, meta, ch):
        return "energy"

    def transition_stmt(self, meta, ch):
        kind, a, b = ch[0], ch[1], ch[2]
        rest = list(ch[3:])
        groups = rest.pop(0)[1] if rest and isinstance(rest[0], tuple) and \
            rest[0] and rest[0][0] == "energy_of" else ()
        return Transition(_span(meta), kind, str(a), str(b), tuple(rest), _tspan(a),
                          _tspan(b), groups)

    def energy_of(self, meta, ch):
        return ("energy_of", tuple(ch), _span(meta))

    def target_ground(self, meta, ch):
        return None

    def target_point(self, meta, ch):
        return ch[0]

    def contact_clause(self, meta, ch):
        label = None
        if ch and isinstance(ch[0], tuple) and ch[0][0] == "label":
            label, ch = ch[0][1], ch[1:]
        a, b = ch[0], ch[1]
        normal, props = None, ()
        for c in ch[2:]:
            if isinstance(c, list):
                props = tuple(c)
            else:
                normal = c
        return Contact(_span(meta), label, a, b, normal, props)

    def contact_props(self, meta, ch):
        out = []  # `friction 0.3 static 0.4` is two props
        for p in ch:
            out.extend(p if isinstance(p, list) else [p])
        return out

    def prop_restitution(self, meta, ch):
        value, law = ch[0], str(ch[1]) if len(ch) > 1 else None
        # `0.6 poisson` lexes as a number with a unit (the unit lexer comes first)
        if law is None and isinstance(value, Num) and value.unit in IMPACT_LAWS:
            law = value.unit
            value = Num(value.span, value.value)
        return Prop(_span(meta), "restitution", value, law or "newton")

    def prop_restitution_unknown(self, meta, ch):
        return Prop(_span(meta), "restitution?")

    def prop_smooth(self, meta, ch):
        return Prop(_span(meta), "smooth")

    def prop_rough(self, meta, ch):
        return Prop(_span(meta), "rough")

    def prop_friction(self, meta, ch):
        return Prop(_span(meta), "friction", ch[0])

    def prop_friction_static(self, meta, ch):
        return [Prop(_span(meta), "friction", ch[0]), Prop(_span(meta), "static", ch[1])]

    def prop_static(self, meta, ch):
        return Prop(_span(meta), "static", ch[0])

    def prop_slip(self, meta, ch):
        return Prop(_span(meta), "slip", ch[0])

    def prop_separation(self, meta, ch):
        return Prop(_span(meta), "separation", ch[0])

    def bearing_friction(self, meta, ch):
        return Clause(_span(meta), "bearing-friction", (str(ch[0]),))

    def stops_relative(self, meta, ch):
        return Clause(_span(meta), "stops-relative", (str(ch[0]), str(ch[1])))

    def stops(self, meta, ch):
        return Clause(_span(meta), "stops", (str(ch[0]),))

    def rolls(self, meta, ch):
        return Clause(_span(meta), "rolls", (str(ch[0]), str(ch[1])))

    def force_clause(self, meta, ch):
        return Clause(_span(meta), "force", value=ch[0], point=ch[1])

    def moment_clause(self, meta, ch):
        return Clause(_span(meta), "moment", (str(ch[1]),), value=ch[0])

    def duration_clause(self, meta, ch):
        return Clause(_span(meta), "duration", value=ch[0])

    def free_body(self, meta, ch):
        return Clause(_span(meta), "free", (str(ch[0]),))

    # -- principles
    def axis_x(self, meta, ch):
        return "x"

    def axis_y(self, meta, ch):
        return "y"

    def axis_vector(self, meta, ch):
        return ch[0]

    def body_set(self, meta, ch):
        return tuple(str(c) for c in ch)

    def conserve_momentum_stmt(self, meta, ch):
        return ConserveMomentum(_span(meta), ch[0], ch[1], str(ch[2]), str(ch[3]))

    def conserve_angular_stmt(self, meta, ch):
        return ConserveAngular(_span(meta), ch[0], ch[1], str(ch[2]), str(ch[3]))

    def restitution_stmt(self, meta, ch):
        return RestitutionLaw(_span(meta), ch[0], ch[1], ch[2], ch[3], str(ch[4]),
                              str(ch[5]))

    def equation_stmt(self, meta, ch):
        return UserEquation(_span(meta), ch[0], ch[1])

    # -- find
    def find_named(self, meta, ch):
        return (str(ch[0]), ch[1])

    def find_expr(self, meta, ch):
        return (None, ch[0])

    def find_item(self, meta, ch):
        name, expr = ch[0]
        unit = ch[1] if len(ch) > 1 else (None, None)
        split = _split_in_unit(expr) if len(ch) == 1 else None
        if split is not None:
            expr, unit = split[0], (split[1], split[2])
        return FindItem(_span(meta), name, expr, unit[0], unit[1])

    def find_stmt(self, meta, ch):
        return Find(_span(meta), tuple(ch))

    # -- expectations
    def error_code(self, meta, ch):
        return "-".join(str(c) for c in ch)

    def expect_error(self, meta, ch):
        return Expect(_span(meta), error=ch[0])

    def expect_value(self, meta, ch):
        tol = ch[2] if len(ch) > 2 else (None, None)
        return Expect(_span(meta), ch[0], ch[1],
                      tol[1] if tol[0] == "abs" else None,
                      tol[1] if tol[0] == "rel" else None)

    def tol_abs(self, meta, ch):
        return ("abs", ch[-1])

    def tol_rel(self, meta, ch):
        return ("rel", ch[-1])


def _make_transformer():
    from lark import Transformer, v_args

    body = {k: v for k, v in vars(Rules).items()
            if not (k.startswith("__") and k.endswith("__"))}
    body["__module__"] = __name__
    return v_args(meta=True)(type("ToNodes", (Transformer,), body))


@functools.lru_cache(maxsize=1)
def _transformer_class():
    return _make_transformer()


def _ToNodes(big: bool = False):
    """A transformer; for a big tree with its callbacks bound once (lark's `v_args` makes a
    new wrapper, through functools.update_wrapper, at every node otherwise)."""
    inst = _transformer_class()()
    if big:
        cls = type(inst)
        for name in dir(cls):
            if not name.startswith("_") and hasattr(getattr(cls, name), "visit_wrapper"):
                setattr(inst, name, getattr(inst, name))
    return inst
