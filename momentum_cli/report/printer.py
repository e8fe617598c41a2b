"""Report stage: an equation's two lines printed by code compiled once per shape of tree.

In: an equation (lhs, rhs), the solved values, the unknowns its block keeps by name.
Out: its symbolic line (`Equation.text()`) and its numeric line in SI and radians
(`reader.numeric_line`), the very same strings. A big scene has a handful of shapes
(the 10^4-ball chain: five), so the tree's layout is read by one short walk (its leaves
in a list) and printed by straight-line code made for that layout once it was met
COMPILE_AFTER times, with the leaves' names and numbers slotted in; a shape met once, and every node other
than a sum, a product or a leaf, are printed by the walks themselves.
"""
from __future__ import annotations

from ..expr import _ADD, _ATOM, _MUL, Add, Const, Known, Mul, Pow, Var, _den_txt, _join, _txt
from ..numbers import fmt_num
from ..shape_codes import compiled_after
from .reader import _NAME, _si_den, _si_text

ENABLED = True  # tests turn it off (or compile every shape at once) to compare the paths
# a shape is compiled once met this often: compile() of its two printers and matcher costs
# about what ~150 uses of the walk cost (callgrind, 100 number variants of a seed: the
# same instructions either way), so a batch's family of a few dozen variants is printed
# cheaper by the walks (12 % fewer instructions per file over families of 14), while a
# big scene's few shapes, met 10^4 times, are compiled after 64 walks of each
COMPILE_AFTER = 64
LIMIT = 512  # compiled shapes kept
MAX_TOKENS = 2000  # a larger tree (a system law over 10^4 bodies) is printed term by term
_LONG = MAX_TOKENS // 4  # a sum of more terms than this is larger

# tokens of a shape, in pre-order: leaves, a sum or product (its size follows), a factor
# x^-p of a product (printed in its denominator by the walk), any other node (by the walk)
_C, _V, _K, _ADDT, _MULT, _DEN, _OTHER, _EQ, _EXPR = range(9)

_FNS: dict = {}  # shape -> compiled printer
_SEEN: dict = {}  # shape -> times met before it was compiled


def _walk(e, toks: list, leaves: list) -> None:
    """The shape's tokens and the leaves (and nodes printed by the walks) of `e`; a sum's
    or product's leaves are taken in its loop (no call per leaf)."""
    t = type(e)
    if t is Add or t is Mul:
        add = toks.append
        put = leaves.append
        if t is Add:
            xs = e.terms
            add(_ADDT)
        else:
            xs = e.factors
            add(_MULT)
        add(len(xs))
        for x in xs:
            tx = type(x)
            if tx is Var:
                add(_V)
                put(x)
            elif tx is Const:
                add(_C)
                put(x)
            elif tx is Known:
                add(_K)
                put(x)
            elif tx is Add or tx is Mul:
                _walk(x, toks, leaves)
            elif tx is Pow and t is Mul and x.exp < 0:
                add(_DEN)
                put(x)
            else:
                add(_OTHER)
                put(x)
    elif t is Const:
        toks.append(_C)
        leaves.append(e)
    elif t is Var:
        toks.append(_V)
        leaves.append(e)
    elif t is Known:
        toks.append(_K)
        leaves.append(e)
    else:
        toks.append(_OTHER)
        leaves.append(e)


