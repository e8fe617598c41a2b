"""Parse the common statement forms a line at a time: one regex match per statement.

In: a loop-free problem text ending in a newline, and `rest(text, line)` (syntax_run
from that line) for any other statement. Out: the statement nodes syntax_run (and lark
with syntax.Rules) give, every span included; None when something other than comments
comes before the first statement: the caller parses the text whole. Lines of one shape
(equal but for their digits) are built by a function written for that shape.
"""
from __future__ import annotations

import sys

from . import builder_store, regex_store, source

_NODES = ("Arg", "AtRest", "BodyDecl", "Clause", "Contact", "Find", "FindItem", "Given",
          "Gravity", "Let", "Neg", "Num", "PointRef", "Problem", "Prop", "Ref", "RollsIn",
          "Shape", "StateDecl", "Transition", "VecLit")
_SETUP = [None]  # the syntax module whose node classes the makers below build


def _maker(cls, nodes: bool = True):
    """A function building `cls` records (frozen, slotted) as its constructor does, about
    twice as fast: the fields are set on a plain twin of the same slots, whose class then
    becomes `cls` (a frozen record sets each slot through a descriptor call). The class
    itself when it is not a plain record (a base, a factory)."""
    fields = getattr(cls, "_fields", None)
    if fields is None or cls.__bases__ != (object,) or tuple(cls.__slots__) != fields or \
            getattr(cls, "_factories", None) or not all(f.isidentifier() and
                                                        not f.startswith("_") for f in fields):
        return cls
    defaults = cls._defaults
    twin = type("_" + cls.__name__, (), {"__slots__": tuple(fields)})
    env = {"_new": object.__new__, "_T": twin, "_C": cls}
    params = []
    for i, f in enumerate(fields):
        if f in defaults:
            env[f"_d{i}"] = defaults[f]
            params.append(f"{f}=_d{i}")
        else:
            params.append(f)
    src = (f"def make({', '.join(params)}):\n    o = _new(_T)\n" +
           "".join(f"    o.{f} = {f}\n" for f in fields) +
           "    o.__class__ = _C\n    return o\n")
    try:
        exec(src, env)  # noqa: S102 (from the field names only)
        make = env["make"]
        probe = make(*range(len(fields)))
        if probe != cls(*range(len(fields))) or type(probe) is not cls:
            return cls
    except Exception:  # a layout __class__ assignment refuses: the constructor
        return cls
    if nodes:  # a syntax node class: builders name its twin (setup)
        _TWIN_OF[cls] = twin
    return make


_TWIN_OF: dict = {}  # record class -> its plain twin (_maker)


def maker(cls):
    """_maker of a record class other than the syntax nodes (scene_deferred's)."""
    return _maker(cls, False)


_ENV: dict = {}  # a builder's globals (setup)


def setup(syntax) -> None:
    """Bind the node classes of `syntax` (passed in: syntax imports this module) and a
    maker for each; the keywords of its grammar."""
    global _MAKERS_OF, _NumClass, _KEYWORDS, IMPACT_LAWS, _CLASSES
    if _SETUP[0] is syntax:
        return
    classes = [source.Span] + [getattr(syntax, n) for n in _NODES]
    _MAKERS_OF = {c: _maker(c) for c in classes}
    _CLASSES = dict(zip(_NODES, classes[1:]))
    _NumClass = syntax.Num
    IMPACT_LAWS = syntax.IMPACT_LAWS
    grammar = syntax.grammar_text()
    _KEYWORDS = keywords(grammar)
    g = globals()
    g["Span"] = _MAKERS_OF[source.Span]
    for n, c in zip(_NODES, classes[1:]):
        g[n] = _MAKERS_OF[c]
    _UNIT_OK.clear()
    _SHAPES.clear()
    # the globals of a builder's code: the records it makes, and their plain twins
    _ENV.clear()
    _ENV["_new"] = object.__new__
    for c, twin in _TWIN_OF.items():
        _ENV["_T" + c.__name__], _ENV["_C" + c.__name__] = twin, c
    builder_store.configure(grammar, (sys.modules[__name__], syntax, source))
    _SETUP[0] = syntax


class _No(Exception):
    """Not a form recognised here: syntax_run parses this statement."""


