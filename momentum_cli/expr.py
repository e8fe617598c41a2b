"""Expressions over unknowns: what an equation is made of.

An equation is an `E` tree of constants, named knowns (given values that print by
name), unknowns (`Var`), sums, products, powers and functions. The same tree prints
symbolically (`m_rod*(rod.vx@3 - rod.vx@2)`) and with numbers, gives its unknowns
(the incidence the structural analysis needs), its affine coefficients when it is
linear in a block, and its derivatives for Newton's method.
"""
from __future__ import annotations

import math
from fractions import Fraction

from .numbers import fmt_num
from .records import record


class E:
    """Base of expression nodes; arithmetic operators build trees with light folding."""

    __slots__ = ()

    def __add__(self, o):
        return add(self, lift(o))

    def __radd__(self, o):
        return add(lift(o), self)

    def __sub__(self, o):
        return add(self, neg(lift(o)))

    def __rsub__(self, o):
        return add(lift(o), neg(self))

    def __mul__(self, o):
        return mul(self, lift(o))

    def __rmul__(self, o):
        return mul(lift(o), self)

    def __truediv__(self, o):
        return mul(self, power(lift(o), -1.0))

    def __rtruediv__(self, o):
        return mul(lift(o), power(self, -1.0))

    def __neg__(self):
        return neg(self)

    def __pow__(self, p):
        return power(self, float(p))


# The nodes are plain slotted classes with hand-written constructors: they are the
# most numerous objects (a 1,000-ball chain builds ~10^5), and immutable by convention.
class Const(E):
    __slots__ = ("value",)

    def __init__(self, value: float):
        self.value = value

    def __repr__(self):
        return f"Const({self.value!r})"


class Known(E):
    """A given value that prints by its name symbolically (`m_rod`, `rod.omega@2`)."""

    __slots__ = ("name", "value")

    def __init__(self, name: str, value: float):
        self.name = name
        self.value = value

    def __repr__(self):
        return f"Known({self.name!r}, {self.value!r})"


class Var(E):
    """An unknown, named as the DSL writes it (`rod.omega@3`, `J_n[A]@2->3`)."""

    __slots__ = ("name",)

    def __init__(self, name: str):
        self.name = name

    def __repr__(self):
        return f"Var({self.name!r})"


class Add(E):
    __slots__ = ("terms",)

    def __init__(self, terms: tuple):
        self.terms = terms


class Mul(E):
    __slots__ = ("factors",)

    def __init__(self, factors: tuple):
        self.factors = factors


class Pow(E):
    __slots__ = ("base", "exp")

    def __init__(self, base: E, exp: float):
        self.base = base
        self.exp = exp


class Fn(E):
    __slots__ = ("name", "arg")

    def __init__(self, name: str, arg: E):
        self.name = name
        self.arg = arg


ZERO = Const(0.0)
ONE = Const(1.0)
# -1 shared as ZERO and ONE are: a big scene's every difference and negation holds one
# (report/reader.py gives 0, 1 and -1 no dimension by id: they may be shared)
NEG_ONE = Const(-1.0)

FUNCS = {
    "sin": math.sin, "cos": math.cos, "tan": math.tan, "asin": math.asin,
    "acos": math.acos, "atan": math.atan, "exp": math.exp, "ln": math.log,
    "log": math.log, "abs": abs,
}


def hypot(x: float, y: float) -> float:
    """math.hypot; a sweep's traced number (sweep/trace.py) keeps its expression."""
    traced = getattr(x, "hypot", None) or getattr(y, "hypot", None)
    return traced(x, y) if traced is not None else math.hypot(x, y)


def lift(x) -> E:
    if isinstance(x, E):
        return x
    if getattr(x, "apply", None) is not None:  # a sweep's traced number stays itself
        return Const(x)
    return Const(float(x))


def is_const(e: E) -> bool:
    return isinstance(e, Const)


def keeps(v) -> bool:
    """A traced number that keeps its terms (exact sensitivities, sweep/trace.py): a 0 or
    1 of it is never folded away (0 + x, 1 * x, 0 * x), its derivative needs them."""
    return type(v) is not float and getattr(v, "keep", False)


def is_zero(e: E) -> bool:
    return isinstance(e, (Const, Known)) and e.value == 0.0 and not keeps(e.value)


