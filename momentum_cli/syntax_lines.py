"""Parse the common statement forms a line at a time: one regex match per token group.

In: a loop-free problem text ending in a newline, and `rest(text, line)` (syntax_run
from that line) for any other statement. Out: the statement nodes syntax_run (and lark
with syntax.Rules) give, every span included; None when something other than comments
comes before the first statement: the caller parses the text whole.
"""
from __future__ import annotations

import re

from .source import Span
from .syntax import (IMPACT_LAWS, Arg, AtRest, BodyDecl, Clause, Contact, Find, FindItem,
                     Given, Gravity, Let, Neg, Num, PointRef, Problem, Prop, Ref, RollsIn,
                     Shape, StateDecl, Transition, VecLit)


def _maker(cls):
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
    return make


_NumClass = Num
Span = _maker(Span)
(Arg, AtRest, BodyDecl, Clause, Contact, Find, FindItem, Given, Gravity, Let, Neg, Num,
 PointRef, Problem, Prop, Ref, RollsIn, Shape, StateDecl, Transition, VecLit) = map(
    _maker, (Arg, AtRest, BodyDecl, Clause, Contact, Find, FindItem, Given, Gravity, Let, Neg,
             Num, PointRef, Problem, Prop, Ref, RollsIn, Shape, StateDecl, Transition, VecLit))


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

# a number with its unit, or a reference, maybe negated; `z`: where it ends (before spaces)
_ATOM = re.compile(
    rf"(?:(?P<neg>-) *)?(?:(?P<num>{_NUM})(?: *(?P<unit>{_UNIT}))?"
    rf"|(?P<name>{_NAME})(?: *\[ *(?P<idx>{_NAME}(?: *- *{_NAME})*) *\])?"
    rf"(?: *\. *(?P<mem>{_NAME}))?(?: *@ *(?P<a1>{_ID})(?: *-> *(?P<a2>{_ID}))?)?)(?P<z>) *")
_PREF = re.compile(rf"(?P<n>{_NAME})(?: *\. *(?:end *\( *(?P<sg>[+-]) *\)|(?P<m>{_NAME})))?"
                   rf"(?P<z>) *")
_TAIL = re.compile(r" *(?:#.*)?")
_SP = re.compile(r" *")
_ITEM = re.compile(
    rf"(?P<n>{_NAME}) *(?:\. *(?P<q>{_NAME})(?P<qz>) *(?P<rel>[=<>]) *"
    rf"|at +rest{_END}(?P<rz>) *|rolls +on +(?P<s>{_NAME})(?P<sz>) *)")
_WORD = re.compile(_NAME)
_HEAD = re.compile(r"[a-z]+(?![A-Za-z_0-9\[])")  # a whole word: a keyword
_BODY = re.compile(rf"body +(?P<n>{_NAME}) *: *(?P<k>{_NAME}) *\( *")
_ARG = re.compile(rf"(?P<n>{_NAME}) *= *")
_LET = re.compile(rf"let +(?P<n>{_NAME}) *= *")
_STATE = re.compile(rf'state *(?P<id>{_ID}) *(?P<s>"[^"\n]*")? *(?P<c>:)? *')
_TRANS = re.compile(rf"(?P<k>impact|interval|energy) *(?P<a>{_ID}) *-> *(?P<b>{_ID})"
                    rf"(?P<z>) *(?P<c>:)?")
_CONTACT = re.compile(rf"contact *(?:(?P<l>{_NAME}) *: *)?")
_WITH = re.compile(rf"with{_END} *")
_NORMAL = re.compile(rf"normal{_END} *")
_PROP = re.compile(rf"(?P<k>restitution|smooth|rough|friction|slip|separation|static)"
                   rf"{_END}(?P<z>) *")
_STOPS = re.compile(rf"(?P<n>{_NAME}) +(?:stops{_END}(?P<z>) *|rolls +on +(?P<s>{_NAME})"
                    rf"(?P<sz>) *)")
_FREE = re.compile(rf"free +(?P<n>{_NAME})(?P<z>) *")
_FIND = re.compile(r"find *")
_NAMED = re.compile(rf"(?P<n>{_NAME}) *= *")
_IN = re.compile(rf"in +(?P<u>{_UNIT})(?P<z>) *")
_PROBLEM = re.compile(r'problem *(?P<s>"[^"\n]*")')
_GRAVITY = re.compile(r"gravity *")
_DIR = re.compile(rf"(?P<d>down|up|left|right){_END}")

# words the grammar writes in quotes: where one is acceptable the lexer tries it before a
# UNIT (a lower priority), and it wins even as a prefix (`5 inch` is `in` then `ch`); the
# impact laws rank below UNIT
_KEYWORDS: frozenset = frozenset()
_UNIT_OK: dict = {}


def keywords(grammar: str) -> frozenset:
    return frozenset(re.findall(r'"([A-Za-z_][A-Za-z_0-9]*)"', grammar))