# the grammar's terminals (momentum.lark), each as one token: atomic groups, so that no
# backtracking splits a token where the lexer would not
_NAME = r"(?>[A-Za-z_][A-Za-z_0-9]*(?:\[[0-9]+\])*)"
_NUM = r"(?>(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)"
_UNIT = (r"(?>[A-Za-z_][A-Za-z_0-9]*(?:(?:\*\*|\^)-?[0-9]+)?"
         r"(?:[*/][A-Za-z_][A-Za-z_0-9]*(?:(?:\*\*|\^)-?[0-9]+)?)*)")
_ID = r"(?>[0-9]+)"
_END = r"(?![A-Za-z_0-9])"  # a keyword ends where a name could not go on

# An expression of the forms read here, as groups in a fixed order (read by _x): a number
# with its unit, or a reference, maybe negated (_A: 9 groups, the last empty, where it
# ends); or a vector of two of them (_X: 29 groups). Atomic, as tokens are: `2 in mm` is
# never re-read as `2` then `in mm`.
_A = (rf"(?:(-) *)?(?>({_NUM})(?: *({_UNIT}))?|({_NAME})(?: *\[ *({_NAME}(?: *- *{_NAME})*)"
      rf" *\])?(?: *\. *({_NAME}))?(?: *@ *({_ID})(?: *-> *({_ID}))?)?)()")
_X = rf"(?:(\() *{_A} *, *{_A} *\)()|{_A})"
_PREF = rf"(?>({_NAME})(?: *\. *(?:end *\( *([+-]) *\)|({_NAME})))?)()"  # 4 groups
# the patterns below, compiled from code kept in the cache folder (regex_store): the
# regex compiler would cost each big file's process ~13 ms
_RE = regex_store.compiled("syntax_lines", {
    "TAIL": r" *(?:#.*)?",
    "SP": r" *",
    "WORD": _NAME,
    "HEAD": r"[a-z]+(?![A-Za-z_0-9\[])",  # a whole word: a keyword
    "BODY": rf"body +({_NAME}) *: *({_NAME}) *\( *",
    "ARG": rf"({_NAME}) *= *{_X} *",  # 1 name, 2.. the value
    "LET": rf"let +({_NAME}) *= *{_X} *",
    "ITEM": rf"({_NAME}) *(?:\. *({_NAME})() *([=<>]) *{_X}|at +rest{_END}()"
            rf"|rolls +on +({_NAME})()) *",  # 1 2 3 4, 5.. value, 34, 35 36
    "REST": rf"({_NAME}) +at +rest{_END}() *, *(?=[A-Za-z_])",  # not the last
    "STATE": rf'state *(?P<id>{_ID}) *(?P<s>"[^"\n]*")? *(?P<c>:)? *',
    "TRANS": rf"(?P<k>impact|interval|energy) *(?P<a>{_ID}) *-> *(?P<b>{_ID})"
             rf"(?P<z>) *(?P<c>:)?",
    # 1 label, 2-5 and 6-9 the points, 10.. the normal, 39 the colon of the properties
    "CONTACT": rf"contact *(?:({_NAME}) *: *)?{_PREF} *with{_END} *{_PREF} *"
               rf"(?:normal{_END} *{_X} *)?(:)? *",
    "PROP": rf"(restitution|smooth|rough|friction|slip|separation|static){_END}"
            rf"(?: *(\?)| *{_X})?() *",  # 1 kind, 2 `?`, 3.. the value, 32 its end
    "STOPS": rf"(?P<n>{_NAME}) +(?:stops{_END}(?P<z>) *|rolls +on +(?P<s>{_NAME})"
             rf"(?P<sz>) *)",
    "FREE": rf"free +(?P<n>{_NAME})(?P<z>) *",
    "FIND": r"find *",
    # 1 name, 2.. the expression, 31 the unit, 32 its end
    "FINDITEM": rf"(?:({_NAME}) *= *)?{_X}(?: *in +({_UNIT})())? *",
    "PROBLEM": r'problem *(?P<s>"[^"\n]*")',
    "GRAVITY": rf"gravity *{_X} *(down|up|left|right){_END}",
    "NUMBER": _NUM,
    "QUOTED": r'"([A-Za-z_][A-Za-z_0-9]*)"',  # a keyword in the grammar
})
_TAIL, _SP, _WORD, _HEAD = _RE["TAIL"], _RE["SP"], _RE["WORD"], _RE["HEAD"]
_BODY, _ARG, _LET, _ITEM, _REST = _RE["BODY"], _RE["ARG"], _RE["LET"], _RE["ITEM"], _RE["REST"]
_STATE, _TRANS, _CONTACT, _PROP = _RE["STATE"], _RE["TRANS"], _RE["CONTACT"], _RE["PROP"]
_STOPS, _FREE, _FIND, _FINDITEM = _RE["STOPS"], _RE["FREE"], _RE["FIND"], _RE["FINDITEM"]
_PROBLEM, _GRAVITY, _NUMBER = _RE["PROBLEM"], _RE["GRAVITY"], _RE["NUMBER"]