class _Gen:
    """Python source of one shape's printer (`numeric`: the numeric line's leaves)."""

    def __init__(self, toks, numeric: bool):
        self.toks, self.numeric = toks, numeric
        self.pos = 0  # next token
        self.slot = 0  # next leaf
        self.n = 0  # next variable
        self.code: list[str] = []

    def var(self) -> str:
        self.n += 1
        return f"_{self.n}"

    def emit(self, line: str, ind: int) -> None:
        self.code.append("    " * ind + line)

    def leaf(self, tok, ind: int) -> tuple[str, str, str]:
        """Code that sets (s, p, v) of the next leaf as `_si_leaf` (numeric) or
        `expr._leaf_txt` (symbolic) gives them; v is _NAME for a leaf shown by name."""
        i = self.slot
        self.slot += 1
        s, p, v = self.var(), self.var(), self.var()
        e = self.emit
        if tok == _C or (self.numeric and tok == _K):
            e(f"{v} = L[{i}].value", ind)
            if tok == _K:  # a known without a value prints as fmt_num does, not moved
                e(f"if {v} is None or (isinstance({v}, float) and {v} != {v}):", ind)
                e(f"    {s} = fmt_num({v}, sig)", ind)
                e(f"    {v} = NAME", ind)
                e("else:", ind)
                e(f"    {s} = F.get({v})", ind)
                e(f"    if {s} is None:", ind)
                e(f"        {s} = F[{v}] = fmt_num({v}, sig)", ind)
            else:
                e(f"{s} = F.get({v})", ind)
                e(f"if {s} is None:", ind)
                e(f"    {s} = F[{v}] = fmt_num({v}, sig)", ind)
            e(f"{p} = ADD if {s}[:1] == '-' else ATOM", ind)
        elif tok == _V and self.numeric:
            e(f"{s} = L[{i}].name", ind)
            e(f"{p} = ATOM", ind)
            e(f"{v} = NAME", ind)
            e(f"if {s} not in keep:", ind)
            e(f"    {v} = values.get({s}, NAME)", ind)
            e(f"    if {v} is None or (isinstance({v}, float) and {v} != {v}):", ind)
            e(f"        {v} = NAME", ind)
            e(f"    elif {v} is not NAME:", ind)
            e(f"        {s} = F.get({v})", ind)
            e(f"        if {s} is None:", ind)
            e(f"            {s} = F[{v}] = fmt_num({v}, sig)", ind)
            e(f"        if {s}[:1] == '-':", ind)
            e(f"            {p} = ADD", ind)
        else:  # a name
            e(f"{s} = L[{i}].name", ind)
            e(f"{p} = ATOM", ind)
            e(f"{v} = NAME", ind)
        return s, p, v

    def node(self, ind: int) -> tuple[str, str]:
        """Code that prints the node at `pos`: (text variable, precedence variable)."""
        tok = self.toks[self.pos]
        self.pos += 1
        if tok in (_C, _V, _K):
            s, p, _ = self.leaf(tok, ind)
            return s, p
        if tok == _OTHER:
            i = self.slot
            self.slot += 1
            s, p = self.var(), self.var()
            self.emit(f"{s}, {p} = " + ("si_text(L[%d], values, keep, sig)" if self.numeric
                                        else "txt(L[%d], False, sig, None, False)") % i, ind)
            return s, p
        n = self.toks[self.pos]
        self.pos += 1
        if tok == _ADDT:
            s = self.var()
            self.emit(f"{s} = ''", ind)
            for k in range(n):
                t, _ = self.node(ind)
                if k == 0:
                    self.emit(f"{s} = {t}", ind)
                else:
                    self.emit(f"{s} += (' - ' + {t}[1:]) if {t}[:1] == '-' else (' + ' + {t})",
                              ind)
            p = self.var()
            self.emit(f"{p} = ADD", ind)
            return s, p
        # a product: its first factor's sign moves in front (a -1 is left out)
        sign = self.var()
        self.emit(f"{sign} = ''", ind)
        items: list = []  # (text, precedence) variables of the factors, in order
        dens: list = []
        skip = None  # the variable that says the first factor (a -1) is left out
        for k in range(n):
            ft = self.toks[self.pos]
            if ft == _DEN:
                self.pos += 1
                i = self.slot
                self.slot += 1
                d = self.var()
                self.emit(f"{d} = " + ("si_den(L[%d], values, keep, sig)" if self.numeric
                                       else "den_txt(L[%d], False, sig, None)") % i, ind)
                dens.append(d)
            elif k == 0 and ft in (_C, _V, _K):
                self.pos += 1
                s, p, v = self.leaf(ft, ind)
                skip = self.var()
                self.emit(f"{skip} = False", ind)
                self.emit(f"if {v} is not NAME and {v} < 0:", ind)
                self.emit(f"    {sign} = '-'", ind)
                self.emit(f"    if {v} == -1.0:", ind)
                self.emit(f"        {skip} = True", ind)
                self.emit("    else:", ind)
                self.emit(f"        {s} = fmt_num(-{v}, sig)", ind)
                self.emit(f"        {p} = ADD if {s}[:1] == '-' else ATOM", ind)
                items.append((s, p))
            else:
                items.append(self.node(ind))
        s, p = self.var(), self.var()
        lst = "[" + ", ".join(f"({a}, {b})" for a, b in items) + "]"
        if len(items) == 2 and not dens:
            # `_join` of two factors: each in parentheses below a product, x*x as x^2
            w = []
            for a, b in items:
                w.append(self.var())
                self.emit(f"{w[-1]} = {a} if {b} >= MUL else '(' + {a} + ')'", ind)
            two = f"({w[0]} + '^2' if {w[0]} == {w[1]} else {w[0]} + '*' + {w[1]})"
            if skip is not None:
                self.emit(f"{s} = {w[1]} if {skip} else {two}", ind)
            else:
                self.emit(f"{s} = {two}", ind)
        else:
            rest = "[" + ", ".join(f"({a}, {b})" for a, b in items[1:]) + "]"
            if skip is not None:
                self.emit(f"{s} = join({rest} if {skip} else {lst})", ind)
            else:
                self.emit(f"{s} = join({lst})", ind)
        if dens:
            d = self.var()
            self.emit(f"{d} = join([{', '.join(dens)}])", ind)
            self.emit(f"{s} += '/(' + {d} + ')'" if len(dens) > 1 else f"{s} += '/' + {d}",
                      ind)
        self.emit(f"{p} = ADD if {sign} else MUL", ind)
        self.emit(f"{s} = {sign} + {s}", ind)
        return s, p

    def source(self) -> str:
        if self.toks[0] == _EXPR:  # one expression: its (text, precedence)
            self.pos = 1
            s, p = self.node(1)
            return "\n".join(["def printer(L, values, keep, sig, F):", *self.code,
                              f"    return {s}, {p}"])
        lhs, _ = self.node(1)
        assert self.toks[self.pos] == _EQ
        self.pos += 1
        rhs, _ = self.node(1)
        return "\n".join(["def printer(L, values, keep, sig, F):", *self.code,
                          f"    return {lhs} + ' = ' + {rhs}"])


