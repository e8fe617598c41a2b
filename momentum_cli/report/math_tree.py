"""Typeset math as plain data: expression trees and quantity names to a small box tree.

Stage: report (used by `build_report`). In: an `E` tree (or a name such as
`A.vx@2`, `J_n[A-B]@1->2`). Out: nested tuples (`("mi", "v")`, `("frac", a, b)`, ...)
that `math_out` writes as LaTeX or MathML, so both formats typeset the same structure.
"""
from __future__ import annotations

import re
from functools import lru_cache

from ..expr import Add, Const, Fn, Known, Mul, Pow, Var, power
from ..numbers import fmt_num

# Box kinds: ("mi", text) identifier; ("mn", text) number; ("mo", text) operator;
# ("mtext", text) words; ("row", (boxes...)); ("sub", base, sub); ("sup", base, sup);
# ("subsup", base, sub, sup); ("frac", num, den); ("sqrt", x); ("paren", x); ("abs", x);
# ("fn", name) a function's name; ("space",) a thin space; ("unit", label) a unit.

GREEK = {n: n for n in (
    "alpha", "beta", "gamma", "delta", "epsilon", "zeta", "eta", "theta", "iota", "kappa",
    "lambda", "mu", "nu", "xi", "pi", "rho", "sigma", "tau", "phi", "chi", "psi", "omega",
    "Gamma", "Delta", "Theta", "Lambda", "Xi", "Pi", "Sigma", "Phi", "Psi", "Omega")}
GREEK_CHAR = dict(zip(GREEK, "αβγδεζηθικλμνξπρστφχψωΓΔΘΛΞΠΣΦΨΩ"))

# a body's state quantity: symbol and component (`A.vx` is v with subscripts A, x)
QUANTITY = {"vx": ("v", "x"), "vy": ("v", "y"), "x": ("x", None), "y": ("y", None),
            "omega": ("omega", None), "angle": ("theta", None), "v": ("v", None),
            "ax": ("a", "x"), "ay": ("a", "y"), "alpha": ("alpha", None)}

FUNCTIONS = {"sin": "sin", "cos": "cos", "tan": "tan", "asin": "arcsin", "acos": "arccos",
             "atan": "arctan", "exp": "exp", "ln": "ln", "log": "ln"}

_NAME = re.compile(r"""^(?P<base>[A-Za-z][A-Za-z0-9]*)(?P<prime>'*)
                       (?:_(?P<sub>[A-Za-z0-9]+))?
                       (?:\.(?P<q>[A-Za-z]+))?
                       (?:\[(?P<label>.+)\])?
                       (?:@(?P<at>[A-Za-z0-9]+(?:->[A-Za-z0-9]+)?))?$""", re.X)

_PREC = {"add": 1, "mul": 2, "pow": 3, "atom": 4}


def symbol(word: str) -> tuple:
    """One word as an identifier: a Greek letter's name as the letter, a single letter
    italic, a longer word upright (MathML and LaTeX both read ("mi", word) that way)."""
    return ("mi", GREEK_CHAR.get(word, word))


def _word_or_text(s: str) -> tuple:
    return symbol(s) if re.fullmatch(r"[A-Za-z][A-Za-z0-9]*", s) else ("mtext", s)


