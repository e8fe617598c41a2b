"""Report stage: numbers in the reader's units, numeric lines, direction words.

In: the solved values (SI), the units the file is written in, `--units si|us|file`.
Out: display values and unit labels (slug, ft, lb, deg where the file used them), an
equation's numeric line with every known value substituted, the sign of an answer in
words. The solve stays in SI; only what is printed is converted.
"""
from __future__ import annotations

import math
import re

from ..expr import Add, Const, E, Fn, Known, Mul, Pow, Var, map_children, to_text
from ..expr import _ADD, _ATOM, _MUL, _den_txt, _join, _pow_txt, _txt  # the printer's own rules
from ..numbers import fmt_num
from ..records import record
from ..units import (
    ACCELERATION,
    ANGULAR_IMPULSE,
    FORCE,
    IMPULSE,
    INERTIA,
    LENGTH,
    MASS,
    MOMENT,
    NONE,
    RATE,
    STIFFNESS,
    TIME,
    UNITS,
    VELOCITY,
    Dim,
    dim_div,
    dim_mul,
    dim_pow,
    si_label,
)

FT = UNITS["ft"][0]
SLUG = UNITS["slug"][0]
US_LABELS: dict[Dim, str] = {
    NONE: "", MASS: "slug", LENGTH: "ft", TIME: "s", VELOCITY: "ft/s",
    ACCELERATION: "ft/s^2", RATE: "rad/s", FORCE: "lb", MOMENT: "lb*ft", IMPULSE: "lb*s",
    ANGULAR_IMPULSE: "lb*ft*s", INERTIA: "slug*ft^2", STIFFNESS: "lb/ft",
    (1, 2, -3): "ft*lb/s", (1, 0, -1): "slug/s", (0, 0, -2): "rad/s^2",
}
_STATE = re.compile(r"^[^.@\s]+\.(x|y|angle|vx|vy|omega)@")
STATE_DIMS = {"x": LENGTH, "y": LENGTH, "angle": NONE, "vx": VELOCITY, "vy": VELOCITY,
              "omega": RATE}


@record(frozen=True)
class Reader:
    """How numbers are shown: `system` "si" or "us", angles in degrees or radians."""

    system: str = "si"
    degrees: bool = False

    def factor(self, dim: Dim) -> float:
        """SI value / factor = the displayed value."""
        if self.system != "us":
            return 1.0
        return SLUG ** dim[0] * FT ** dim[1]

    def label(self, dim: Dim, si_unit: str | None = None) -> str:
        if self.system != "us":
            return si_unit if si_unit is not None else si_label(dim)
        if si_unit == "J":
            return "ft*lb"
        if dim in US_LABELS:
            return US_LABELS[dim]
        parts = []
        for sym, e in zip(("slug", "ft", "s"), dim):
            parts.append(sym if e == 1 else f"{sym}^{e}" if e else "")
        return "*".join(p for p in parts if p)

    def show(self, si_value, dim: Dim, si_unit: str, angle: bool = False):
        """(value, unit) of one quantity as the reader reads it."""
        if si_value is None:
            return None, self.label(dim, si_unit)
        if angle and self.degrees:
            return math.degrees(si_value), "deg"
        return si_value / self.factor(dim), self.label(dim, si_unit)


def reader_for(choice: str, file_units) -> Reader:
    """`--units file` follows the file (system and degrees); `si` is SI in radians;
    `us` is US customary, in degrees where the file typed degrees."""
    degrees = bool(getattr(file_units, "degrees", False))
    if choice == "si":
        return Reader("si", False)
    if choice == "us":
        return Reader("us", degrees)
    return Reader(getattr(file_units, "system", "si"), degrees)


# ---- the dimension of each leaf of an equation ---------------------------------------------------
def leaf_dim(e: E, system) -> Dim | None:
    """The dimension of an unknown or a named known; None for bare numbers."""
    name = getattr(e, "name", None)
    if name is None:
        return None
    u = system.unknowns.get(name)
    if u is not None:
        return u.dim
    m = _STATE.match(name)
    if m:
        return STATE_DIMS[m.group(1)]
    if name == "g":
        return ACCELERATION
    if name.startswith("m_"):
        return MASS
    if name.startswith("I_"):
        return INERTIA
    if name.startswith("t@"):
        return TIME
    if name.startswith(("e[", "mu[", "mu_")):
        return NONE
    q = system.scene.constants.get(name)
    return getattr(q, "dim", None)


