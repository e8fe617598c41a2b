"""Solve stage helper: expression trees lowered to one Python function, for Newton.

In: `E` trees (a block's residuals, its Jacobian). Out: a function of the values dict
returning their values, computed by the very operations `expr.evaluate` performs
(math.fsum of each sum, products from 1.0 left to right, `**`, the same math
functions), so every float is bit-identical; a tree walk per evaluation is replaced
by one call. Trees too deep for Python's compiler are not lowered (None). The source
names constants, never prints them, so the same shape of block (a variant of a file in
a batch, a regime tried again) reuses its compiled code.
"""
from __future__ import annotations

import math

from .expr import FUNCS, Add, Const, Fn, Known, Mul, Pow, Var

MAX_DEPTH = 60  # nesting Python's parser and compiler take comfortably
CACHE_SIZE = 256  # compiled sources kept (compile() is ~0.5 ms for a small block)
CACHE_CHARS = 20_000  # longer sources (large blocks) are compiled each time
_CODE: dict = {}


class _TooDeep(Exception):
    pass


class _NotFloat(Exception):
    pass


class _Writer:
    """Python source for trees; constants and names are bound, never printed."""

    def __init__(self):
        self.ns: dict = {"fsum": math.fsum, "float": float}
        self.ids: dict = {}

    def bind(self, obj, prefix: str) -> str:
        key = (prefix, id(obj))
        name = self.ids.get(key)
        if name is None:
            name = f"{prefix}{len(self.ids)}"
            self.ids[key] = name
            self.ns[name] = obj
        return name

    def expr(self, e, depth: int = 0) -> str:
        if depth > MAX_DEPTH:
            raise _TooDeep
        t = type(e)
        if t is Const or t is Known:
            if type(e.value) is not float:
                raise _NotFloat  # a traced or exact number: evaluate's own arithmetic
            return self.bind(e.value, "c")
        if t is Var:
            return f"v[{self.bind(e.name, 'n')}]"
        if t is Add:
            return "fsum((" + "".join(self.expr(x, depth + 1) + ", " for x in e.terms) + "))"
        if t is Mul:
            # a zero known factor hides its partners (evaluate returns 0.0 at once)
            if any((type(f) is Known or type(f) is Const) and f.value == 0.0
                   for f in e.factors):
                return "0.0"
            return "(1.0" + "".join(" * " + self.expr(f, depth + 1) for f in e.factors) + ")"
        if t is Pow:
            return f"({self.expr(e.base, depth + 1)} ** {self.bind(e.exp, 'c')})"
        if t is Fn:
            return f"float({self.bind(FUNCS[e.name], 'f')}({self.expr(e.arg, depth + 1)}))"
        raise TypeError(f"not an expression node: {t.__name__}")


def lower(rows):
    """A function v -> [[value of each tree] for each row] (rows: lists of trees), or
    None when a tree is too deep to lower or holds a number other than a float (use
    `expr.evaluate` then)."""
    w = _Writer()
    try:
        body = ", ".join("[" + ", ".join(w.expr(e) for e in row) + "]" for row in rows)
    except (_TooDeep, _NotFloat, RecursionError):
        return None
    code = f"def _lowered(v):\n    return [{body}]\n"
    try:
        exec(_compiled(code), w.ns)
    except (RecursionError, MemoryError, SyntaxError):
        return None
    return w.ns["_lowered"]


def _compiled(code: str):
    """compile(code), from the cache when this source was compiled before."""
    obj = _CODE.get(code)
    if obj is None:
        obj = compile(code, "<lowered>", "exec")
        if len(code) <= CACHE_CHARS:
            if len(_CODE) >= CACHE_SIZE:
                _CODE.clear()
            _CODE[code] = obj
    return obj