def _unit_ok(u: str) -> bool:
    """A UNIT token is read as one only when no keyword is a prefix of it."""
    ok = _UNIT_OK.get(u)
    if ok is None:
        ok = _UNIT_OK[u] = not any(u.startswith(k) for k in _KEYWORDS
                                   if k not in IMPACT_LAWS)
    return ok


def parse(text: str, rest):
    """The statements of `text` (ending in "\\n"), or None (not plain: parse it whole).
    `rest(chunk, line)` parses a statement not recognised here (it may raise)."""
    global _KEYWORDS
    if not _KEYWORDS:
        from .syntax import grammar_text

        _KEYWORDS = keywords(grammar_text())
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
    out = []
    for k in range(len(heads) - 1):
        a, b = heads[k], heads[k + 1]
        try:
            out.append(_statement(lines, a, b))
        except _No:
            out.extend(rest("\n".join(lines[a:b]) + "\n", a + 1))
    return out


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
    return f(lines, a, b, s, a + 1)


def _tail(s: str, p: int) -> None:
    """Only spaces and a comment are left on the line."""
    if _TAIL.match(s, p).end() != len(s):
        raise _No


def _expr(s: str, p: int, L: int):
    """(node, end, next): a number with its unit, a reference, maybe negated, or a vector
    of two of them, at s[p:]; end is where it ends, next after the spaces."""
    if s.startswith("(", p):
        q = _SP.match(s, p + 1).end()
        x, _, q = _atom(s, q, L)
        if not s.startswith(",", q):
            raise _No
        q = _SP.match(s, q + 1).end()
        y, _, q = _atom(s, q, L)
        if not s.startswith(")", q):
            raise _No
        return VecLit(Span(L, p + 1, L, q + 2), x, y), q + 1, _SP.match(s, q + 1).end()
    return _atom(s, p, L)


def _atom(s: str, p: int, L: int):
    m = _ATOM.match(s, p)
    if m is None:
        raise _No
    neg, num, u, name, idx, mem, a1, a2, _ = m.groups()
    r = m.regs  # every group's place at once
    z = r[9][0]
    if num is not None:
        st = r[2][0]
        if u is None:
            node = Num(Span(L, st + 1, L, z + 1), float(num))
        else:
            if u not in _UNIT_OK and not _unit_ok(u) or not _UNIT_OK[u]:
                raise _No
            node = Num(Span(L, st + 1, L, z + 1), float(num), u,
                       Span(L, r[3][0] + 1, L, z + 1))
    else:
        at = () if a1 is None else (a1,) if a2 is None else (a1, a2)
        node = Ref(Span(L, r[4][0] + 1, L, z + 1), name,
                   None if idx is None else idx.replace(" ", ""), mem, at)
    if neg is not None:
        node = Neg(Span(L, p + 1, L, z + 1), node)
    return node, z, r[0][1]


def _pref(s: str, p: int, L: int):
    """A point reference (`A`, `rod.A`, `rod.end(+)`): (node, end, next)."""
    m = _PREF.match(s, p)
    if m is None:
        raise _No
    z = m.start("z")
    sg = m.group("sg")
    if sg is not None:
        return PointRef(Span(L, p + 1, L, z + 1), m.group("n"), end=sg), z, m.end()
    mem = m.group("m")
    if mem == "end":
        raise _No  # the keyword `end`, without its `(+)`
    return PointRef(Span(L, p + 1, L, z + 1), m.group("n"), mem), z, m.end()


def _end(b: int) -> int:
    return b + 1  # a statement's span ends at column 1 of the line after its last


# ---- statements ---------------------------------------------------------------------------
def _body(lines, a, b, s, L):
    m = _BODY.match(s)
    if m is None or m.group("k") == "composite" or _block(lines, a, b):
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
            v, z, p = _expr(s, ma.end(), L)
            args.append(Arg(Span(L, ma.start() + 1, L, z + 1), ma.group("n"), v))
            if s.startswith(",", p):
                p = _SP.match(s, p + 1).end()
            elif s.startswith(")", p):
                p += 1
                break
            else:
                raise _No
    _tail(s, p)
    shape = Shape(Span(L, m.start("k") + 1, L, p + 1), m.group("k"), tuple(args))
    return BodyDecl(Span(L, 1, _end(b), 1), m.group("n"), (shape,), False)


def _let(lines, a, b, s, L):
    m = _LET.match(s)
    if m is None or _block(lines, a, b):
        raise _No
    v, _, p = _expr(s, m.end(), L)
    _tail(s, p)
    return Let(Span(L, 1, _end(b), 1), m.group("n"), v)


