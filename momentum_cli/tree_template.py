"""Compile helper: expression trees built once per kind, replayed with new leaves.

In: a builder (the folding code itself: mul, add, V2.dot) and a kind key (the numbers its
folding depends on). Out: a generated function of the leaves making the builder's nodes
(fresh where it makes fresh ones, the same shared objects such as ZERO), without its calls
(each node by object.__new__ and its slots, not its class's __init__).
"""
from __future__ import annotations

from .expr import V2, Add, Const, Fn, Known, Mul, Pow, Var

_CACHE: dict = {}  # kind key -> generated function (or None: the builder cannot be replayed)
_LIMIT = 512  # kinds remembered (a scene with thousands of distinct normals: no template)
_FOLDED = (Const, Add, Mul)
ENABLED = True  # tests switch it off to compare with the builders' own nodes


def plain_leaves(*leaves) -> bool:
    """Whether the leaves fold like the builder's stand-in Vars (no constant, sum or
    product: add and mul fold only those). Callers check it before a replay."""
    for x in leaves:
        if type(x) in _FOLDED:
            return False
    return True


def template(key, builder, nargs: int, *args):
    """The replay of `builder` (a function of `nargs` leaves; or, with `args`, of what
    `builder(*args)` returns: made only when the kind is new) for kind `key`; None when
    it cannot be replayed (then call the builder itself)."""
    if not ENABLED:
        return None
    hit = _CACHE.get(key, _CACHE)
    if hit is not _CACHE:
        return hit
    f = _generate(builder(*args) if args else builder, nargs)
    if len(_CACHE) < _LIMIT:
        _CACHE[key] = f
    return f


class _Gen:
    def __init__(self, args, shared):
        self.args = {id(a): f"a{k}" for k, a in enumerate(args)}
        self.shared = shared  # id -> object made by both runs: referenced, not rebuilt
        self.consts: list = []  # captured objects and numbers, K[k]
        self.names: dict = {}  # id -> the local that holds it
        self.lines: list[str] = []
        self.uses: dict = {}
        self.ok = True

    def count(self, x) -> None:
        """How many times each node is referenced (a shared one gets a local)."""
        stack = [x]
        while stack:
            y = stack.pop()
            k = id(y)
            n = self.uses.get(k, 0)
            self.uses[k] = n + 1
            if n:
                continue
            for kid in _kids(y):
                stack.append(kid)

    def cap(self, obj) -> str:
        self.consts.append(obj)
        return f"K[{len(self.consts) - 1}]"

    def expr(self, x) -> str:
        k = id(x)
        hit = self.args.get(k) or self.names.get(k)
        if hit is not None:
            return hit
        if k in self.shared or x is None:
            src = "None" if x is None else self.cap(x)
        else:
            # each node made as its class's __init__ makes it, without the call (a third
            # faster): object.__new__, then its slots set in order
            t = type(x)
            if t is Const and type(x.value) is float and x.value in (0.0, 1.0, -1.0):
                src = self.cap(x)  # shared by every replay, as ZERO is (see expr.NEG_ONE)
            elif t is Const:
                return self.node(k, "Const", f".value = {self.cap(x.value)}")
            elif t is Add:
                return self.node(k, "Add",
                                 f".terms = ({''.join(self.expr(y) + ', ' for y in x.terms)})")
            elif t is Mul:
                return self.node(k, "Mul",
                                 f".factors = ({''.join(self.expr(y) + ', ' for y in x.factors)})")
            elif t is Pow:
                base = self.expr(x.base)
                return self.node(k, "Pow", f".base = {base}", f".exp = {self.cap(x.exp)}")
            elif t is Fn:
                arg = self.expr(x.arg)
                return self.node(k, "Fn", f".name = {self.cap(x.name)}", f".arg = {arg}")
            elif t is V2:
                a, b = self.expr(x.x), self.expr(x.y)
                name = self.node(k, "V2")
                self.lines.append(f"    _sx({name}, {a}); _sy({name}, {b})")
                return name
            elif t is tuple:
                src = f"({''.join(self.expr(y) + ', ' for y in x)})"
            else:  # a leaf the builder made afresh (a Var or Known of its own): not replayed
                self.ok = False
                return "None"
        if self.uses.get(k, 1) > 1:
            name = f"n{len(self.names)}"
            self.lines.append(f"    {name} = {src}")
            self.names[k] = name
            return name
        return src

    def node(self, k: int, cls: str, *sets: str) -> str:
        """A local holding a new node of class `cls` with its slots set (`.slot = src`);
        made after its kids' lines; `k`: the id of the builder's node it stands for."""
        name = f"n{len(self.lines)}_"
        self.lines.append(f"    {name} = _new({cls})" + "".join(f"; {name}{a}" for a in sets))
        self.names[k] = name
        return name