_ENV = dict(fmt_num=fmt_num, NAME=_NAME, ADD=_ADD, ATOM=_ATOM, MUL=_MUL, join=_join,
            si_text=_si_text, si_den=_si_den, txt=_txt, den_txt=_den_txt)


def _compile(key) -> tuple:
    out = []
    for numeric in (False, True):
        env = dict(_ENV)
        exec(_Gen(key, numeric).source(), env)  # noqa: S102 - our own generated code
        out.append(env["printer"])
    # the symbolic line of a kind of row by a template of its names (imported here: a
    # small file compiles no shape)
    from .sym_template import templated

    out[0] = templated(key, out[0], (_C, _V, _K, _ADDT, _MULT, _EQ, _EXPR))
    return tuple(out)


def printers(eq):
    """(leaves, (symbolic printer, numeric printer)) for `eq`, or None: a shape met for
    the first time (or printing turned off) is printed by the walks; False: too large.
    The last two compiled shapes met with the same top (the sides' node types and sizes)
    are tried first by their matchers: the leaves without the walk, the shape without
    its key."""
    global READ_BY
    if not ENABLED:
        return None
    lhs, rhs = eq.lhs, eq.rhs
    tl, tr = type(lhs), type(rhs)
    top = (tl, len(lhs.terms) if tl is Add else len(lhs.factors) if tl is Mul else -1,
           tr, len(rhs.terms) if tr is Add else len(rhs.factors) if tr is Mul else -1)
    last = _LAST.get(top)
    if last is not None:
        for pair in last:
            leaves = pair[0](lhs, rhs)
            if leaves is not None:
                READ_BY = pair
                return leaves, pair[1]
    if (tl is Add and top[1] > _LONG) or (tr is Add and top[3] > _LONG):
        return False  # a long sum: not walked whole to find it out
    toks: list = []
    leaves: list = []
    _walk(lhs, toks, leaves)
    toks.append(_EQ)
    _walk(rhs, toks, leaves)
    got = _found(toks, leaves)
    if got:
        m = _matcher_of(toks)
        last = _LAST.get(top)  # two shapes kept per top: a sequence alternates them
        _LAST[top] = ((m, got[1]),) if last is None else ((m, got[1]), last[0])
        READ_BY = _LAST[top][0]
    return got