def is_angle(e: E, system) -> bool:
    name = getattr(e, "name", None)
    if name is None:
        return False
    u = system.unknowns.get(name)
    if u is not None:
        return u.qty == "angle"  # an orientation (not a rotation such as dtheta)
    return bool(re.match(r"^[^.@\s]+\.angle@", name))


def _dim_up(e: E, system, memo: dict) -> Dim | None:
    k = id(e)
    if k in memo:
        return memo[k]
    t = type(e)
    if t is Const:
        d = None
    elif t is Var or t is Known:
        d = leaf_dim(e, system)
    elif t is Add:
        ds = [_dim_up(x, system, memo) for x in e.terms]
        d = next((x for x in ds if x is not None), None)
    elif t is Mul:
        ds = [_dim_up(x, system, memo) for x in e.factors]
        d = None
        if all(x is not None for x in ds):
            d = NONE
            for x in ds:
                d = dim_mul(d, x)
    elif t is Pow:
        b = _dim_up(e.base, system, memo)
        d = dim_pow(b, e.exp) if b is not None else None
    else:
        _dim_up(e.arg, system, memo)
        d = NONE
    memo[k] = d
    return d


def _dim_guess(e: E, system) -> Dim | None:
    """The dimension of `e` if its bare numbers and unnamed knowns are pure numbers."""
    t = type(e)
    if t is Const:
        return NONE
    if t is Var or t is Known:
        d = leaf_dim(e, system)
        return NONE if d is None and t is Known else d
    if t is Add:
        ds = [_dim_guess(x, system) for x in e.terms]
        return ds[0] if ds and all(d == ds[0] for d in ds) else None
    if t is Mul:
        d = NONE
        for x in e.factors:
            g = _dim_guess(x, system)
            if g is None:
                return None
            d = dim_mul(d, g)
        return d
    if t is Pow:
        b = _dim_guess(e.base, system)
        return dim_pow(b, e.exp) if b is not None else None
    return NONE


def _dim_down(e: E, target: Dim | None, system, memo: dict, slots: dict) -> None:
    """Give each bare number the dimension its place in the equation needs."""
    t = type(e)
    if t is Const or (t is Known and memo.get(id(e)) is None):
        if target is not None or e.value not in (0.0, 1.0, -1.0):  # 0 and 1 need none
            slots[id(e)] = target
    elif t is Add:
        d = memo.get(id(e)) or target
        for x in e.terms:
            _dim_down(x, d, system, memo, slots)
    elif t is Mul:
        open_ = [x for x in e.factors if memo.get(id(x)) is None]
        guess: dict = {}
        if len(open_) > 1 and target is not None:
            # several open factors (`0.2*(0.6*J_n - 0.8*J_t)`, `3000*ln(m0/m1)`): the
            # numbers inside a sum or a named ratio are taken as pure numbers (direction
            # cosines, ratios), which leaves one bare number to carry the dimension
            bare = [x for x in open_ if type(x) is Const]
            rest_open = [x for x in open_ if type(x) is not Const]
            if len(bare) == 1:
                guess = {id(x): _dim_guess(x, system) for x in rest_open}
                if all(g is not None for g in guess.values()):
                    open_ = bare
        if len(open_) == 1 and target is not None:
            rest = NONE
            for x in e.factors:
                if x is not open_[0]:
                    rest = dim_mul(rest, memo.get(id(x)) or guess[id(x)])
            _dim_down(open_[0], dim_div(target, rest), system, memo, slots)
        for x in e.factors:
            if len(open_) != 1 or x is not open_[0]:
                _dim_down(x, memo.get(id(x)) or guess.get(id(x)), system, memo, slots)
    elif t is Pow:
        d = memo.get(id(e.base))
        if d is None and target is not None and e.exp:
            d = dim_pow(target, 1.0 / e.exp)
        _dim_down(e.base, d, system, memo, slots)
    elif t is Fn:
        _dim_down(e.arg, NONE, system, memo, slots)