# words the grammar writes in quotes: where one is acceptable the lexer tries it before a
# UNIT (a lower priority), and it wins even as a prefix (`5 inch` is `in` then `ch`); the
# impact laws rank below UNIT
_KEYWORDS: frozenset = frozenset()
_UNIT_OK: dict = {}
_MAKERS_OF: dict = {}  # node class -> its maker (setup)
_CLASSES: dict = {}  # a node class's name -> the class (setup)
_NumClass = None
IMPACT_LAWS: tuple = ()


def keywords(grammar: str) -> frozenset:
    """The words `grammar` writes in quotes (its keywords)."""
    return frozenset(_RE["QUOTED"].findall(grammar))


def _unit_ok(u: str) -> bool:
    """A UNIT token is read as one only when no keyword is a prefix of it."""
    ok = _UNIT_OK.get(u)
    if ok is None:
        ok = _UNIT_OK[u] = not any(u.startswith(k) for k in _KEYWORDS
                                   if k not in IMPACT_LAWS)
    return ok


def parse(text: str, rest, syntax, defer: bool = False):
    """The statements of `text` (ending in "\\n"), or None (not plain: parse it whole).
    `rest(chunk, line)` parses a statement not recognised here (it may raise); `syntax`:
    the module whose nodes are built. `defer`: a big text's common lines may be kept as
    deferred items (below; DEFERRED says whether any was)."""
    setup(syntax)
    lines = text.split("\n")
    n = len(lines) - 1  # the last element is the "" after the final newline
    # a statement starts with a keyword at column 1: every other line (indented, blank,
    # a comment, a bracket's continuation) belongs to the statement before it
    heads = [i for i in range(n) if lines[i][:1].isalpha() and lines[i][0].isascii()]
    if not heads:
        return None
    for i in range(heads[0]):
        s = lines[i].lstrip(" \t\f")
        if s and s[0] != "#":
            return None  # something before the first statement: the whole parse decides
    heads.append(n)
    _STORING[0] = STORE and len(text) >= STORE_BYTES
    _DEFERRING[0] = defer and DEFER and len(text) >= DEFER_BYTES
    DEFERRED[0] = False
    try:
        return _statements(lines, heads, rest)
    finally:
        _DEFERRING[0] = False
        if _STORING[0]:
            builder_store.flush()
            _STORING[0] = False


# A big text's body lines and impacts' contact lines whose shape has a builder are kept
# as their text: a deferred item (node class, make, text, line), the node being
# make(text, line). The scene reads most of them from their text at the places their
# shape fixes (scene_deferred.py), skipping ~20 records a line; anything else reading
# the document gets the nodes (statement_deferred.DeferredDocument makes them then).
DEFER = True  # (tests turn it off to compare)
DEFER_BYTES = 1 << 17  # a smaller text (a batch's files) builds its nodes straight away
_DEFERRING = [False]  # within `parse` of such a text
DEFERRED = [False]  # whether the last `parse` returned a deferred item
_CONTACT_SHAPES: dict = {}  # a clause line's shape -> whether it is a contact


def _is_word(s: str, p: int, word: str) -> bool:
    """s has the whole word `word` at p (no name character follows it)."""
    q = p + len(word)
    return s.startswith(word, p) and not (s[q:q + 1].isalnum() or s[q:q + 1] in ("_", "["))


def fill_transition(node, _L=None):
    """A Transition whose deferred contact lines (`_transition`) are made into nodes."""
    clauses = tuple([c if c.__class__ is not tuple else c[1](c[2], c[3])
                     for c in node.clauses])
    return node.__class__(*[clauses if f == "clauses" else getattr(node, f)
                            for f in node._fields])