def _items(s: str, p: int, L: int, out: list) -> None:
    """A comma list of state items from s[p:] to the line's end."""
    while True:
        m = _ITEM.match(s, p)
        if m is None:
            raise _No
        rel = m.group("rel")
        st = m.start()
        if rel is not None:
            v, z, p = _expr(s, m.end(), L)
            out.append(Given(Span(L, st + 1, L, z + 1), m.group("n"), m.group("q"),
                             Span(L, st + 1, L, m.start("qz") + 1), v, rel))
        elif m.group("s") is not None:
            out.append(RollsIn(Span(L, st + 1, L, m.start("sz") + 1), m.group("n"),
                               m.group("s")))
            p = m.end()
        else:
            out.append(AtRest(Span(L, st + 1, L, m.start("rz") + 1), m.group("n")))
            p = m.end()
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
    for i in _block(lines, a, b):
        x = lines[i]
        _items(x, len(x) - len(x.lstrip(" ")), i + 1, items)
    label = m.group("s")
    return StateDecl(Span(L, 1, _end(b), 1), m.group("id"),
                     None if label is None else label[1:-1], tuple(items))


def _transition(lines, a, b, s, L):
    m = _TRANS.match(s)
    if m is None:
        raise _No
    _tail(s, m.end())
    block = _block(lines, a, b)
    if bool(block) != (m.group("c") is not None):
        raise _No
    clauses = []
    for i in block:
        x = lines[i]
        clauses.append(_clause(x, len(x) - len(x.lstrip(" ")), i + 1))
    return Transition(Span(L, 1, _end(b), 1), m.group("k"), m.group("a"), m.group("b"),
                      tuple(clauses), Span(L, m.start("a") + 1, L, m.end("a") + 1),
                      Span(L, m.start("b") + 1, L, m.end("b") + 1))


def _clause(s: str, p: int, L: int):
    """One clause of a transition's block: a contact, `B stops`, `B rolls on S`,
    `free B`."""
    w = _WORD.match(s, p)
    word = w and w.group()
    if word == "contact":  # (a clause starts with a name or a keyword: a whole word)
        m = _CONTACT.match(s, p)
        label = m.group("l")
        pa, _, q = _pref(s, m.end(), L)
        w = _WITH.match(s, q)
        if w is None:
            raise _No
        pb, z, q = _pref(s, w.end(), L)
        if pb.name == "ground":
            if pb.member is not None or pb.end is not None:
                raise _No
            pb = None
        normal, props = None, []
        nm = _NORMAL.match(s, q)
        if nm is not None:
            normal, z, q = _expr(s, nm.end(), L)
        if s.startswith(":", q):
            q = _SP.match(s, q + 1).end()
            while True:
                pm = _PROP.match(s, q)
                if pm is None:
                    raise _No
                k = pm.group("k")
                st = pm.start()
                if k in ("smooth", "rough"):
                    z, q = pm.start("z"), pm.end()
                    props.append(Prop(Span(L, st + 1, L, z + 1), k))
                elif k == "restitution" and s.startswith("?", pm.end()):
                    z = pm.end() + 1
                    q = _SP.match(s, z).end()
                    props.append(Prop(Span(L, st + 1, L, z + 1), "restitution?"))
                else:
                    v, z, q = _expr(s, pm.end(), L)
                    if k == "restitution":
                        law = "newton"
                        if v.__class__ is _NumClass and v.unit in IMPACT_LAWS:
                            law = v.unit
                            v = Num(v.span, v.value)
                        props.append(Prop(Span(L, st + 1, L, z + 1), k, v, law))
                    else:
                        props.append(Prop(Span(L, st + 1, L, z + 1), k, v))
                if s.startswith(",", q):
                    q = _SP.match(s, q + 1).end()
                else:
                    break
        _tail(s, q)
        return Contact(Span(L, p + 1, L, z + 1), label, pa, pb, normal, tuple(props))
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
        st = p
        mn = _NAMED.match(s, p)
        name = None
        if mn is not None:
            name, p = mn.group("n"), mn.end()
        v, z, p = _expr(s, p, L)
        unit = uspan = None
        mi = _IN.match(s, p)
        if mi is not None:
            if v.__class__ is _NumClass and v.unit is None or not _unit_ok(mi.group("u")):
                raise _No  # `2 in mm` is one quantity
            z = mi.start("z")
            unit, uspan, p = mi.group("u"), Span(L, mi.start("u") + 1, L, z + 1), mi.end()
        items.append(FindItem(Span(L, st + 1, L, z + 1), name, v, unit, uspan))
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
    if _block(lines, a, b):
        raise _No
    v, _, p = _expr(s, m.end(), L)
    d = _DIR.match(s, p)
    if d is None:
        raise _No
    _tail(s, d.end())
    return Gravity(Span(L, 1, _end(b), 1), v, d.group("d"), None)


_FORMS = {"body": _body, "let": _let, "state": _state, "impact": _transition,
          "interval": _transition, "energy": _transition, "find": _find,
          "problem": _problem, "gravity": _gravity}