# ---- the numeric line -----------------------------------------------------------------------------
def symbolic_line(eq, system, reader: Reader, sig: int = 6) -> str:
    """`lhs = rhs` with knowns by name; its bare numbers (lever arms, inertias) in the
    reader's units."""
    if reader.system != "us":
        return eq.text()
    return numeric_line(eq, {}, set(), system, reader, sig, symbolic=True)


def numeric_line(eq, values: dict, keep: set, system, reader: Reader, sig: int = 6,
                 symbolic: bool = False, placed: tuple | None = None) -> str:
    """`lhs = rhs` with every value that is known here substituted (the givens and what
    earlier blocks solved), the unknowns in `keep` by name, in the reader's units.

    In US units every bare number is converted by the dimension its place needs; a line
    whose numbers cannot all be placed is shown in SI and says so. `placed`: `_placed`
    of the line, made already (by `lines_in`)."""
    scale, memo, slots = placed if placed is not None else _placed(eq, system, reader)
    r = reader if scale else Reader("si", reader.degrees)
    if symbolic and not scale:
        return eq.text()
    if not scale:  # SI: the leaves' numbers as they are (an angle's in degrees)
        angle = angle_names(system) if reader.degrees else None
        text = f"{_si_text(eq.lhs, values, keep, sig, angle)[0]} = " \
               f"{_si_text(eq.rhs, values, keep, sig, angle)[0]}"
        return text + "   (SI)" if reader.system == "us" else text
    leaf = _Sub(values, keep, system, r, memo, slots, scale, symbolic).leaf
    num = not symbolic
    # printed with the leaves substituted as they are reached (no copy of the tree)
    text = f"{to_text(eq.lhs, num, sig, leaf)} = {to_text(eq.rhs, num, sig, leaf)}"
    if reader.system == "us" and not scale:
        text += "   (SI)"
    return text


def _placed(eq, system, reader: Reader) -> tuple:
    """(scale, memo, slots): whether the line's numbers are converted to the reader's
    units (US, every bare number placed), the nodes' dimensions, the numbers' dimensions."""
    memo: dict = {}
    slots: dict = {}
    scale = reader.system == "us"
    if scale:
        dl, dr = _dim_up(eq.lhs, system, memo), _dim_up(eq.rhs, system, memo)
        d = dl if dl is not None else dr
        _dim_down(eq.lhs, d, system, memo, slots)
        _dim_down(eq.rhs, d, system, memo, slots)
        # a number that no dimension reaches is a pure number only if the line is one
        if any(v is None for v in slots.values()):
            scale = False
    return scale, memo, slots


def lines_in(eq, values: dict, keep: set, system, reader: Reader, sig: int = 6):
    """(`symbolic_line(eq, ...)`, `numeric_line(eq, values, keep, ...)`), the numbers'
    dimensions placed once for the two (a US line's)."""
    if reader.system != "us":
        return eq.text(), numeric_line(eq, values, keep, system, reader, sig)
    placed = _placed(eq, system, reader)
    return (numeric_line(eq, {}, set(), system, reader, sig, True, placed),
            numeric_line(eq, values, keep, system, reader, sig, False, placed))


# ---- the numeric line in SI and radians: one walk that prints and substitutes ---------------
_NAME = object()  # a leaf printed by its name (or a known whose value cannot be shown)


def _si_leaf(f: E, values, keep, sig: int, angle=None, in_fn: bool = False):
    """(text, precedence, value) of a leaf as `_Sub.leaf` (SI) substitutes it and `to_text`
    prints it: `value` the number it shows, or _NAME. `angle`: None (radians), or a
    function telling a name that holds an angle (shown in degrees, as a name is: `in_fn`,
    a function's argument, without parentheses around a negative one)."""
    t = type(f)
    if t is Const:
        v = f.value
    elif t is Var:
        n = f.name
        if n in keep or n not in values:
            return n, _ATOM, _NAME
        v = values[n]
        if v is None or (isinstance(v, float) and v != v):
            return n, _ATOM, _NAME
        if angle is not None and angle(n):
            return _degrees(v, in_fn), _ATOM, _NAME
    else:  # a Known: its value (one that cannot be shown stays a Known: no sign moved)
        v = f.value
        if v is None or (isinstance(v, float) and v != v):
            s = fmt_num(v, sig)
            return s, (_ADD if s[:1] == "-" else _ATOM), _NAME
        if angle is not None and angle(f.name):
            return _degrees(v, in_fn), _ATOM, _NAME
    s = fmt_num(v, sig)
    return s, (_ADD if s[:1] == "-" else _ATOM), v