@lru_cache(maxsize=16384)  # a name recurs in many equations; boxes are immutable
def name_box(name: str) -> tuple:
    """A quantity's name typeset: `A.vx@2` is v with subscript (A, x) and superscript (2),
    `m_rod` is m with subscript rod, `J_n[A-B]@1->2` is J with subscript (n, A-B) and
    superscript (1→2); a name outside this pattern stays as written, in text."""
    if re.fullmatch(r"[\d.]+(?:e[+-]?\d+)?°", str(name)):  # an angle in degrees
        return ("row", (("mn", str(name)[:-1]), ("mo", "°")))
    m = _NAME.match(str(name))
    if m is None:
        return ("mtext", str(name))
    base, prime, sub, q, label, at = m.group("base", "prime", "sub", "q", "label", "at")
    subs: list[tuple] = []
    if label is not None and _NAME.match(label) and base == "integral":
        body = ("row", (("mo", "∫"), name_box(label)))
        return body if at is None else ("sup", body, _at_box(at))
    if q is not None:
        letter, comp = QUANTITY.get(q, (q, None))
        head = symbol(letter)
        subs.append(_word_or_text(base if sub is None else f"{base}_{sub}"))
    else:
        comp = None
        if len(base) == 2 and base[1] in "xy" and (base[0].isupper() or prime):
            base, comp = base[0], base[1]  # Jx, Fy: a component of J, F
        head = symbol(base)
        if sub is not None:
            subs.append(_word_or_text(sub))
    if prime:  # v' : the common velocity after (a prime on the letter itself)
        head = ("row", (head, ("mo", "′" * len(prime))))
    if label is not None:
        subs.append(_word_or_text(label))
    if comp is not None:
        subs.append(("mi", comp))
    sub_box = None
    if subs:
        sub_box = subs[0] if len(subs) == 1 else \
            ("row", tuple(x for i, s in enumerate(subs) for x in ((("mo", ","),) if i else ()) + (s,)))
    sup_box = _at_box(at) if at is not None else None
    if sub_box is not None and sup_box is not None:
        return ("subsup", head, sub_box, sup_box)
    if sub_box is not None:
        return ("sub", head, sub_box)
    if sup_box is not None:
        return ("sup", head, sup_box)
    return head


def _at_box(at: str) -> tuple:
    """`@2` as (2), `@1->2` as (1→2): the state or the interval a value belongs to."""
    parts = at.split("->")
    inner: list[tuple] = []
    for i, p in enumerate(parts):
        if i:
            inner.append(("mo", "→"))
        inner.append(("mn", p) if p.isdigit() else symbol(p))
    return ("paren", ("row", tuple(inner)) if len(inner) > 1 else inner[0])


def number_box(x: float, sig: int = 6) -> tuple:
    """A number to `sig` figures; `1.5e-7` as 1.5 × 10^-7, a minus sign as U+2212."""
    s = fmt_num(x, sig)
    neg = s.startswith("-")
    s = s.lstrip("-")
    if "e" in s:
        mant, exp = s.split("e")
        box = ("row", (("mn", mant), ("mo", "×"), ("sup", ("mn", "10"), ("mn", exp.replace("-", "−")))))
    else:
        box = ("mn", s)
    return ("row", (("mo", "−"), box)) if neg else box


def equation_box(lhs, rhs, numeric: bool = False, sig: int = 6) -> tuple:
    """`lhs = rhs` typeset: knowns by name, or (numeric) by value."""
    return ("row", (expr_box(lhs, numeric, sig), ("mo", "="), expr_box(rhs, numeric, sig)))


def expr_box(e, numeric: bool = False, sig: int = 6) -> tuple:
    """An expression tree typeset, with the same grouping as the plain printer."""
    return _box(e, numeric, sig)[0]


def _negative(box: tuple) -> tuple | None:
    """The box without its leading minus sign, or None when it has none."""
    if box[0] == "row" and box[1] and box[1][0] == ("mo", "−"):
        rest = box[1][1:]
        return rest[0] if len(rest) == 1 else ("row", rest)
    return None