_MATCHERS: dict = {}  # shape -> its matcher
# (matcher, printers) of the compiled shape `printers` read last: a loop over many rows
# tries the few it met last before `printers` (model.row_texts)
READ_BY: tuple | None = None
_LAST: dict = {}  # the sides' top node types and sizes -> the (matcher, printers) met last
_LEAFY = (Add, Mul, Var, Const, Known)  # the nodes `_walk` tells apart from "other"


def _matcher(key: tuple):
    """A function (lhs, rhs) -> the leaves `_walk` would list, or None where the tree is
    not of shape `key` (the same node types, the same sizes, at every token); for a key
    of one expression (`_EXPR` first: a term of a long sum), a function of it."""
    expr = key[0] == _EXPR
    code = ["def match(e):" if expr else "def match(lhs, rhs):", "    L = []",
            "    put = L.append"]
    pos = [1 if expr else 0]
    n = [0]

    def var() -> str:
        n[0] += 1
        return f"_{n[0]}"

    def emit(line: str) -> None:
        code.append("    " + line)

    def node(x: str, parent) -> None:
        tok = key[pos[0]]
        pos[0] += 1
        if tok in (_C, _V, _K):
            emit(f"if type({x}) is not {('Const', 'Var', 'Known')[(_C, _V, _K).index(tok)]}: "
                 "return None")
            emit(f"put({x})")
        elif tok in (_ADDT, _MULT):
            size = key[pos[0]]
            pos[0] += 1
            cls, attr = ("Add", "terms") if tok == _ADDT else ("Mul", "factors")
            xs = var()
            emit(f"if type({x}) is not {cls}: return None")
            emit(f"{xs} = {x}.{attr}")
            emit(f"if len({xs}) != {size}: return None")
            for i in range(size):
                c = var()
                emit(f"{c} = {xs}[{i}]")
                node(c, cls)
        elif tok == _DEN:  # a factor x^-p of a product
            emit(f"if type({x}) is not Pow or not {x}.exp < 0: return None")
            emit(f"put({x})")
        else:  # _OTHER: any node `_walk` does not tell apart (a negative power in a product
            # is a _DEN there)
            emit(f"if type({x}) in LEAFY: return None")
            if parent == "Mul":
                emit(f"if type({x}) is Pow and {x}.exp < 0: return None")
            emit(f"put({x})")

    if expr:
        node("e", None)
    else:
        node("lhs", None)
        assert key[pos[0]] == _EQ
        pos[0] += 1
        node("rhs", None)
    assert pos[0] == len(key)
    code.append("    return L")
    env = dict(Add=Add, Mul=Mul, Var=Var, Const=Const, Known=Known, Pow=Pow, LEAFY=_LEAFY)
    exec("\n".join(code), env)  # noqa: S102 - our own generated code
    return env["match"]


def _term_printers(e, last: list | None = None):
    """`printers` of one expression (a term of a long sum). `last`: [matcher, printers]
    of the term met before, tried first (a long sum's terms are mostly of one shape: read
    by its matcher, not walked); set to this term's where its shape is compiled."""
    if last is not None and last[0] is not None:
        leaves = last[0](e)
        if leaves is not None:
            return leaves, last[1]
    toks: list = [_EXPR]
    leaves = []
    _walk(e, toks, leaves)
    got = _found(toks, leaves)
    if got and last is not None:
        last[:] = [_matcher_of(toks), got[1]]
    return got


