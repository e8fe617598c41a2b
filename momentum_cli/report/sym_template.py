"""Report stage: an equation's symbolic line as one template per kind of equation.

In: a shape's compiled symbolic printer (printer.py) and the shape's tokens. Out: a
printer with its signature that, for a shape of sums, products and leaves only, prints
the line by joining the leaves' names into literal text made once per shape and set of
numbers (the shape's `Const` values): a big scene's rows of one kind (10^4 restitutions,
10^4 momentum rows) differ only in their names, so the tree's layout is walked once per
kind, not once per row. The text is the printer's own, made by running it on stand-in
names; where a name could change what the printer decides (a term whose text would
begin with '-', two neighbouring factors that could print alike and merge as x^2), the
row is checked and, if in doubt, printed by the printer itself: the same strings.
"""
from __future__ import annotations

import re

from ..expr import _ADD, _ATOM, _MUL
from ..numbers import fmt_num

ENABLED = True  # tests turn it off to compare with the compiled printers
TEMPLATES_PER_SHAPE = 8  # sets of numbers templated per shape (more: the printer alone)
_SLOT = re.compile("\x00([0-9]+)\x00")


class _StandIn:
    """A leaf the printer reads only by name."""

    __slots__ = ("name",)

    def __init__(self, name: str):
        self.name = name


def _tree(key: tuple, c, v, k, addt, mult, eq, expr):
    """The shape's nodes: ("c" | "n", leaf index) or (+ or *, children), per side; None
    if the shape holds anything but sums and products of two or more, and leaves."""
    pos = [1 if key[0] == expr else 0]
    slot = [0]

    def node():
        tok = key[pos[0]]
        pos[0] += 1
        if tok in (c, v, k):
            i = slot[0]
            slot[0] += 1
            return ("c" if tok == c else "n", i)
        if tok in (addt, mult):
            size = key[pos[0]]
            pos[0] += 1
            if size < 2:
                raise ValueError
            return ("+" if tok == addt else "*", [node() for _ in range(size)])
        raise ValueError  # a power in a denominator, a function, any other node

    try:
        if key[0] == expr:
            sides = [node()]
        else:
            lhs = node()
            if key[pos[0]] != eq:
                return None
            pos[0] += 1
            sides = [lhs, node()]
    except (ValueError, IndexError):
        return None
    return sides if pos[0] == len(key) else None


def _names(n) -> list:
    """The leaf indices of the names under node `n`."""
    if n[0] == "n":
        return [n[1]]
    if n[0] == "c":
        return []
    return [i for x in n[1] for i in _names(x)]


class _Checks:
    """What a row's names must satisfy for the template's text to be the printer's."""

    def __init__(self, consts: dict):
        self.consts = consts  # leaf index -> its value (this template's numbers)
        self.dash: list = []  # names that must not begin with '-'
        self.differ: list = []  # pairs of names that must differ
        self.not_text: list = []  # (name, literal text) that must differ
        self.plain: list = []  # names that must hold none of " *^(": unlike any compound,
        # a number in parentheses or a merged x^2

    def const_text(self, i: int) -> str:
        return fmt_num(self.consts[i], 6)

    def first(self, n):
        """("slot", i) if `n`'s text begins with name i, else ("fixed", None)."""
        if n[0] == "n":
            return ("slot", n[1])
        if n[0] == "c":
            return ("fixed", None)
        if n[0] == "+":
            return self.first(n[1][0])
        items, sign = self.items(n)
        if sign:
            return ("fixed", None)
        x = items[0]
        return ("fixed", None) if self.prec(x) < _MUL or x[0] == "-c" else self.first(x)

    def items(self, n):
        """A product's factors as the printer lists them, and whether it moves a sign out
        (a first factor that is a negative number; -1 itself left out)."""
        fs = n[1]
        if fs[0][0] == "c":
            x = self.consts[fs[0][1]]
            if x < 0:
                if x == -1.0:
                    return fs[1:], True
                return [("-c", fs[0][1])] + fs[1:], True
        return fs, False

    def prec(self, n) -> int:
        if n[0] == "n":
            return _ATOM
        if n[0] == "c":
            return _ADD if self.const_text(n[1])[:1] == "-" else _ATOM
        if n[0] == "-c":
            t = fmt_num(-self.consts[n[1]], 6)
            return _ADD if t[:1] == "-" else _ATOM
        if n[0] == "+":
            return _ADD
        return _ADD if self.items(n)[1] else _MUL

    def visit(self, n) -> bool:
        """Collect `n`'s checks; False where the template cannot be made safe."""
        if n[0] in ("n", "c", "-c"):
            return True
        xs = n[1]
        if n[0] == "+":
            for x in xs[1:]:  # a later term whose text begins with a name: not with '-'
                kind, i = self.first(x)
                if kind == "slot":
                    self.dash.append(i)
            return all(self.visit(x) for x in xs)
        items, _sign = self.items(n)
        for a, b in zip(items, items[1:]):  # neighbours the printer compares (x*x: x^2)
            na, nb = _names(a) if a[0] != "-c" else [], _names(b) if b[0] != "-c" else []
            if not na and not nb:
                continue  # numbers only: decided by this template's numbers
            if a[0] == "n" and b[0] == "n":
                self.differ.append((a[1], b[1]))
            elif a[0] == "n" or b[0] == "n":
                name, other = (a, b) if a[0] == "n" else (b, a)
                self.plain.append(name[1])  # unlike any text in parentheses or merged
                # (x^2), and unlike a number's text as the product shows it
                if other[0] in ("c", "-c") and self.prec(other) >= _MUL:
                    self.not_text.append((name[1], self.const_text(other[1])
                                          if other[0] == "c" else
                                          fmt_num(-self.consts[other[1]], 6)))
                # (a compound's text holds one of " *^(": sizes 2 and up)
            else:
                return False  # two compounds with names (or one with numbers): the printer
        return all(self.visit(x) for x in items if x[0] != "-c")