def _degrees(v, in_fn: bool) -> str:
    """An angle's value as `_Sub.leaf` shows it in degrees (a name: no sign moved)."""
    s = f"{fmt_num(math.degrees(v))} deg"
    return f"({s})" if s[:1] == "-" and not in_fn else s


def _si_text(e: E, values, keep, sig: int, angle=None) -> tuple[str, int]:
    """`expr._txt(e, True, sig, _Sub(values, keep, ...).leaf)` for SI (in radians, or with
    `angle` in degrees: see `_si_leaf`), in one walk without a leaf object per number
    (the report prints 10^5 such lines)."""
    t = type(e)
    if t is Const or t is Var or t is Known:
        s, p, _ = _si_leaf(e, values, keep, sig, angle)
        return s, p
    if t is Add:
        parts = []
        for x in e.terms:
            s = _si_text(x, values, keep, sig, angle)[0]
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
                s, p, v = _si_leaf(f, values, keep, sig, angle)
                if first and v is not _NAME and v < 0:
                    sign = "-"
                    first = False
                    if v == -1.0:
                        continue
                    s = fmt_num(-v, sig)
                    p = _ADD if s[:1] == "-" else _ATOM
                num.append((s, p))
            elif tf is Pow and f.exp < 0:
                num_den = _si_den(f, values, keep, sig, angle)
                den.append(num_den)
            else:
                num.append(_si_text(f, values, keep, sig, angle))
            first = False
        s = _join(num)
        if den:
            d = _join(den)
            s += "/" + (f"({d})" if len(den) > 1 else d)
        return sign + s, _MUL if not sign else _ADD
    if t is Pow:
        b, p = _si_text(e.base, values, keep, sig, angle)
        return _pow_txt(b, p, e.exp, sig)
    x = e.arg
    tx = type(x)
    # a function's argument that is a leaf: an angle in it without parentheses
    a = _si_leaf(x, values, keep, sig, angle, True)[0] if \
        angle is not None and (tx is Var or tx is Known) else \
        _si_text(x, values, keep, sig, angle)[0]
    return f"{e.name}({a})", _ATOM


def _si_den(f: Pow, values, keep, sig: int, angle=None) -> tuple[str, int]:
    """A factor x^-p of a product in its denominator, as `expr._den_txt` prints it."""
    p = -f.exp
    b = f.base
    tb = type(b)
    if tb is Const or tb is Known or tb is Var:
        s, bp, v = _si_leaf(b, values, keep, sig, angle)
        if p == 1.0:
            return s, bp
        if v is not _NAME:  # a number folds, as `power` folds a Const
            try:
                r = v ** p
            except (ZeroDivisionError, OverflowError):
                return _pow_txt(s, bp, p, sig)
            rs = fmt_num(r, sig)
            return rs, (_ADD if rs[:1] == "-" else _ATOM)
        return _pow_txt(s, bp, p, sig)
    bs, bp = _si_text(b, values, keep, sig, angle)
    return (bs, bp) if p == 1.0 else _pow_txt(bs, bp, p, sig)


_ANGLE_NAME = re.compile(r"^[^.@\s]+\.angle@")


def angle_names(system):
    """`is_angle` of a leaf by its name, each name decided once (a function for
    `_si_leaf`'s `angle`)."""
    memo: dict = {}
    unknowns = system.unknowns

    def angle(n: str) -> bool:
        a = memo.get(n)
        if a is None:
            u = unknowns.get(n)
            a = memo[n] = u.qty == "angle" if u is not None else \
                _ANGLE_NAME.match(n) is not None
        return a
    return angle


def si_lines(eq, values, keep, sig: int, six: dict, shown: dict, angle=None):
    """(`eq.text()`, `numeric_line(eq, values, keep, ...)`) for a reader in SI (radians,
    or degrees with `angle`: see `_si_leaf`), the same strings, in one walk of the tree
    that prints both. `six`, `shown`: the numbers printed so far to 6 and to `sig`
    figures (value -> text), kept by the caller across equations."""
    texts = eq._texts
    if texts is not None and texts[0] is not None:  # printed already: the numbers only
        return texts[0], f"{_si_text(eq.lhs, values, keep, sig, angle)[0]} = " \
                         f"{_si_text(eq.rhs, values, keep, sig, angle)[0]}"
    sl, _, nl, _ = _pair(eq.lhs, values, keep, sig, six, shown, angle)
    sr, _, nr, _ = _pair(eq.rhs, values, keep, sig, six, shown, angle)
    return f"{sl} = {sr}", f"{nl} = {nr}"