def add(a: E, b: E) -> E:
    # exact types, as in `mul` (no node class has subclasses)
    ta, tb = type(a), type(b)
    if ta is Const and a.value == 0.0 and not keeps(a.value):
        return b
    if tb is Const and b.value == 0.0 and not keeps(b.value):
        return a
    if ta is Const and tb is Const:
        return Const(a.value + b.value)
    return Add((a.terms if ta is Add else (a,)) + (b.terms if tb is Add else (b,)))


def add_all(terms) -> E:
    """The sum of many terms in one node (repeated `add` would copy tuples: O(n^2))."""
    flat: list = []
    const = 0.0
    for t in terms:
        if type(t) is Const:
            const += t.value
        elif type(t) is Add:
            flat.extend(t.terms)
        else:
            flat.append(t)
    if const != 0.0 or keeps(const) or not flat:
        flat.append(ZERO if const == 0.0 and type(const) is float else Const(const))
    return flat[0] if len(flat) == 1 else Add(tuple(flat))


def neg(a: E) -> E:
    t = type(a)
    if t is Const:
        return Const(-a.value)
    if t is not Mul:  # what mul(Const(-1.0), a) gives, without the call
        return Mul((NEG_ONE, a))
    return mul(NEG_ONE, a)


def mul(a: E, b: E) -> E:
    # exact types (no subclass of these exists): the hottest function of a compile
    ta, tb = type(a), type(b)
    if ta is Const:
        if tb is Const:
            return Const(a.value * b.value)
        if a.value == 0.0 and not keeps(a.value):
            return ZERO
        if a.value == 1.0 and not keeps(a.value):
            return b
    elif tb is Const:
        if b.value == 0.0 and not keeps(b.value):
            return ZERO
        if b.value == 1.0 and not keeps(b.value):
            return a
    # two factors, neither a product: what the general fold below gives, directly
    if ta is not Mul and tb is not Mul:
        if ta is Const:
            if type(a.value) is float:  # c = 1.0 * a, neither 0 nor 1 (see above);
                # a fresh leaf: the report gives each bare number of a line the dimension
                # of its place by id (report/reader.py), so places never share a Const
                return Mul((Const(a.value), b))
        elif tb is Const:
            if type(b.value) is float:
                return Mul((Const(b.value), a))
        else:
            return Mul((a, b))
    fs = (a.factors if ta is Mul else (a,)) + (b.factors if tb is Mul else (b,))
    # keep one leading constant
    c = 1.0
    rest = []
    for f in fs:
        if type(f) is Const:
            c *= f.value
        else:
            rest.append(f)
    if c == 0.0 and not keeps(c):
        return ZERO
    if not rest:
        return Const(c)
    if c == 1.0 and not keeps(c):
        return rest[0] if len(rest) == 1 else Mul(tuple(rest))
    return Mul((Const(c), *rest))


def power(a: E, p: float) -> E:
    if p == 1.0:
        return a
    if p == 0.0:
        return ONE
    if isinstance(a, Const):
        try:
            return Const(a.value**p)
        except (ZeroDivisionError, OverflowError):
            return Pow(a, p)
    return Pow(a, p)


def fn(name: str, a: E) -> E:
    if isinstance(a, Const):
        traced = getattr(a.value, "apply", None)  # a sweep's traced number (sweep/trace.py)
        if traced is not None:
            return Const(traced(name))
        try:
            return Const(float(FUNCS[name](a.value)))
        except (ValueError, OverflowError):
            return Fn(name, a)
    return Fn(name, a)


# ---- evaluation --------------------------------------------------------------------------
def evaluate(e: E, values: dict[str, float]) -> float:
    """The value of `e` with unknowns taken from `values` (KeyError if missing)."""
    t = type(e)
    if t is Const or t is Known:
        return e.value
    if t is Var:
        return values[e.name]
    if t is Add:  # leaves inline: this walk runs over every equation and answer
        return math.fsum([x.value if type(x) is Const or type(x) is Known else
                          values[x.name] if type(x) is Var else evaluate(x, values)
                          for x in e.terms])
    if t is Mul:
        fs = e.factors
        for f in fs:  # a zero known factor hides its partners (as in `variables`)
            if (type(f) is Known or type(f) is Const) and f.value == 0.0:
                return 0.0
        r = 1.0
        for f in fs:
            tf = type(f)
            r *= f.value if tf is Const or tf is Known else \
                values[f.name] if tf is Var else evaluate(f, values)
        return r
    if t is Pow:
        return evaluate(e.base, values) ** e.exp
    return float(FUNCS[e.name](evaluate(e.arg, values)))


