"""Expression trees compiled to vectorised numpy functions, once per sweep.

In: `expr.E` trees whose numbers may be `trace.Traced` (functions of the parameters)
and whose unknowns are solved arrays. Out: Python source with numpy operations,
compiled by `compile()` once; the function takes the parameters' and the solved
unknowns' arrays and returns arrays over all variants (no walk per variant).
Shared subtrees (by identity) are computed once.
"""
from __future__ import annotations

import numpy as np

from ..expr import Add, Const, Fn, Known, Mul, Pow, Var
from .trace import PREFIX, Traced

NP_FUNCS = {"sin": "np.sin", "cos": "np.cos", "tan": "np.tan", "asin": "np.arcsin",
            "acos": "np.arccos", "atan": "np.arctan", "exp": "np.exp", "ln": "np.log",
            "log": "np.log", "abs": "np.abs"}


class Emitter:
    """Writes one function's body: temporaries for shared subtrees, names for inputs."""

    def __init__(self, params: list[str], unknowns: list[str]):
        self.pidx = {p: i for i, p in enumerate(params)}
        self.vidx = {v: i for i, v in enumerate(unknowns)}
        self.lines: list[str] = []
        self.memo: dict[int, str] = {}
        self.keep: list = []  # the nodes memoised by id stay alive
        self.count = 0

    def value(self, x: float) -> str:
        if isinstance(x, Traced):
            return self.emit(x.expr)
        x = float(x)
        if x != x:
            return "np.nan"
        if x in (np.inf, -np.inf):
            return "np.inf" if x > 0 else "(-np.inf)"
        return repr(x) if x >= 0 else f"({x!r})"

    def emit(self, e) -> str:
        """A Python expression (or temporary's name) for `e`."""
        key = id(e)
        hit = self.memo.get(key)
        if hit is not None:
            return hit
        t = type(e)
        if t is Const:
            s = self.value(e.value)
        elif t is Known:
            if e.name.startswith(PREFIX):
                s = f"p[{self.pidx[e.name[len(PREFIX):]]}]"
            else:
                s = self.value(e.value)
        elif t is Var:
            s = f"v[{self.vidx[e.name]}]"
        elif t is Add:
            s = "(" + " + ".join(self.emit(x) for x in e.terms) + ")"
        elif t is Mul:
            if any(type(f) in (Const, Known) and type(f.value) is float and f.value == 0.0
                   for f in e.factors):
                s = "0.0"  # as `expr.evaluate`: a zero factor hides its partners
            else:
                s = "(" + " * ".join(self.emit(x) for x in e.factors) + ")"
        elif t is Pow:
            b = self.emit(e.base)
            s = f"np.sqrt({b})" if e.exp == 0.5 else \
                (f"(1.0 / {b})" if e.exp == -1.0 else
                 (f"({b} * {b})" if e.exp == 2.0 else f"np.power({b}, {e.exp!r})"))
        elif t is Fn:
            s = f"{NP_FUNCS[e.name]}({self.emit(e.arg)})"
        else:
            raise TypeError(f"cannot compile {e!r}")
        if t in (Add, Mul, Pow, Fn) and len(s) > 12:
            name = f"t{self.count}"
            self.count += 1
            self.lines.append(f"    {name} = {s}")
            self.keep.append(e)
            s = name
        self.memo[key] = s
        return s


def build(source_lines: list[str], name: str = "kernel"):
    """Compile the generated source once; the function it defines."""
    src = "\n".join(source_lines) + "\n"
    ns = {"np": np}
    exec(compile(src, f"<sweep {name}>", "exec"), ns)  # noqa: S102 - generated here
    return ns[name]


def function(exprs: list, params: list[str], unknowns: list[str], name: str = "kernel"):
    """f(p, v) -> list of arrays (or floats), one per expression."""
    em = Emitter(params, unknowns)
    outs = [em.emit(e) for e in exprs]
    lines = [f"def {name}(p, v):"] + em.lines + [f"    return [{', '.join(outs)}]"]
    return build(lines, name)