def _statements(lines, heads, rest) -> list:
    """The nodes of the statements starting at `heads` (line indices, the last one the
    end), each by its shape's builder, its form, or `rest`."""
    out = []
    shapes, mask, fn = _SHAPES, _MASK, _FUNCTION
    defer, body_class = _DEFERRING[0], _CLASSES.get("BodyDecl")
    for k in range(len(heads) - 1):
        a, b = heads[k], heads[k + 1]
        if b == a + 1:  # a line of a shape already seen: its builder, straight away
            s = lines[a]
            hit = shapes.get(s.encode().translate(mask))
            if hit.__class__ is fn:
                if defer and s.startswith("body "):  # kept as its text (a BodyDecl)
                    out.append((body_class, hit, s, b))
                    DEFERRED[0] = True
                else:
                    out.append(hit(s, b))
                continue
        try:
            out.append(_statement(lines, a, b))
        except _No:
            out.extend(rest("\n".join(lines[a:b]) + "\n", a + 1))
    return out


def read(lines, a: int, b: int, syntax):
    """The node of the statement on lines[a:b] (0-based, a file's lines cut as `parse`
    cuts them), as `parse` of that file gives it, or None: not a form read here (in a
    batch, statement_memo reads each new statement so, its shape's builder once made)."""
    if _SETUP[0] is not syntax:
        setup(syntax)
    if b == a + 1:
        s = lines[a]
        hit = _SHAPES.get(s.encode().translate(_MASK))
        if hit.__class__ is _FUNCTION:
            return hit(s, b)
    try:
        return _statement(lines, a, b)
    except _No:
        return None


def _block(lines, a, b) -> list:
    """The indented content lines of a statement (line numbers, 0-based): one indentation
    for all, comments and blank lines left to the newline token."""
    found = []
    ind = None
    for i in range(a + 1, b):
        x = lines[i]
        s = x.lstrip(" ")
        if not s or s[0] == "#":
            continue
        w = len(x) - len(s)
        if w == 0:
            raise _No  # a continuation line (`\\`, a bracket) or a tab
        if ind is None:
            ind = w
        elif w != ind:
            raise _No
        found.append(i)
    return found


def _statement(lines, a, b):
    s = lines[a]
    m = _HEAD.match(s)
    if m is None:
        raise _No
    word = m.group()
    f = _FORMS.get(word)
    if f is None:
        raise _No
    if b == a + 1:  # a line of its own: its nodes depend on its text and number only
        return _shaped(word, f, s, a + 1)
    if b - a <= SHORT_BLOCK:  # a short block: its nodes depend on its text and first line
        text = "\n".join(lines[a:b])
        if f is _transition and _DEFERRING[0]:
            hit = _SHAPES.get(text.encode().translate(_MASK))
            if hit.__class__ is _FUNCTION:  # kept as its text (a Transition)
                DEFERRED[0] = True
                return (_CLASSES["Transition"], hit, text, a + 1)
        return _shaped(word, f, text, a + 1)
    if f is _transition and _DEFERRING[0]:
        return _transition(lines, a, b, s, a + 1, True)
    return f(lines, a, b, s, a + 1)


SHORT_BLOCK = 6  # lines; a longer block is read a line at a time (_line_clause)


def _line_statement(f, s: str, L: int):
    """Form `f` of the statement whose lines are s, the first being line L."""
    if "\n" not in s:
        return f(None, L - 1, L, s, L)
    ls = s.split("\n")
    return f(dict(enumerate(ls, L - 1)), L - 1, L - 1 + len(ls), ls[0], L)


def _line_clause(_, s: str, L: int):
    """A clause line of a transition's block (s with its indentation), line L."""
    return _clause(s, len(s) - len(s.lstrip(" ")), L)


# ---- one builder per shape of line ---------------------------------------------------------
# Lines whose text differs only in its digits (`contact c17: b18 with b17` and `contact
# c20: b21 with b20`) are read the same way, token for token at the same columns (the
# grammar's terminals see digits only as a class): after a few such lines, a function
# written for that shape builds the nodes straight from slices of the line.
_MASK = bytes.maketrans(b"123456789", b"000000000")
_PROBE = str.maketrans("0123456789", "1234567890")
BUILD_AFTER = 4  # lines of one shape read before its builder is written
MAX_SHAPES = 5_000  # (then forgotten: a bound on the memory they hold)
_SHAPES: dict = {}  # masked text -> lines of that shape read so far, or its builder
_FUNCTION = type(lambda: 0)
_BIG = 1 << 40  # the line number a template is read at (so its line fields are known)