def _kids(y):
    t = type(y)
    if t is Add:
        return y.terms
    if t is Mul:
        return y.factors
    if t is Pow:
        return (y.base,)
    if t is Fn:
        return (y.arg,)
    if t is V2:
        return (y.x, y.y)
    if t is tuple:
        return y
    return ()


def _ids(x, out: dict) -> None:
    stack = [x]
    while stack:
        y = stack.pop()
        if id(y) in out:
            continue
        out[id(y)] = y
        stack.extend(_kids(y))


def _generate(builder, nargs: int):
    a1 = tuple(Var(f"\x00a{k}") for k in range(nargs))
    a2 = tuple(Var(f"\x00b{k}") for k in range(nargs))
    out1, out2 = builder(*a1), builder(*a2)
    seen1: dict = {}
    seen2: dict = {}
    _ids(out1, seen1)
    _ids(out2, seen2)
    shared = {k: v for k, v in seen1.items() if k in seen2 and type(v) is not tuple}
    g = _Gen(a1, shared)
    g.count(out1)
    body = g.expr(out1)
    if not g.ok:
        return None
    src = "def replay(" + ", ".join(f"a{k}" for k in range(nargs)) + "):\n" + \
        "".join(line + "\n" for line in g.lines) + f"    return {body}\n"
    ns = {"K": g.consts, "Const": Const, "Add": Add, "Mul": Mul, "Pow": Pow, "Fn": Fn,
          "V2": V2, "Known": Known, "_new": object.__new__, "_sx": V2.x.__set__,
          "_sy": V2.y.__set__}
    exec(compile(src, "<tree_template>", "exec"), ns)
    f = ns["replay"]
    # the replay must make what the builder makes: checked once, on a third set of leaves
    a3 = tuple(Var(f"\x00c{k}") for k in range(nargs))
    if _shape(f(*a3), a3, shared) != _shape(builder(*a3), a3, shared):
        return None
    return f


def _shape(x, args, shared) -> list:
    """The nodes in order, each a leaf's index, a shared object, a type with its numbers,
    or a reference to an earlier node of this tree (the sharing)."""
    index = {id(a): k for k, a in enumerate(args)}
    seen: dict = {}
    out: list = []
    stack = [x]
    while stack:
        y = stack.pop()
        k = id(y)
        if k in index:
            out.append(("arg", index[k]))
            continue
        if k in seen and type(y) is not tuple:
            out.append(("ref", seen[k]))
            continue
        seen[k] = len(seen)
        t = type(y)
        if k in shared:
            out.append(("shared", k))
        elif t is Const:
            out.append(("C", repr(y.value), type(y.value)))
        elif t is Pow:
            out.append(("P", repr(y.exp)))
        elif t is Fn:
            out.append(("F", y.name))
        elif t in (Known, Var):
            out.append((t.__name__, y.name, repr(getattr(y, "value", None))))
        elif y is None:
            out.append(None)
        else:
            out.append((t.__name__, len(_kids(y))))
        stack.extend(reversed(_kids(y)))
    return out