def _q(x) -> Fraction:
    """A number as the exact rational it is (a float is exactly one)."""
    return x if type(x) is Fraction else Fraction(x)


def _qpow(b: Fraction, p: float) -> Fraction:
    """b**p exactly for an integer p; otherwise the float power, taken as exact."""
    if p == int(p) and abs(p) <= 64 and (b != 0 or p > 0):
        return b ** int(p)
    return Fraction(float(b) ** p)


def evaluate_exact(e: E, values: dict) -> Fraction:
    """The value of `e` in rationals: sums and products of the data as given are exact
    (no cancellation); functions and non-integer powers round once, to float64."""
    t = type(e)
    if t is Const or t is Known:
        return _q(e.value)
    if t is Var:
        return _q(values[e.name])
    if t is Add:
        return sum((evaluate_exact(x, values) for x in e.terms), Fraction(0))
    if t is Mul:
        fs = e.factors
        for f in fs:
            if (type(f) is Known or type(f) is Const) and f.value == 0.0:
                return Fraction(0)
        r = Fraction(1)
        for f in fs:
            r *= evaluate_exact(f, values)
        return r
    if t is Pow:
        return _qpow(evaluate_exact(e.base, values), e.exp)
    return Fraction(float(FUNCS[e.name](float(evaluate_exact(e.arg, values)))))


def map_children(e: E, f) -> E:
    """The same node over `f(child, in_fn)` (Add, Mul, Pow, Fn; `in_fn`: the child is a
    function's argument); a leaf as it is. The shape is kept (no folding): a rewrite of
    leaves for display or naming."""
    t = type(e)
    if t is Add:
        return Add(tuple(f(x, False) for x in e.terms))
    if t is Mul:
        return Mul(tuple(f(x, False) for x in e.factors))
    if t is Pow:
        return Pow(f(e.base, False), e.exp)
    if t is Fn:
        return Fn(e.name, f(e.arg, True))
    return e


def variables(e: E, out: set | None = None) -> set[str]:
    """The unknowns `e` really depends on (terms multiplied by a zero known drop out)."""
    if out is None:
        out = set()
    t = type(e)
    if t is Var:
        out.add(e.name)
    elif t is Add:  # leaves inline: the analysis walks every equation
        for x in e.terms:
            tx = type(x)
            if tx is Var:
                out.add(x.name)
            elif tx is not Const and tx is not Known:
                variables(x, out)
    elif t is Mul:
        fs = e.factors
        for f in fs:
            if (type(f) is Const or type(f) is Known) and f.value == 0.0:
                return out
        for f in fs:
            tf = type(f)
            if tf is Var:
                out.add(f.name)
            elif tf is not Const and tf is not Known:
                variables(f, out)
    elif t is Pow:
        variables(e.base, out)
    elif t is Fn:
        variables(e.arg, out)
    return out


class NonLinear(Exception):
    """Raised by `affine` when an expression is not affine in the block's unknowns."""


class _Reals:
    """Float arithmetic for `affine` (numbers pass as they are: traced ones too)."""

    zero, one = 0.0, 1.0

    @staticmethod
    def q(x):
        return x

    @staticmethod
    def pow(b, p):
        return b**p

    @staticmethod
    def fn(name: str, x):
        return float(FUNCS[name](x))


class _Rationals:
    """Exact arithmetic for `affine_exact`: sums and products of the data without rounding;
    functions and non-integer powers round once, to float64."""

    zero, one = Fraction(0), Fraction(1)
    q = staticmethod(_q)
    pow = staticmethod(_qpow)

    @staticmethod
    def fn(name: str, x):
        return Fraction(float(FUNCS[name](float(x))))


def affine(e: E, block: set[str], values: dict[str, float]) -> tuple[dict[str, float], float]:
    """Coefficients and constant of `e` as an affine function of the `block` unknowns.

    Unknowns outside the block take their solved value from `values`.
    Raises NonLinear if `e` is not affine in the block.
    """
    return _affine_float(e, block, values)


def affine_exact(e: E, block: set[str], values: dict) -> tuple[dict[str, Fraction], Fraction]:
    """`affine` in rationals: the block's rows formed without rounding."""
    return _affine(e, block, values, _Rationals)


