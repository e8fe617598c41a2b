"""Report stage: the checks' tree walks compiled once per shape of tree.

In: a tree of sums, products, powers, functions and leaves (a residual, a kinetic energy)
and the solved values. Out: `expr.evaluate(e)` and `model.value_and_magnitude(e)` by
straight-line code made for the tree's shape (on its second sight), which checks the
shape as it reads the leaves and performs the walks' float operations in their order:
the same floats. Anything else (a shape met once, a zero or non-float number, a node the
code does not know, any exception) returns None and the caller walks the tree.
"""
from __future__ import annotations

import math

from ..expr import FUNCS, Add, Const, Fn, Known, Mul, Pow, Var
from ..shape_codes import compiled_after

ENABLED = True  # tests turn it off to compare with the walks
COMPILE_AFTER = 1  # a shape is compiled the second time it is met
LIMIT = 256  # compiled shapes kept
MAX_NODES = 200  # a larger tree (a scene's energy over 10^4 bodies) is walked

_FNS: dict = {}  # (what, shape) -> compiled function
_SEEN: dict = {}  # (what, shape) -> times met
_LAST: dict = {}  # (what, top node type, size) -> [shape met last, what came next, shapes]


class _Big(Exception):
    pass


def _key(e, out: list) -> None:
    """The shape of `e` in pre-order: a leaf's kind, a node's type and size, a power's
    exponent and a function's name (what the code is made from)."""
    if len(out) > MAX_NODES:
        raise _Big
    t = type(e)
    if t is Var:
        out.append("v")
    elif t is Const or t is Known:
        out.append("c" if t is Const else "k")
    elif t is Mul and _zero(e):
        out.append("z")  # 0, its factors not read (as the walks stop there)
    elif t is Add or t is Mul:
        xs = e.terms if t is Add else e.factors
        out.append(("+" if t is Add else "*", len(xs)))
        for x in xs:
            _key(x, out)
    elif t is Pow:
        p = e.exp
        if (type(p) is not float and type(p) is not int) or p != p:
            raise _Big  # a traced or odd exponent: walked (the key holds plain numbers)
        out.append(("^", type(p), p))
        _key(e.base, out)
    elif t is Fn and e.name in FUNCS:
        out.append(("f", e.name))
        _key(e.arg, out)
    else:
        raise _Big


def _zero(m) -> bool:
    """Whether a product has a zero number factor (the walks return 0 for it)."""
    for f in m.factors:
        if (type(f) is Const or type(f) is Known) and f.value == 0.0:
            return True
    return False


class _Gen:
    """The source of one function `f(e, values)`: the shape checks, then the sums."""

    def __init__(self, key: tuple):
        self.key, self.pos = key, 0
        self.check: list[str] = []
        self.body: list[str] = []
        self.env: dict = dict(Add=Add, Mul=Mul, Pow=Pow, Fn=Fn, Var=Var, Const=Const,
                              Known=Known, fsum=math.fsum, float=float, zero=_zero)
        self.n = 0

    def name(self, p: str) -> str:
        self.n += 1
        return f"{p}{self.n}"

    def tmp(self, expr: str) -> str:
        t = self.name("t")
        self.body.append(f"    {t} = {expr}")
        return t

    def node(self, x: str, in_mul: bool):
        """Check the node at `x` against the key; a tree of what it is: ("v"|"c", local)
        or (kind, kids, extra)."""
        tok = self.key[self.pos]
        self.pos += 1
        c = self.check
        if tok == "v":
            c.append(f"    if type({x}) is not Var: return None")
            loc = self.name("x")
            self.body.append(f"    {loc} = values[{x}.name]")
            return ("leaf", loc)
        if tok in ("c", "k"):
            cls = "Const" if tok == "c" else "Known"
            loc = self.name("c")
            c.append(f"    if type({x}) is not {cls}: return None")
            c.append(f"    {loc} = {x}.value")
            # a float only (a traced number is walked); in a product, never 0 (the walks
            # stop at a zero factor without reading its partners)
            c.append(f"    if type({loc}) is not float: return None")
            if in_mul:
                c.append(f"    if {loc} == 0.0: return None")
            return ("leaf", loc)
        if tok == "z":
            c.append(f"    if type({x}) is not Mul or not zero({x}): return None")
            return ("leaf", "0.0")
        kind = tok[0]
        if kind in ("+", "*"):
            cls, attr = ("Add", "terms") if kind == "+" else ("Mul", "factors")
            xs = self.name("n")
            c.append(f"    if type({x}) is not {cls}: return None")
            c.append(f"    {xs} = {x}.{attr}")
            c.append(f"    if len({xs}) != {tok[1]}: return None")
            kids = []
            for i in range(tok[1]):
                y = self.name("n")
                c.append(f"    {y} = {xs}[{i}]")
                kids.append(self.node(y, kind == "*"))
            return (kind, kids, None)
        if kind == "^":
            p = self.name("P")
            self.env[p] = tok[2]
            c.append(f"    if type({x}) is not Pow or type({x}.exp) is not {p}t "
                     f"or {x}.exp != {p}: return None")
            self.env[p + "t"] = tok[1]
            y = self.name("n")
            c.append(f"    {y} = {x}.base")
            return ("^", [self.node(y, False)], p)
        fn = self.name("F")
        self.env[fn] = FUNCS[tok[1]]
        c.append(f"    if type({x}) is not Fn or {x}.name != {tok[1]!r}: return None")
        y = self.name("n")
        c.append(f"    {y} = {x}.arg")
        return ("f", [self.node(y, False)], fn)

    def val(self, t) -> str:
        """`expr.evaluate` of a node."""
        if t[0] == "leaf":
            return t[1]
        kind, kids, extra = t
        if kind == "+":
            return self.tmp("fsum([" + ", ".join(self.val(k) for k in kids) + "])")
        if kind == "*":
            return self.tmp("1.0" + "".join(" * " + self.val(k) for k in kids))
        if kind == "^":
            return self.tmp(f"{self.val(kids[0])} ** {extra}")
        return self.tmp(f"float({extra}({self.val(kids[0])}))")

    def vm(self, t) -> tuple[str, str]:
        """`model.value_and_magnitude` of a node: (value, magnitude)."""
        if t[0] == "leaf":
            return t[1], f"abs({t[1]})"
        kind, kids, _ = t
        if kind == "+":
            parts = [self.vm(k) for k in kids]
            return (self.tmp("fsum([" + ", ".join(v for v, _m in parts) + "])"),
                    self.tmp("sum([" + ", ".join(m for _v, m in parts) + "])"))
        if kind == "*" and sum(1 for k in kids if k[0] == "+") == 1:
            r, k_, m = "1.0", "1.0", None
            for x in kids:
                if x[0] == "+":
                    v, m = self.vm(x)
                else:
                    v = self.val(x)
                    k_ += " * " + v
                r += " * " + v
            return self.tmp(r), self.tmp(f"abs({k_}) * {m}")
        v = self.val(t)
        return v, f"abs({v})"

    def source(self, what: str) -> str:
        root = self.node("e", False)
        assert self.pos == len(self.key)
        if what == "val":
            out = self.val(root)
        else:
            v, m = self.vm(root)
            out = f"({v}, {m})"
        return "def f(e, values):\n" + "\n".join(self.check + self.body) + \
            f"\n    return {out}\n"