def _matcher_of(toks: list):
    """The matcher of the shape `toks`, made once (the tables bounded: cleared at LIMIT)."""
    key = tuple(toks)
    m = _MATCHERS.get(key)
    if m is None:
        if len(_MATCHERS) >= LIMIT:
            _MATCHERS.clear()
            _LAST.clear()
        m = _MATCHERS[key] = _matcher(key)
    return m


def _found(toks: list, leaves: list):
    if len(toks) > MAX_TOKENS:
        return False
    key = tuple(toks)
    fns = _FNS.get(key)
    if fns is None:
        # emptied with it: _LAST's printers, not kept alive beside the table
        fns = compiled_after(_FNS, _SEEN, key, _compile, COMPILE_AFTER, LIMIT,
                             forget=_LAST.clear)
        if fns is None:
            return None
    return leaves, fns


def lines(eq, values, keep, sig: int, six: dict | None = None, shown: dict | None = None):
    """(symbolic line, numeric line in SI and radians) of `eq` by its shape's printers, or
    None (print it by the walks). `six`, `shown`: numbers already printed to 6 and to
    `sig` figures (value -> text), kept by the caller across equations."""
    return lines_of(printers(eq), eq, values, keep, sig, six, shown)


def lines_of(got, eq, values, keep, sig: int, six: dict | None = None,
             shown: dict | None = None):
    """`lines` of `eq` once `got = printers(eq)` (a caller that read the shape itself and
    met a shape not compiled, or a long equation, hands it on: not read twice)."""
    if not got:
        if got is None or not ENABLED:
            return None
        if six is None:
            six = {}
        if shown is None:
            shown = six if sig == 6 else {}
        # a long equation (a system's momentum over 10^4 bodies): its sums term by term
        sl, nl = _side(eq.lhs, values, keep, sig, six, shown)
        sr, nr = _side(eq.rhs, values, keep, sig, six, shown)
        texts = getattr(eq, "_texts", None)
        s = texts[0] if texts is not None and texts[0] is not None else f"{sl} = {sr}"
        return s, f"{nl} = {nr}"
    leaves, (sym, num) = got
    if six is None:
        six = {}
    if shown is None:
        shown = six if sig == 6 else {}
    texts = getattr(eq, "_texts", None)  # `Equation.text()` printed it already
    s = texts[0] if texts is not None and texts[0] is not None else \
        sym(leaves, None, None, 6, six)
    return s, num(leaves, values, keep, sig, shown)


def _side(e, values, keep, sig: int, six: dict, shown: dict) -> tuple[str, str]:
    """(symbolic, numeric) text of one side; a sum term by term, each term by its
    shape's printers, joined as the walks join a sum's terms."""
    if type(e) is not Add:
        return _txt(e, False, 6, None, False)[0], _si_text(e, values, keep, sig)[0]
    syms: list = []
    nums: list = []
    last: list = [None, None]  # the shape met last: its matcher and printers
    for x in e.terms:
        m = last[0]  # `_term_printers`' first try, in line: the last term's matcher
        leaves = m(x) if m is not None else None
        got = (leaves, last[1]) if leaves is not None else _term_printers(x, last)
        if got:
            leaves, (sym, num) = got
            s, n = sym(leaves, None, None, 6, six)[0], num(leaves, values, keep, sig, shown)[0]
        else:
            s, n = _txt(x, False, 6, None, False)[0], _si_text(x, values, keep, sig)[0]
        if syms:  # both lists as long: a term's two texts joined alike
            syms.append(" - " + s[1:] if s[:1] == "-" else " + " + s)
            nums.append(" - " + n[1:] if n[:1] == "-" else " + " + n)
        else:
            syms.append(s)
            nums.append(n)
    return "".join(syms), "".join(nums)