def _source(text: str, checks: _Checks, names: list, prec: int | None) -> str:
    """The template function's source: read the names, check them, join the text."""
    parts = _SLOT.split(text)
    pieces = []
    for j, p in enumerate(parts):
        if j % 2:
            pieces.append(f"_{int(p)}")
        elif p:
            pieces.append(repr(p))
    code = ["def template(L):"]
    code += [f"    _{i} = L[{i}].name" for i in names]
    for i in checks.dash:
        code.append(f"    if _{i}[:1] == '-': return None")
    for i, j in checks.differ:
        code.append(f"    if _{i} == _{j}: return None")
    for i, t in checks.not_text:
        code.append(f"    if _{i} == {t!r}: return None")
    for i in checks.plain:
        code.append(f"    if ' ' in _{i} or '*' in _{i} or '^' in _{i} or '(' in _{i}: "
                    "return None")
    joined = f"''.join(({', '.join(pieces)},))"
    code.append(f"    return {joined}" if prec is None else f"    return {joined}, {prec!r}")
    return "\n".join(code)


def _template(sides, sym, leaves: list, kinds: list):
    """The template of this shape for the numbers of `leaves`, or False."""
    consts = {i: leaves[i].value for i, kd in enumerate(kinds) if kd == "c"}
    checks = _Checks(consts)
    if not all(checks.visit(s) for s in sides):
        return False
    names = [i for i, kd in enumerate(kinds) if kd == "n"]
    stand = [leaves[i] if kd == "c" else _StandIn(f"\x00{i}\x00")
             for i, kd in enumerate(kinds)]
    text = sym(stand, None, None, 6, {})
    prec = None
    if type(text) is tuple:  # a term's printer (a term of a long sum): (text, precedence)
        text, prec = text
    if "\x00" in _SLOT.sub("", text):
        return False
    env: dict = {}
    exec(_source(text, checks, names, prec), env)  # noqa: S102 - our own generated code
    return env["template"]


def templated(key: tuple, sym, toks: tuple):
    """`sym` (a shape's symbolic printer: `printer(L, values, keep, sig, F)`) printing
    from per-kind templates where the shape allows; `sym` itself otherwise. `toks`: the
    printer module's tokens (C, V, K, ADDT, MULT, EQ, EXPR)."""
    sides = _tree(key, *toks)
    if sides is None or not ENABLED:
        return sym
    kinds: list = []

    def leaf_kinds(n):
        if n[0] in ("c", "n"):
            kinds.append(n[0])
        else:
            for x in n[1]:
                leaf_kinds(x)
    for s in sides:
        leaf_kinds(s)
    consts = [i for i, kd in enumerate(kinds) if kd == "c"]
    made: dict = {}  # the numbers' values -> template (False: printed by `sym`)

    def make(L, numbers):
        t = _template(sides, sym, L, kinds) if len(made) < TEMPLATES_PER_SHAPE else False
        if len(made) < TEMPLATES_PER_SHAPE:
            made[numbers] = t
        return t

    src = ["def printer(L, values, keep, sig, F):",
           "    if sig == 6:",
           f"        n = ({''.join(f'L[{i}].value, ' for i in consts)})",
           "        t = get(n)",
           "        if t is None:",
           "            t = make(L, n)",
           "        if t:",
           "            s = t(L)",
           "            if s is not None:",
           "                return s",
           "    return sym(L, values, keep, sig, F)"]
    env = dict(get=made.get, make=make, sym=sym)
    exec("\n".join(src), env)  # noqa: S102 - our own generated code
    return env["printer"]