def _box(e, numeric: bool, sig: int) -> tuple[tuple, int]:
    t = type(e)
    if t is Const or (t is Known and numeric):
        b = number_box(e.value, sig)
        return b, _PREC["add"] if _negative(b) else _PREC["atom"]
    if t is Known or t is Var:
        return name_box(e.name), _PREC["atom"]
    if t is Add:
        items: list[tuple] = []
        for i, x in enumerate(e.terms):
            b, _ = _box(x, numeric, sig)
            pos = _negative(b)
            if i == 0:
                items.append(b)
            elif pos is not None:
                items += [("mo", "−"), pos]
            else:
                items += [("mo", "+"), b]
        return ("row", tuple(items)), _PREC["add"]
    if t is Mul:
        return _mul(e, numeric, sig)
    if t is Pow:
        b, p = _box(e.base, numeric, sig)
        if e.exp == 0.5:
            return ("sqrt", b), _PREC["atom"]
        if e.exp < 0:
            den = _box(power(e.base, -e.exp), numeric, sig)[0]
            return ("frac", ("mn", "1"), den), _PREC["atom"]
        return ("sup", _power_base(b, p), number_box(e.exp, sig)), _PREC["pow"]
    a, _ = _box(e.arg, numeric, sig)
    if e.name == "abs":
        return ("abs", a), _PREC["atom"]
    return ("row", (("fn", FUNCTIONS.get(e.name, e.name)), ("paren", a))), _PREC["atom"]


def _mul(e, numeric: bool, sig: int) -> tuple[tuple, int]:
    fs = list(e.factors)
    neg = False
    if type(fs[0]) is Const and fs[0].value < 0:
        neg = True
        fs = fs[1:] if fs[0].value == -1.0 else [Const(-fs[0].value)] + fs[1:]
    num = [f for f in fs if not (type(f) is Pow and f.exp < 0)]
    den = [power(f.base, -f.exp) for f in fs if type(f) is Pow and f.exp < 0]
    top = _product(num, numeric, sig, bool(den))
    box = ("frac", top, _product(den, numeric, sig, True)) if den else top
    if neg:
        return ("row", (("mo", "−"), box)), _PREC["add"]
    return box, _PREC["mul"] if not den else _PREC["atom"]


def _product(factors, numeric: bool, sig: int, in_frac: bool) -> tuple:
    """Factors side by side (a dot before a number), x·x as x²; sums in parentheses
    (not needed on their own in a fraction's numerator or denominator)."""
    boxes: list[tuple] = []
    for f in factors:
        b, p = _box(f, numeric, sig)
        if p <= _PREC["add"] and not (in_frac and len(factors) == 1):
            b = ("paren", b)
        if boxes and boxes[-1] == b:
            boxes[-1] = ("sup", _power_base(b, _PREC["atom"]), ("mn", "2"))
        elif boxes and boxes[-1] == ("sup", _power_base(b, _PREC["atom"]), ("mn", "2")):
            boxes[-1] = ("sup", _power_base(b, _PREC["atom"]), ("mn", "3"))
        else:
            boxes.append(b)
    if not boxes:
        return ("mn", "1")
    items: list[tuple] = []
    for i, b in enumerate(boxes):
        if i and _starts_with_number(b):
            items.append(("mo", "·"))
        items.append(b)
    return items[0] if len(items) == 1 else ("row", tuple(items))


def _power_base(b: tuple, prec: int) -> tuple:
    """A power's base: in parentheses when it is a sum or product, or already carries a
    superscript (the state of v^(2) squared is (v^(2))^2, not a stacked v^(2)^2)."""
    if prec <= _PREC["pow"] or b[0] in ("sup", "subsup"):
        return ("paren", b)
    return b


def _starts_with_number(b: tuple) -> bool:
    """Whether `b` begins with a digit or a minus sign (after any opening parenthesis):
    then a product needs a dot before it, 2·3 and 0·(3 − 0), not 23 or 0(3 − 0)."""
    while b[0] in ("row", "sup", "sub", "subsup", "paren"):
        if b[0] == "row":
            if not b[1]:
                return False
            b = b[1][0]
        else:
            b = b[1]
    return b[0] == "mn" or b == ("mo", "−")


# ---- a printed line back to a tree: for lines that come without one --------------------
_TOKEN = re.compile(r"""\s*(?:
    (?P<deg>\d+(?:\.\d*)?(?:e[+-]?\d+)?)\ deg\b
  | (?P<num>\d+(?:\.\d*)?(?:e[+-]?\d+)?|\.\d+(?:e[+-]?\d+)?)
  | (?P<name>[A-Za-z_][A-Za-z0-9_']*(?:\[(?:[^\[\]]|\[[^\]]*\])*\])?
             (?:\.[A-Za-z_][A-Za-z0-9_']*(?:\[(?:[^\[\]]|\[[^\]]*\])*\])?)*
             (?:@[A-Za-z0-9]+(?:->[A-Za-z0-9]+)?)?)
  | (?P<op>[-+*/^(),])
)""", re.X)