def _shaped(kind, f, s: str, L: int):
    """The nodes of s (a line, or the lines of a short statement; the first is line L)
    by `f` (a form; None: a clause) or by the builder of the shape of s."""
    key = s.encode().translate(_MASK)  # (its first word tells the kind: a statement's
    # keyword, or the indentation of a clause)
    hit = _SHAPES.get(key)
    if hit is None and _STORING[0]:
        hit = _stored(key)
        if hit is not None:  # a builder, or False: none can be written for this shape
            if len(_SHAPES) >= MAX_SHAPES:
                _SHAPES.clear()
            _SHAPES[key] = hit
    if hit is None or hit.__class__ is int:
        run = _line_clause if kind is None else _line_statement
        node = run(f, s, L)  # (_No: not a form read here; the count stays)
        n = (hit or 0) + 1
        if len(_SHAPES) >= MAX_SHAPES:
            _SHAPES.clear()
        _SHAPES[key] = _builder(run, f, s) if n >= BUILD_AFTER else n
        return node
    if hit is False:
        return (_line_clause if kind is None else _line_statement)(f, s, L)
    return hit(s, L)


def _builder(run, f, s: str):
    """A function (text, L) -> the nodes `run(f, text, L)` gives for every text of the
    shape of s; False when one cannot be written (then each line is read). Read three
    times (s, and s with its digits changed two ways), every text field is found at one
    place only, and the function is checked against each reading."""
    texts = (s, s.translate(_PROBE),
             "".join(str((3 * i + 1) % 10) if c in "0123456789" else c
                     for i, c in enumerate(s)))
    try:
        trees = [run(f, x, _BIG) for x in texts]
        env = {"_new": object.__new__}
        body: list = []
        out = _code(trees, texts, (env, body))
        src = "def build(s, L):\n" + "".join(f"    {x}\n" for x in body) + \
            f"    return {out}\n"
        code = compile(src, "<syntax_lines>", "exec")
        exec(code, env)  # noqa: S102 (from the nodes)
        fn = env["build"]
        if any(fn(x, 7) != run(f, x, 7) for x in texts):
            fn = code = False
    except Exception:  # a field found nowhere or at two places, a deep tree...: read each
        fn = code = False
    if _STORING[0]:
        builder_store.add(s.encode().translate(_MASK), code)
    return fn


STORE = True  # builders kept in the cache folder between runs (tests turn it off)
# a text this long reads and keeps stored builders: a smaller one (a batch's files) makes
# its few builders itself, where loading and writing the file would cost it more
STORE_BYTES = 1 << 17
_STORING = [False]  # within `parse` of such a text


def _stored(key: bytes):
    """The builder of the shape `key` made by an earlier run (builder_store), False when
    that run found none can be written, None when it met no such line. Its code was
    checked against the readings when it was made, from these modules."""
    code = builder_store.get(key)
    if code is None or code is False:
        return code
    env = dict(_ENV)
    try:
        exec(code, env)  # noqa: S102 (written by _builder, read from a private file)
        return env["build"]
    except Exception:  # not a builder's code: read the line
        return None