def _affine(e: E, block: set[str], values: dict, num) -> tuple[dict, object]:
    t = type(e)
    if t is Const or t is Known:
        return {}, num.q(e.value)
    if t is Var:
        if e.name in block:
            return {e.name: num.one}, num.zero
        return {}, num.q(values[e.name])
    if t is Add:
        coef: dict = {}
        const = num.zero
        for x in e.terms:
            c, k = _affine(x, block, values, num)
            const += k
            for n, v in c.items():
                coef[n] = coef.get(n, num.zero) + v
        return coef, const
    if t is Mul:
        if any(is_zero(f) for f in e.factors):
            return {}, num.zero
        coef, const = {}, num.one
        for f in e.factors:
            c, k = _affine(f, block, values, num)
            if c and coef:
                raise NonLinear()
            if c:
                coef = {n: v * const for n, v in c.items()}
                const = k * const
            else:
                coef = {n: v * k for n, v in coef.items()}
                const *= k
        return coef, const
    if t is Pow:
        c, k = _affine(e.base, block, values, num)
        if c:
            raise NonLinear()
        return {}, num.pow(k, e.exp)
    c, k = _affine(e.arg, block, values, num)
    if c:
        raise NonLinear()
    return {}, num.fn(e.name, k)


def _affine_float(e: E, block: set[str], values: dict) -> tuple[dict, object]:
    """`_affine` with `_Reals`, the same operations in the same order (the same floats,
    signed zeros included), with the leaves handled inline: a big block's rows are
    formed ~2x faster (tests/test_fast_walks.py compares the two)."""
    t = type(e)
    if t is Const or t is Known:
        return {}, e.value
    if t is Var:
        if e.name in block:
            return {e.name: 1.0}, 0.0
        return {}, values[e.name]
    if t is Add:
        coef: dict = {}
        const = 0.0
        for x in e.terms:
            tx = type(x)
            if tx is Var:
                if x.name in block:
                    const += 0.0
                    coef[x.name] = coef.get(x.name, 0.0) + 1.0
                else:
                    const += values[x.name]
                continue
            if tx is Const or tx is Known:
                const += x.value
                continue
            c, k = _affine_float(x, block, values)
            const += k
            for n, v in c.items():
                coef[n] = coef.get(n, 0.0) + v
        return coef, const
    if t is Mul:
        fs = e.factors
        for f in fs:
            tf = type(f)
            if (tf is Const or tf is Known) and f.value == 0.0 and not keeps(f.value):
                return {}, 0.0
        coef, const = {}, 1.0
        for f in fs:
            tf = type(f)
            if tf is Const or tf is Known:
                k = f.value
                coef = {n: v * k for n, v in coef.items()} if coef else {}
                const *= k
                continue
            if tf is Var:
                if f.name in block:
                    c, k = {f.name: 1.0}, 0.0
                else:
                    k = values[f.name]
                    coef = {n: v * k for n, v in coef.items()} if coef else {}
                    const *= k
                    continue
            else:
                c, k = _affine_float(f, block, values)
            if c and coef:
                raise NonLinear()
            if c:
                coef = {n: v * const for n, v in c.items()}
                const = k * const
            else:
                coef = {n: v * k for n, v in coef.items()} if coef else {}
                const *= k
        return coef, const
    return _affine(e, block, values, _Reals)


def magnitude(e: E, values: dict[str, float]) -> float:
    """The sum of the absolute values of the terms of `e`: the scale of a residual."""
    t = type(e)
    if t is Add:
        return sum(magnitude(x, values) for x in e.terms)
    if t is Mul:
        if any(is_zero(f) for f in e.factors):
            return 0.0
        sums = [f for f in e.factors if type(f) is Add]
        if len(sums) == 1:
            k = 1.0
            for f in e.factors:
                if f is not sums[0]:
                    k *= evaluate(f, values)
            return abs(k) * magnitude(sums[0], values)
    return abs(evaluate(e, values))