class _Unparsable(Exception):
    pass


def line_box(text: str, sig: int = 6) -> tuple | None:
    """A line printed by `expr.to_text` (`lhs = rhs`, or an expression) typeset by
    reading it back into a tree: for equations that reach the report only as text.
    None when the text is not in that form (the caller shows it verbatim)."""
    note = None
    m = re.search(r"\s+(\([A-Za-z ]+\))$", text)  # a trailing note, e.g. "(SI)"
    if m:
        text, note = text[:m.start()], m.group(1)
    items: list[tuple] = []
    for i, side in enumerate(text.split(" = ")):
        if i:
            items.append(("mo", "="))
        try:
            items.append(expr_box(_parse(side), True, sig))
        except (_Unparsable, RecursionError, ValueError):
            if i == 0 or not re.fullmatch(r"[A-Za-z ,;:'()-]+", side):
                return None
            items.append(("mtext", side))  # words: "integrated from the given start"
    if note:
        items += [("space",), ("mtext", note)]
    return items[0] if len(items) == 1 else ("row", tuple(items))


def _parse(text: str):
    tokens = []
    pos = 0
    text = text.rstrip()
    while pos < len(text):
        m = _TOKEN.match(text, pos)
        if m is None or m.end() == pos:
            raise _Unparsable(text[pos:])
        kind = m.lastgroup
        tokens.append((kind, m.group(kind)))
        pos = m.end()
    p = _Parser(tokens)
    e = p.sum()
    if p.i != len(tokens):
        raise _Unparsable(text)
    return e


class _Parser:
    """Recursive descent over the printer's grammar: sums of products of powers."""

    def __init__(self, tokens):
        self.t, self.i = tokens, 0

    def peek(self, value=None):
        if self.i < len(self.t) and (value is None or self.t[self.i][1] == value):
            return self.t[self.i]
        return None

    def take(self, value=None):
        tok = self.peek(value)
        if tok is None:
            raise _Unparsable(value or "end")
        self.i += 1
        return tok

    def sum(self):
        terms = [self.product()]
        while self.peek("+") or self.peek("-"):
            op = self.take()[1]
            t = self.product()
            terms.append(t if op == "+" else Mul((Const(-1.0), t)))
        return terms[0] if len(terms) == 1 else Add(tuple(terms))

    def product(self):
        if self.peek("-"):
            self.take()
            return _negated(self.product())
        factors = [self.power()]
        while self.peek("*") or self.peek("/"):
            op = self.take()[1]
            f = self.power()
            if op == "/":
                dens = f.factors if type(f) is Mul and self._grouped else (f,)
                factors += [Pow(d, -1.0) for d in dens]
            else:
                factors.append(f)
        return factors[0] if len(factors) == 1 else Mul(tuple(factors))

    def power(self):
        base = self.atom()
        if self.peek("^"):
            self.take()
            neg = bool(self.peek("-")) and self.take()
            exp = float(self.take()[1])
            return Pow(base, -exp if neg else exp)
        return base

    def atom(self):
        self._grouped = False
        kind, value = self.take()
        if kind == "num":
            return Const(float(value))
        if kind == "deg":  # an angle shown in degrees (the reader's units)
            return Var(f"{value}°")
        if kind == "name":
            if self.peek("("):
                self.take()
                arg = self.sum()
                self.take(")")
                if value == "sqrt":
                    return Pow(arg, 0.5)
                return Fn(value, arg)
            return Var(value)
        if value == "(":
            inner = self.sum()
            self.take(")")
            self._grouped = True
            return inner
        raise _Unparsable(value)


def _negated(e):
    if type(e) is Const and e.value != 0:
        return Const(-e.value)
    return Mul((Const(-1.0), e))