def _compile_key(k: tuple):
    """`_compile` of a table key (what, shape)."""
    return _compile(k[0], k[1])


def _compile(what: str, key: tuple):
    g = _Gen(key)
    src = g.source(what)
    exec(compile(src, "<treecode>", "exec"), g.env)  # noqa: S102 - our own generated code
    return g.env["f"]


def _run(what: str, e, values):
    """The compiled `what` of `e`, or None (walk it)."""
    return _run_code(what, e, values)[0]


def caller(what: str):
    """A function (e, values) -> `_run(what, e, values)`, the same results, for a loop over
    many like trees: the code of the shape that followed the last tree's shape the time
    before is tried first, with no other lookup (a long sequence repeats its shapes in
    order); else `_run`'s lookups."""
    after: dict = {}  # the code that read a tree -> the code that read the next one
    last: list = [None]

    def run(e, values):
        f = after.get(last[0])
        if f is not None:
            try:
                got = f(e, values)
            except Exception:  # noqa: BLE001 - as `_call`: `_run` and the walk decide
                got = None
            if got is not None:
                last[0] = f
                return got
        got, f = _run_code(what, e, values)
        if f is not None:
            if len(after) > 64:
                after.clear()
            after[last[0]] = f
            last[0] = f
        return got
    return run


def _run_code(what: str, e, values):
    """(`_run(what, e, values)`, the code that gave it or None)."""
    if not ENABLED:
        return None, None
    t = type(e)
    top = (what, t, len(e.terms) if t is Add else len(e.factors) if t is Mul else -1)
    st = _LAST.get(top)
    if st is not None:  # [shape met last, shape -> the one met after it, shapes]
        prev, after, fs = st
        guess = after.get(prev)
        if guess is not None:
            got = _call(guess, e, values)
            if got is not None:
                st[0] = guess
                return got, guess
        for f in fs:
            if f is not guess:
                got = _call(f, e, values)
                if got is not None:
                    after[prev] = st[0] = f
                    return got, f
    key: list = []
    try:
        _key(e, key)
    except (_Big, RecursionError):
        return None, None
    if len(key) > MAX_NODES:
        return None, None
    k = (what, tuple(key))
    f = _FNS.get(k)
    if f is None:
        f = compiled_after(_FNS, _SEEN, k, _compile_key, COMPILE_AFTER, LIMIT,
                           forget=_LAST.clear)
        if f is None:
            return None, None
    st = _LAST.get(top)  # a few kept per top, the next guessed from the last
    if st is None:
        st = _LAST[top] = [None, {}, []]
    if f not in st[2]:
        st[2] = [f] + st[2][:3]
        st[1] = {a: b for a, b in st[1].items() if a in st[2] and b in st[2]}
    st[1][st[0]] = f
    st[0] = f
    got = _call(f, e, values)
    return got, (f if got is not None else None)


def _call(f, e, values):
    """`f(e, values)`, None where it fails (the walk then raises what it raises: it
    may meet a zero division before the missing name the code reads first)."""
    try:
        return f(e, values)
    except Exception:  # noqa: BLE001 - any failure: the walk decides
        return None


def evaluate(e, values):
    """`expr.evaluate(e, values)` by the shape's code, or None (walk it)."""
    return _run("val", e, values)


def value_and_magnitude(e, values):
    """`model.value_and_magnitude(e, values)` by the shape's code, or None (walk it)."""
    return _run("vm", e, values)