def diff(e: E, name: str) -> E:
    """The partial derivative of `e` with respect to unknown `name`."""
    t = type(e)
    if t is Var:
        return ONE if e.name == name else ZERO
    if t is Const or t is Known:
        return ZERO
    if t is Add:
        out: E = ZERO
        for x in e.terms:
            out = add(out, diff(x, name))
        return out
    if t is Mul:
        out = ZERO
        fs = e.factors
        for i, f in enumerate(fs):
            d = diff(f, name)
            if is_const(d) and d.value == 0.0:
                continue
            term = d
            for j, g in enumerate(fs):
                if j != i:
                    term = mul(term, g)
            out = add(out, term)
        return out
    if t is Pow:
        d = diff(e.base, name)
        if is_const(d) and d.value == 0.0:
            return ZERO
        return mul(mul(Const(e.exp), power(e.base, e.exp - 1.0)), d)
    d = diff(e.arg, name)
    if is_const(d) and d.value == 0.0:
        return ZERO
    a = e.arg
    derivs = {
        "sin": lambda: fn("cos", a),
        "cos": lambda: neg(fn("sin", a)),
        "tan": lambda: power(fn("cos", a), -2.0),
        "asin": lambda: power(add(ONE, neg(power(a, 2.0))), -0.5),
        "acos": lambda: neg(power(add(ONE, neg(power(a, 2.0))), -0.5)),
        "atan": lambda: power(add(ONE, power(a, 2.0)), -1.0),
        "exp": lambda: fn("exp", a),
        "ln": lambda: power(a, -1.0),
        "log": lambda: power(a, -1.0),
        "abs": lambda: mul(a, power(fn("abs", a), -1.0)),
    }
    return mul(derivs[e.name](), d)


# ---- printing ---------------------------------------------------------------------------------
_PREC = {"add": 1, "mul": 2, "pow": 3, "atom": 4}
_ADD, _MUL, _POW, _ATOM = 1, 2, 3, 4


def to_text(e: E, numeric: bool = False, sig: int = 6, leaf=None) -> str:
    """Print `e`; symbolically (knowns by name) or with numbers (knowns by value).

    `leaf(node, in_fn)`, if given, is the leaf printed in place of each Const, Known and
    Var (`in_fn`: it is a function's argument): the text is that of the tree with its
    leaves so replaced (no folding but what printing does), without copying the tree.
    The report substitutes its numbers this way."""
    return _txt(e, numeric, sig, leaf, False)[0]


def _num(x: float, sig: int) -> str:
    return fmt_num(x, sig)


def _leaf_txt(e: E, numeric: bool, sig: int) -> tuple[str, int]:
    t = type(e)
    if t is Var or (t is Known and not numeric):
        return e.name, _ATOM
    s = fmt_num(e.value, sig)
    return s, (_ADD if s[:1] == "-" else _ATOM)


def _pow_txt(b: str, p: int, exp: float, sig: int) -> tuple[str, int]:
    if exp == 0.5:
        return f"sqrt({b})", _ATOM
    if exp == -1.0:
        return f"1/{b if p >= _POW else '(' + b + ')'}", _MUL
    bs = b if p > _POW else f"({b})"
    return f"{bs}^{fmt_num(exp, sig)}", _POW


def _join(items: list) -> str:
    """Factors `a*b`, a factor below a product's precedence in parentheses; x*x as x^2."""
    merged: list[str] = []
    last = None
    for s, p in items:
        if p < _MUL:
            s = f"({s})"
        if s == last:
            merged[-1] = last = f"{s}^2"
        else:
            merged.append(s)
            last = s
    return "*".join(merged) if merged else "1"


def _txt(e: E, numeric: bool, sig: int, leaf=None, in_fn: bool = False) -> tuple[str, int]:
    t = type(e)
    if t is Const or t is Known or t is Var:
        return _leaf_txt(e if leaf is None else leaf(e, in_fn), numeric, sig)
    if t is Add:
        parts = []
        for x in e.terms:
            s = _txt(x, numeric, sig, leaf)[0]
            if not parts:
                parts.append(s)
            elif s[:1] == "-":
                parts.append(" - " + s[1:])
            else:
                parts.append(" + " + s)
        return "".join(parts), _ADD
    if t is Mul:
        num: list = []
        den: list = []
        sign = ""
        first = True
        for f in e.factors:
            tf = type(f)
            if tf is Const or tf is Known or tf is Var:
                if leaf is not None:
                    f = leaf(f, False)
                if first and type(f) is Const and f.value < 0:
                    sign = "-"
                    first = False
                    if f.value == -1.0:
                        continue
                    f = Const(-f.value)
                num.append(_leaf_txt(f, numeric, sig))
            elif tf is Pow and f.exp < 0:
                den.append(_den_txt(f, numeric, sig, leaf))
            else:
                num.append(_txt(f, numeric, sig, leaf))
            first = False
        s = _join(num)
        if den:
            d = _join(den)
            s += "/" + (f"({d})" if len(den) > 1 else d)
        return sign + s, _MUL if not sign else _ADD
    if t is Pow:
        b, p = _txt(e.base, numeric, sig, leaf)
        return _pow_txt(b, p, e.exp, sig)
    a = _txt(e.arg, numeric, sig, leaf, True)[0]
    return f"{e.name}({a})", _ATOM