def _code(vs: list, texts: tuple, out: tuple) -> str:
    """An expression of s and L giving vs[i] for (texts[i], _BIG), for every i; the
    records it names are built by statements appended to out[1] (a record: a plain twin
    of its slots, filled, then given the record's class; out[0]: their globals)."""
    v1 = vs[0]
    t = v1.__class__
    if any(v.__class__ is not t for v in vs):
        raise ValueError
    if v1 is None or t is bool or t is int:
        if any(v != v1 for v in vs):
            raise ValueError
        d = v1 - _BIG if t is int else _BIG
        if d == 0:
            return "L"  # (one int object for every span of the line)
        return f"(L + {d})" if -1000 < d < 1000 else repr(v1)
    if t is str:
        if not any(c in "0123456789" for c in v1):
            if any(v != v1 for v in vs):
                raise ValueError
            return repr(v1)
        n = len(v1)
        s = texts[0]
        at = [a for a in range(len(s) - n + 1)
              if all(x.startswith(v, a) for x, v in zip(texts, vs))]
        if len(at) != 1 or any(len(v) != n for v in vs):
            raise ValueError
        return f"s[{at[0]}:{at[0] + n}]"
    if t is tuple:
        if any(len(v) != len(v1) for v in vs):
            raise ValueError
        return "(" + "".join(_code([v[i] for v in vs], texts, out) + ", "
                             for i in range(len(v1))) + ")"
    twin = _TWIN_OF.get(t)
    if twin is None:
        raise ValueError
    env, body = out
    args = []
    for k in t._fields:
        fs = [getattr(v, k) for v in vs]
        if fs[0].__class__ is float:  # a Num's value: the number its span starts with
            dl = v1.span.line - _BIG
            if t is not _NumClass or not 0 <= dl < 1000:
                raise ValueError
            c = 0
            for _ in range(dl):  # the start of the span's line (a text of several lines)
                c = texts[0].index("\n", c) + 1
            c += v1.span.column - 1
            m = _NUMBER.match(texts[0], c)
            if m is None or any(float(x[c:m.end()]) != f for x, f in zip(texts, fs)):
                raise ValueError
            args.append(f"float(s[{c}:{m.end()}])")
        else:
            args.append(_code(fs, texts, out))
    name = t.__name__
    env["_T" + name], env["_C" + name] = twin, t
    v = f"o{len(body)}"
    body.append(f"{v} = _new(_T{name}); " +
                "".join(f"{v}.{k} = {a}; " for k, a in zip(t._fields, args)) +
                f"{v}.__class__ = _C{name}")
    return v


def _tail(s: str, p: int) -> None:
    """Only spaces and a comment are left on the line."""
    if _TAIL.match(s, p).end() != len(s):
        raise _No


def _a(g, r, i: int, L: int):
    """The atom whose 9 groups start at group i (g: the match's groups(), r: its regs)."""
    z = r[i + 8][0]
    num = g[i]
    if num is not None:
        st = r[i + 1][0]
        u = g[i + 1]
        if u is None:
            node = Num(Span(L, st + 1, L, z + 1), float(num))
        else:
            ok = _UNIT_OK.get(u)
            if not (_unit_ok(u) if ok is None else ok):
                raise _No
            node = Num(Span(L, st + 1, L, z + 1), float(num), u,
                       Span(L, r[i + 2][0] + 1, L, z + 1))
    else:
        idx, a1, a2 = g[i + 3], g[i + 5], g[i + 6]
        node = Ref(Span(L, r[i + 3][0] + 1, L, z + 1), g[i + 2],
                   None if idx is None else idx.replace(" ", ""), g[i + 4],
                   () if a1 is None else (a1,) if a2 is None else (a1, a2))
    if g[i - 1] is not None:
        node = Neg(Span(L, r[i][0] + 1, L, z + 1), node)
    return node, z


def _x(g, r, i: int, L: int):
    """(node, end) of the expression whose 29 groups start at group i."""
    if g[i - 1] is None:
        return _a(g, r, i + 20, L)
    x = _a(g, r, i + 1, L)[0]
    y = _a(g, r, i + 10, L)[0]
    z = r[i + 19][0]
    return VecLit(Span(L, r[i][0] + 1, L, z + 1), x, y), z


def _pref(g, r, i: int, L: int):
    """The point reference (`A`, `rod.A`, `rod.end(+)`) of groups i..i+3."""
    z = r[i + 3][0]
    if g[i] is not None:
        return PointRef(Span(L, r[i][0] + 1, L, z + 1), g[i - 1], end=g[i])
    if g[i + 1] == "end":
        raise _No  # the keyword `end`, without its `(+)`
    return PointRef(Span(L, r[i][0] + 1, L, z + 1), g[i - 1], g[i + 1])


def _end(b: int) -> int:
    return b + 1  # a statement's span ends at column 1 of the line after its last


# ---- statements ---------------------------------------------------------------------------
def _body(lines, a, b, s, L):
    m = _BODY.match(s)
    if m is None or m.group(2) == "composite" or _block(lines, a, b):
        raise _No
    args = []
    p = m.end()
    if s.startswith(")", p):
        p += 1
    else:
        while True:
            ma = _ARG.match(s, p)
            if ma is None:
                raise _No
            g, r = ma.groups(), ma.regs
            v, z = _x(g, r, 2, L)
            args.append(Arg(Span(L, r[1][0] + 1, L, z + 1), g[0], v))
            p = r[0][1]
            if s.startswith(",", p):
                p = _SP.match(s, p + 1).end()
            elif s.startswith(")", p):
                p += 1
                break
            else:
                raise _No
    _tail(s, p)
    shape = Shape(Span(L, m.start(2) + 1, L, p + 1), m.group(2), tuple(args))
    return BodyDecl(Span(L, 1, _end(b), 1), m.group(1), (shape,), False)


