"""All first derivatives of an expression at a point, in one pass (reverse mode).

Stage: a helper of the derivatives (sensitivity.py, traced_partials.py). In: an `expr.E`
tree and values for its unknowns. Out: d e / d name for every unknown, the numbers that
`evaluate(diff(e, name), values)` gives, from one sweep of the tree instead of one `diff`
per unknown (a chain's kinetic energy has thousands of unknowns: quadratic the other way).
"""
from __future__ import annotations

import math

from .expr import FUNCS, Add, Const, Fn, Known, Mul, Pow, Var

_DERIV = {
    "sin": math.cos, "cos": lambda a: -math.sin(a), "tan": lambda a: math.cos(a) ** -2.0,
    "asin": lambda a: (1.0 - a * a) ** -0.5, "acos": lambda a: -(1.0 - a * a) ** -0.5,
    "atan": lambda a: 1.0 / (1.0 + a * a), "exp": math.exp, "ln": lambda a: 1.0 / a,
    "log": lambda a: 1.0 / a, "abs": lambda a: a / abs(a),
}


def _hidden(e) -> bool:
    """A product with a known zero factor: zero, its partners unseen (as `evaluate`)."""
    return any((type(f) is Const or type(f) is Known) and f.value == 0.0 for f in e.factors)


def _children(e) -> tuple:
    t = type(e)
    if t is Add:
        return e.terms
    if t is Mul:
        return () if _hidden(e) else e.factors
    if t is Pow:
        return (e.base,)
    if t is Fn:
        return (e.arg,)
    return ()


def _order(e) -> list:
    """The nodes of `e`, each once, every node after its children (iterative: deep
    trees do not hit the recursion limit)."""
    out: list = []
    seen: set = set()
    stack = [(e, False)]
    while stack:
        node, done = stack.pop()
        if done:
            out.append(node)
            continue
        if id(node) in seen:
            continue
        seen.add(id(node))
        stack.append((node, True))
        stack.extend((c, False) for c in _children(node))
    return out


def gradient(e, values: dict) -> dict[str, float]:
    """d e / d v at `values` for every unknown v the value of `e` depends on (KeyError
    if one has no value)."""
    order = _order(e)
    val: dict = {}
    for n in order:
        t = type(n)
        if t is Const or t is Known:
            v = float(n.value)
        elif t is Var:
            v = values[n.name]
        elif t is Add:
            v = math.fsum(val[id(x)] for x in n.terms)
        elif t is Mul:
            v = 0.0 if _hidden(n) else math.prod(val[id(x)] for x in n.factors)
        elif t is Pow:
            v = val[id(n.base)] ** n.exp
        else:
            v = float(FUNCS[n.name](val[id(n.arg)]))
        val[id(n)] = v
    adj: dict = {id(e): 1.0}
    out: dict[str, float] = {}
    for n in reversed(order):
        a = adj.get(id(n))
        if not a:
            continue
        t = type(n)
        if t is Var:
            out[n.name] = out.get(n.name, 0.0) + a
        elif t is Add:
            for x in n.terms:
                adj[id(x)] = adj.get(id(x), 0.0) + a
        elif t is Mul:
            if _hidden(n):
                continue
            fs = n.factors
            vs = [val[id(x)] for x in fs]
            # the product of the others: prefix and suffix products (a zero is no problem)
            pre = [1.0] * (len(fs) + 1)
            for i, v in enumerate(vs):
                pre[i + 1] = pre[i] * v
            suf = 1.0
            for i in range(len(fs) - 1, -1, -1):
                x = fs[i]
                if type(x) is not Const and type(x) is not Known:
                    adj[id(x)] = adj.get(id(x), 0.0) + a * pre[i] * suf
                suf *= vs[i]
        elif t is Pow:
            b = val[id(n.base)]
            adj[id(n.base)] = adj.get(id(n.base), 0.0) + a * n.exp * b ** (n.exp - 1.0)
        elif t is Fn:
            x = val[id(n.arg)]
            adj[id(n.arg)] = adj.get(id(n.arg), 0.0) + a * _DERIV[n.name](x)
    return out