def _den_txt(f: Pow, numeric: bool, sig: int, leaf) -> tuple[str, int]:
    """A factor x^-p of a product, printed in its denominator as `power(x, p)` prints."""
    p = -f.exp
    b = f.base
    tb = type(b)
    if tb is Const or tb is Known or tb is Var:
        if leaf is not None:
            b = leaf(b, False)
        if p == 1.0:
            return _leaf_txt(b, numeric, sig)
        r = power(b, p)  # a number folds, as it would in the tree
        if type(r) is Const:
            return _leaf_txt(r, numeric, sig)
        bs, bp = _leaf_txt(b, numeric, sig)
        return _pow_txt(bs, bp, p, sig)
    bs, bp = _txt(b, numeric, sig, leaf)
    return (bs, bp) if p == 1.0 else _pow_txt(bs, bp, p, sig)


# ---- planar vectors of expressions ------------------------------------------------------------
_setattr = object.__setattr__  # V2 is frozen: its own __setattr__ refuses

@record(frozen=True)
class V2:
    """A planar vector of expressions; `cross` is the z-component of a x b."""

    x: E
    y: E

    def __init__(self, x: E, y: E):
        # by hand: the compile makes ~36 per contact (the record's generic one is 3x slower)
        _set_x(self, x)  # the slots' own setters: twice as fast as object.__setattr__
        _set_y(self, y)

    def __add__(self, o: "V2") -> "V2":
        return V2(add(self.x, o.x), add(self.y, o.y))

    def __sub__(self, o: "V2") -> "V2":
        return V2(add(self.x, neg(o.x)), add(self.y, neg(o.y)))

    def __neg__(self) -> "V2":
        return V2(neg(self.x), neg(self.y))

    def scale(self, k) -> "V2":
        k = lift(k)
        return V2(mul(k, self.x), mul(k, self.y))

    def dot(self, o: "V2") -> E:
        ox, oy = o.x, o.y
        if type(ox) is Const and type(oy) is Const and type(ox.value) is float and \
                type(oy.value) is float:
            # along a direction of plain numbers (a normal, an axis): the products as
            # `mul` folds them (0 -> ZERO, 1 -> the term, else (c, term)) without the calls
            sx, sy = self.x, self.y
            tx, ty = type(sx), type(sy)
            if tx is not Const and tx is not Mul and ty is not Const and ty is not Mul:
                a, b = ox.value, oy.value
                px = ZERO if a == 0.0 else sx if a == 1.0 else Mul((Const(a), sx))
                py = ZERO if b == 0.0 else sy if b == 1.0 else Mul((Const(b), sy))
                return add(px, py)
        return add(mul(self.x, ox), mul(self.y, oy))

    def cross(self, o: "V2") -> E:
        return add(mul(self.x, o.y), neg(mul(self.y, o.x)))

    def is_zero(self) -> bool:
        return is_zero(self.x) and is_zero(self.y)


_set_x, _set_y = V2.x.__set__, V2.y.__set__


def omega_cross(w: E, r: V2) -> V2:
    """w k x r for a planar angular velocity w: (-w*r_y, w*r_x)."""
    return V2(neg(mul(w, r.y)), mul(w, r.x))


def rotate(r: tuple[float, float], angle: E) -> V2:
    """A body-frame offset r turned by the body's angle: R(angle) r."""
    c, s = fn("cos", angle), fn("sin", angle)
    x, y = r
    return V2(add(mul(Const(x), c), neg(mul(Const(y), s))), add(mul(Const(x), s), mul(Const(y), c)))


def rotate_v2(r: V2, angle: E) -> V2:
    """A body-frame offset whose components are expressions (a point an unknown locates)."""
    c, s = fn("cos", angle), fn("sin", angle)
    return V2(add(mul(r.x, c), neg(mul(r.y, s))), add(mul(r.x, s), mul(r.y, c)))