def _let(lines, a, b, s, L):
    m = _LET.match(s)
    if m is None or _block(lines, a, b):
        raise _No
    _tail(s, m.end())
    return Let(Span(L, 1, _end(b), 1), m.group(1), _x(m.groups(), m.regs, 2, L)[0])


def _items(s: str, p: int, L: int, out: list) -> None:
    """A comma list of state items from s[p:] to the line's end."""
    match, rest = _ITEM.match, _REST.match
    while True:
        m = rest(s, p)  # `B at rest, `: the common item, by a regex of few groups
        if m is not None:
            out.append(AtRest(Span(L, p + 1, L, m.end(2) + 1), m.group(1)))
            p = m.end()
            continue
        m = match(s, p)
        if m is None:
            raise _No
        g, r = m.groups(), m.regs
        st = r[0][0] + 1
        if g[3] is not None:
            v, z = _x(g, r, 5, L)
            out.append(Given(Span(L, st, L, z + 1), g[0], g[1], Span(L, st, L, r[3][0] + 1),
                             v, g[3]))
        elif g[34] is not None:
            out.append(RollsIn(Span(L, st, L, r[36][0] + 1), g[0], g[34]))
        else:
            out.append(AtRest(Span(L, st, L, r[34][0] + 1), g[0]))
        p = r[0][1]
        if s.startswith(",", p):
            p = _SP.match(s, p + 1).end()
        else:
            _tail(s, p)
            return


def _state(lines, a, b, s, L):
    m = _STATE.match(s)
    if m is None:
        raise _No
    items = []
    p = m.end()
    if m.group("c") is not None and _TAIL.match(s, p).end() != len(s):
        _items(s, p, L, items)
    else:
        _tail(s, p)
    if b > a + 1:
        for i in _block(lines, a, b):
            x = lines[i]
            _items(x, len(x) - len(x.lstrip(" ")), i + 1, items)
    label = m.group("s")
    return StateDecl(Span(L, 1, _end(b), 1), m.group("id"),
                     None if label is None else label[1:-1], tuple(items))


def _transition(lines, a, b, s, L, defer: bool = False):
    m = _TRANS.match(s)
    if m is None:
        raise _No
    _tail(s, m.end())
    block = _block(lines, a, b)
    if bool(block) != (m.group("c") is not None):
        raise _No
    clauses = []
    kept = False
    contact, shapes, mask, fn = _CLASSES.get("Contact"), _SHAPES, _MASK, _FUNCTION
    contacts = _CONTACT_SHAPES
    for i in block:
        x = lines[i]
        if defer:  # a contact line of a shape with a builder: kept as its text
            key = x.encode().translate(mask)
            hit = shapes.get(key)
            if hit.__class__ is fn:
                is_contact = contacts.get(key)
                if is_contact is None:
                    if len(contacts) >= MAX_SHAPES:
                        contacts.clear()
                    is_contact = contacts[key] = _is_word(x, len(x) - len(x.lstrip(" ")),
                                                          "contact")
                if is_contact:
                    clauses.append((contact, hit, x, i + 1))
                    kept = True
                    continue
        clauses.append(_shaped(None, None, x, i + 1))
    node = Transition(Span(L, 1, _end(b), 1), m.group("k"), m.group("a"), m.group("b"),
                      tuple(clauses), Span(L, m.start("a") + 1, L, m.end("a") + 1),
                      Span(L, m.start("b") + 1, L, m.end("b") + 1))
    if kept:
        DEFERRED[0] = True
        return (_CLASSES["Transition"], fill_transition, node, L)
    return node