def _pleaf(f: E, values, keep, sig: int, six: dict, shown: dict, angle):
    """(symbolic text, precedence, numeric text, precedence, value shown or _NAME) of a
    leaf: `expr._leaf_txt` and `_si_leaf`, the numbers through the caches."""
    t = type(f)
    if t is Const:
        v = f.value
        if type(v) is not float:
            s = fmt_num(v, 6)
            n = fmt_num(v, sig)
        else:
            s = six.get(v)
            if s is None:
                s = six[v] = fmt_num(v, 6)
            n = shown.get(v)
            if n is None:
                n = shown[v] = fmt_num(v, sig)
        return s, (_ADD if s[:1] == "-" else _ATOM), n, (_ADD if n[:1] == "-" else _ATOM), v
    name = f.name
    if t is Var:
        if name in keep or name not in values:
            return name, _ATOM, name, _ATOM, _NAME
        v = values[name]
        if v is None or (isinstance(v, float) and v != v):
            return name, _ATOM, name, _ATOM, _NAME
    else:  # a Known
        v = f.value
        if v is None or (isinstance(v, float) and v != v):
            n = fmt_num(v, sig)
            return name, _ATOM, n, (_ADD if n[:1] == "-" else _ATOM), _NAME
    if angle is not None and angle(name):
        return name, _ATOM, _degrees(v, False), _ATOM, _NAME
    if type(v) is not float:
        n = fmt_num(v, sig)
    else:
        n = shown.get(v)
        if n is None:
            n = shown[v] = fmt_num(v, sig)
    return name, _ATOM, n, (_ADD if n[:1] == "-" else _ATOM), v


def _pair(e: E, values, keep, sig: int, six: dict, shown: dict, angle):
    """(symbolic text, precedence, numeric text, precedence) of `e`: `expr._txt(e, False,
    6)` and `_si_text(e, values, keep, sig, angle)` in one walk (a node of another type
    than these by the two walks)."""
    t = type(e)
    if t is Add:
        ss: list = []
        ns: list = []
        for x in e.terms:
            tx = type(x)
            if tx is Const or tx is Var or tx is Known:
                s, _, n, _, _ = _pleaf(x, values, keep, sig, six, shown, angle)
            else:
                s, _, n, _ = _pair(x, values, keep, sig, six, shown, angle)
            if not ss:
                ss.append(s)
                ns.append(n)
                continue
            ss.append(" - " + s[1:] if s[:1] == "-" else " + " + s)
            ns.append(" - " + n[1:] if n[:1] == "-" else " + " + n)
        return "".join(ss), _ADD, "".join(ns), _ADD
    if t is Mul:
        snum: list = []
        nnum: list = []
        sden: list = []
        nden: list = []
        ssign = nsign = ""
        first = True
        for f in e.factors:
            tf = type(f)
            if tf is Const or tf is Known or tf is Var:
                s, sp, n, np_, v = _pleaf(f, values, keep, sig, six, shown, angle)
                if first:
                    # a negative number first: its sign in front, a -1 left out (the
                    # symbolic line moves a constant's; the numeric one any number's)
                    if tf is Const and f.value < 0:
                        ssign = "-"
                        if f.value != -1.0:
                            s = fmt_num(-f.value, 6)
                            snum.append((s, _ADD if s[:1] == "-" else _ATOM))
                    else:
                        snum.append((s, sp))
                    if v is not _NAME and v < 0:
                        nsign = "-"
                        if v != -1.0:
                            n = fmt_num(-v, sig)
                            nnum.append((n, _ADD if n[:1] == "-" else _ATOM))
                    else:
                        nnum.append((n, np_))
                else:
                    snum.append((s, sp))
                    nnum.append((n, np_))
            elif tf is Pow and f.exp < 0:
                sden.append(_den_txt(f, False, 6, None))
                nden.append(_si_den(f, values, keep, sig, angle))
            else:
                s, sp, n, np_ = _pair(f, values, keep, sig, six, shown, angle)
                snum.append((s, sp))
                nnum.append((n, np_))
            first = False
        s = _join(snum)
        n = _join(nnum)
        if sden:
            d = _join(sden)
            s += "/" + (f"({d})" if len(sden) > 1 else d)
            d = _join(nden)
            n += "/" + (f"({d})" if len(nden) > 1 else d)
        return ssign + s, (_ADD if ssign else _MUL), nsign + n, (_ADD if nsign else _MUL)
    if t is Const or t is Var or t is Known:
        return _pleaf(e, values, keep, sig, six, shown, angle)[:4]
    if t is Pow:
        s, sp, n, np_ = _pair(e.base, values, keep, sig, six, shown, angle)
        return (*_pow_txt(s, sp, e.exp, 6), *_pow_txt(n, np_, e.exp, sig))
    if t is Fn:
        x = e.arg
        tx = type(x)
        if angle is not None and (tx is Var or tx is Known):  # an angle without parentheses
            s, n = x.name, _si_leaf(x, values, keep, sig, angle, True)[0]
        else:
            s, _, n, _ = _pair(x, values, keep, sig, six, shown, angle)
        return f"{e.name}({s})", _ATOM, f"{e.name}({n})", _ATOM
    s, sp = _txt(e, False, 6, None, False)
    n, np_ = _si_text(e, values, keep, sig, angle)
    return s, sp, n, np_