def _contact(s: str, p: int, L: int):
    """`contact [LABEL:] A with B|ground [normal V] [: PROP, ...]`."""
    m = _CONTACT.match(s, p)
    if m is None:
        raise _No
    g, r = m.groups(), m.regs
    pa = _pref(g, r, 2, L)
    z = r[9][0]
    if g[5] == "ground":
        if g[6] is not None or g[7] is not None:
            raise _No
        pb = None
    else:
        pb = _pref(g, r, 6, L)
    normal = None
    if r[10][0] >= 0 or r[38][0] >= 0:
        normal, z = _x(g, r, 10, L)
    props = []
    q = r[0][1]
    if g[38] is not None:
        match = _PROP.match
        while True:
            pm = match(s, q)
            if pm is None:
                raise _No
            h, t = pm.groups(), pm.regs
            k = h[0]
            st = t[0][0] + 1
            z = t[32][0]
            has = t[3][0] >= 0 or t[31][0] >= 0
            if k == "smooth" or k == "rough":
                if has or h[1] is not None:
                    raise _No
                props.append(Prop(Span(L, st, L, z + 1), k))
            elif h[1] is not None:
                if k != "restitution":
                    raise _No
                props.append(Prop(Span(L, st, L, z + 1), "restitution?"))
            elif not has:
                raise _No
            else:
                v = _x(h, t, 3, L)[0]
                if k == "restitution":
                    law = "newton"
                    if v.__class__ is _NumClass and v.unit in IMPACT_LAWS:
                        law = v.unit
                        v = Num(v.span, v.value)
                    props.append(Prop(Span(L, st, L, z + 1), k, v, law))
                else:
                    props.append(Prop(Span(L, st, L, z + 1), k, v))
            q = t[0][1]
            if s.startswith(",", q):
                q = _SP.match(s, q + 1).end()
            else:
                break
    _tail(s, q)
    return Contact(Span(L, p + 1, L, z + 1), g[0], pa, pb, normal, tuple(props))


def _clause(s: str, p: int, L: int):
    """One clause of a transition's block: a contact, `B stops`, `B rolls on S`,
    `free B`."""
    w = _WORD.match(s, p)
    word = w and w.group()
    if word == "contact":  # (a clause starts with a name or a keyword: a whole word)
        return _contact(s, p, L)
    if word == "free":
        m = _FREE.match(s, p)
        if m is None:
            raise _No
        _tail(s, m.end())
        return Clause(Span(L, p + 1, L, m.start("z") + 1), "free", (m.group("n"),))
    m = _STOPS.match(s, p)
    if m is None or m.group("n") in _KEYWORDS:
        raise _No
    _tail(s, m.end())
    if m.group("s") is None:
        return Clause(Span(L, p + 1, L, m.start("z") + 1), "stops", (m.group("n"),))
    return Clause(Span(L, p + 1, L, m.start("sz") + 1), "rolls", (m.group("n"), m.group("s")))


def _find(lines, a, b, s, L):
    m = _FIND.match(s)
    if _block(lines, a, b):
        raise _No
    items = []
    p = m.end()
    while True:
        mi = _FINDITEM.match(s, p)
        if mi is None:
            raise _No
        g, r = mi.groups(), mi.regs
        v, z = _x(g, r, 2, L)
        unit = uspan = None
        if g[30] is not None:
            u = g[30]
            if v.__class__ is _NumClass and v.unit is None or not _unit_ok(u):
                raise _No  # `2 in mm` is one quantity
            z = r[32][0]
            unit, uspan = u, Span(L, r[31][0] + 1, L, z + 1)
        items.append(FindItem(Span(L, p + 1, L, z + 1), g[0], v, unit, uspan))
        p = r[0][1]
        if s.startswith(",", p):
            p = _SP.match(s, p + 1).end()
        else:
            break
    _tail(s, p)
    return Find(Span(L, 1, _end(b), 1), tuple(items))


def _problem(lines, a, b, s, L):
    m = _PROBLEM.match(s)
    if m is None or _block(lines, a, b):
        raise _No
    _tail(s, m.end())
    return Problem(Span(L, 1, _end(b), 1), m.group("s")[1:-1])


def _gravity(lines, a, b, s, L):
    m = _GRAVITY.match(s)
    if m is None or _block(lines, a, b):
        raise _No
    _tail(s, m.end())
    return Gravity(Span(L, 1, _end(b), 1), _x(m.groups(), m.regs, 1, L)[0], m.group(30), None)


_FORMS = {"body": _body, "let": _let, "state": _state, "impact": _transition,
          "interval": _transition, "energy": _transition, "find": _find,
          "problem": _problem, "gravity": _gravity}