class _Sub:
    """Known leaves replaced by display numbers: `leaf` one at a time (as `to_text`
    prints), or a copy of a whole tree (`__call__`)."""

    def __init__(self, values, keep, system, reader, memo, slots, scale, names=False):
        self.values, self.keep, self.system, self.reader = values, keep, system, reader
        self.memo, self.slots, self.scale, self.names = memo, slots, scale, names

    def __call__(self, e: E, in_fn: bool) -> E:
        t = type(e)
        if t is Const or t is Var or t is Known:
            return self.leaf(e, in_fn)
        return map_children(e, self)

    def leaf(self, e: E, in_fn: bool) -> E:
        """The leaf shown in place of `e` (a Const, Known or Var; `in_fn`: it is a
        function's argument)."""
        t = type(e)
        if t is Const:
            if not self.scale or e.value in (0.0, 1.0, -1.0):
                return e
            d = self.slots.get(id(e))
            return Const(e.value / self.reader.factor(d)) if d else e
        if t is Var or t is Known:
            if self.names:
                return e
            if t is Var and (e.name in self.keep or e.name not in self.values):
                return e
            v = e.value if t is Known else self.values[e.name]
            if v is None or (isinstance(v, float) and math.isnan(v)):
                return e
            if self.reader.degrees and is_angle(e, self.system):
                s = f"{fmt_num(math.degrees(v))} deg"
                return Var(f"({s})" if s.startswith("-") and not in_fn else s)
            d = leaf_dim(e, self.system) if self.scale else None
            if d is None and self.scale:
                d = self.slots.get(id(e))
            return Const(v / self.reader.factor(d) if d else v)
        return e


# ---- the sign of an answer in words ----------------------------------------------------------------
_WORDS = {"omega": ("counterclockwise", "clockwise"), "vx": ("to the right", "to the left"),
          "vy": ("upward", "downward")}


_JXY = re.compile(r"^J(x|y)\[")  # an impulse component along x or y
_HM = re.compile(r"^(H|M)\[")  # an angular momentum or angular impulse


def direction(name: str, value: float | None, system) -> str | None:
    """`clockwise`, `to the left`, `downward`...: the sign of a velocity component, an
    angular velocity or an impulse component along x or y, in the words of a textbook
    (x to the right, y up, counterclockwise positive)."""
    if value is None or value == 0:
        return None
    u = system.unknowns.get(name)
    qty = u.qty if u is not None else None
    if qty is None:
        m = _STATE.match(name)
        qty = m.group(1) if m else None
    if qty is None and _JXY.match(name):
        qty = "v" + name[1]
    if qty is None and _HM.match(name):
        qty = "omega"
    words = _WORDS.get(qty)
    if words is None:
        return None
    return words[0] if value > 0 else words[1]
