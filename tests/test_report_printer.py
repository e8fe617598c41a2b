"""The report's fast paths print exactly what the slow ones printed.

`expr.to_text(e, leaf=...)` prints a tree with its leaves substituted as it reaches them;
the report used to copy the tree with the leaves replaced, then print the copy. Both are
compared here on random trees (every node shape, negative and unit constants, powers
folded in a denominator), with the printer as it was kept below as the reference; and
`fmt_num`'s float fast path against the general one.
"""
from __future__ import annotations

import math

from hypothesis import assume, given, settings
from hypothesis import strategies as st

from momentum_cli.expr import Add, Const, Fn, Known, Mul, Pow, Var, map_children, power, to_text
from momentum_cli.numbers import fmt_num

# ---- the reference: the printer before the fast path, verbatim ------------------------------
_PREC = {"add": 1, "mul": 2, "pow": 3, "atom": 4}


def _ref_fmt(x, sig=6):
    if x is None:
        return "-"
    if isinstance(x, float) and (math.isnan(x) or math.isinf(x)):
        return "nan" if math.isnan(x) else ("inf" if x > 0 else "-inf")
    if x == 0:
        return "0"
    s = f"{x:.{sig}g}"
    if "e" in s:
        mant, exp = s.split("e")
        return f"{mant}e{int(exp)}"
    if s in ("-0",):
        return "0"
    return s


def _ref_txt(e, numeric, sig):
    t = type(e)
    if t is Const:
        s = _ref_fmt(e.value, sig)
        return s, (_PREC["add"] if s.startswith("-") else _PREC["atom"])
    if t is Known:
        if numeric:
            s = _ref_fmt(e.value, sig)
            return s, (_PREC["add"] if s.startswith("-") else _PREC["atom"])
        return e.name, _PREC["atom"]
    if t is Var:
        return e.name, _PREC["atom"]
    if t is Add:
        parts = []
        for i, x in enumerate(e.terms):
            s, p = _ref_txt(x, numeric, sig)
            if i == 0:
                parts.append(s)
            elif s.startswith("-"):
                parts.append(" - " + s[1:])
            else:
                parts.append(" + " + s)
        return "".join(parts), _PREC["add"]
    if t is Mul:
        fs = list(e.factors)
        sign = ""
        if isinstance(fs[0], Const) and fs[0].value < 0:
            sign = "-"
            fs = fs[1:] if fs[0].value == -1.0 else [Const(-fs[0].value)] + fs[1:]
        num, den = [], []
        for f in fs:
            if isinstance(f, Pow) and f.exp < 0:
                den.append(power(f.base, -f.exp))
            else:
                num.append(f)

        def join(items):
            out = []
            for f in items:
                s, p = _ref_txt(f, numeric, sig)
                out.append(f"({s})" if p < _PREC["mul"] or (p == _PREC["add"]) else s)
            merged: list[str] = []
            for s in out:
                if merged and merged[-1] == s:
                    merged[-1] = f"{s}^2"
                else:
                    merged.append(s)
            return "*".join(merged) if merged else "1"
        s = join(num)
        if den:
            d = join(den)
            s += "/" + (f"({d})" if len(den) > 1 else d)
        return sign + s, _PREC["mul"] if not sign else _PREC["add"]
    if t is Pow:
        b, p = _ref_txt(e.base, numeric, sig)
        if e.exp == 0.5:
            return f"sqrt({b})", _PREC["atom"]
        if e.exp == -1.0:
            return f"1/{b if p >= _PREC['pow'] else '(' + b + ')'}", _PREC["mul"]
        bs = b if p > _PREC["pow"] else f"({b})"
        return f"{bs}^{_ref_fmt(e.exp, sig)}", _PREC["pow"]
    a, _ = _ref_txt(e.arg, numeric, sig)
    return f"{e.name}({a})", _PREC["atom"]


def _copy(e, leaf, in_fn=False):
    """The tree with its leaves replaced (what the report printed before)."""
    if type(e) in (Const, Known, Var):
        return leaf(e, in_fn)
    return map_children(e, lambda x, f: _copy(x, leaf, f))


# ---- random trees and substitutions ----------------------------------------------------------
NUMBERS = st.one_of(st.sampled_from([0.0, -0.0, 1.0, -1.0, 2.0, -2.0, 0.5, 1e-7, -3e12,
                                     math.nan, math.inf, -math.inf]),
                    st.floats(allow_nan=True, allow_infinity=True, width=64))
NAMES = st.sampled_from(["a", "b", "c", "m_rod", "rod.vx@2", "g"])
LEAVES = st.one_of(NUMBERS.map(Const), st.builds(Known, NAMES, NUMBERS), NAMES.map(Var))


def _trees(children):
    exps = st.sampled_from([-1.0, -2.0, -0.5, 0.5, 2.0, 3.0, -3.0, 1.5])
    return st.one_of(
        st.lists(children, min_size=1, max_size=4).map(lambda xs: Add(tuple(xs))),
        st.lists(children, min_size=1, max_size=4).map(lambda xs: Mul(tuple(xs))),
        st.builds(Pow, children, exps),
        st.builds(Fn, st.sampled_from(["sin", "sqrt", "ln"]), children))


TREES = st.recursive(LEAVES, _trees, max_leaves=12)


@st.composite
def substitutions(draw):
    """A leaf map like the report's: unknowns to values (or kept by name), knowns to
    values, numbers rescaled, an angle to `(-30 deg)` outside a function."""
    table = draw(st.dictionaries(NAMES, st.one_of(NUMBERS, st.just("deg"), st.just(None))))
    scale = draw(st.sampled_from([1.0, 0.3048, 14.59]))

    def leaf(e, in_fn):
        if type(e) is Const:
            return e if e.value in (0.0, 1.0, -1.0) else Const(e.value / scale)
        v = table.get(e.name, e.value if type(e) is Known else None)
        if v is None:
            return e
        if v == "deg":
            return Var("-30 deg" if in_fn else "(-30 deg)")
        return Const(v)
    return leaf


def _outcome(f):
    """The text, or the error raised (a complex power of a negative number fails alike)."""
    try:
        return f()
    except ValueError as exc:
        return type(exc)


@settings(max_examples=200, deadline=None)
@given(TREES, substitutions(), st.booleans(), st.sampled_from([6, 3, 1]))
def test_printing_with_leaves_substituted_equals_printing_the_copy(e, leaf, numeric, sig):
    assert _outcome(lambda: to_text(e, numeric, sig, leaf)) == \
        _outcome(lambda: _ref_txt(_copy(e, leaf), numeric, sig)[0])


@settings(max_examples=200, deadline=None)
@given(TREES, st.booleans(), st.sampled_from([6, 2]))
def test_printing_without_substitution_is_unchanged(e, numeric, sig):
    assert _outcome(lambda: to_text(e, numeric, sig)) == \
        _outcome(lambda: _ref_txt(e, numeric, sig)[0])


@settings(max_examples=300, deadline=None)
@given(NUMBERS, st.integers(min_value=1, max_value=17))
def test_fmt_num_fast_path_equals_general(x, sig):
    assert fmt_num(x, sig) == _ref_fmt(x, sig)


# ---- the JSON text: json_out.dumps against json.dumps(clean(x), indent=2) -------------------
import json  # noqa: E402

from momentum_cli.report.json_out import clean, dumps  # noqa: E402

SCALARS = st.one_of(st.none(), st.booleans(), st.integers(), NUMBERS, st.text(max_size=8))
JSONISH = st.recursive(
    SCALARS,
    lambda inner: st.one_of(st.lists(inner, max_size=4), st.lists(inner, max_size=3).map(tuple),
                            st.dictionaries(st.text(max_size=5), inner, max_size=4)),
    max_leaves=20)


@settings(max_examples=150, deadline=None)
@given(JSONISH, st.booleans(), st.sampled_from(["", "    "]))
def test_json_text_equals_the_json_module(x, ascii_only, indent):
    want = json.dumps(clean(x), allow_nan=False, indent=2, ensure_ascii=ascii_only)
    assert dumps(x, ascii_only, indent) == want.replace("\n", "\n" + indent)


def test_json_text_leaves_what_it_does_not_know_to_the_json_module():
    assert dumps({1: [float("nan")], "a": ()}) == json.dumps({1: [None], "a": []}, indent=2)
    try:
        dumps({"a": object()})
    except TypeError:
        pass
    else:
        raise AssertionError("an object json cannot encode must still raise TypeError")


def test_json_text_of_str_and_int_subclasses_is_their_value():
    import enum

    class Kind(str, enum.Enum):
        AUTO = "auto"

    class Level(enum.IntEnum):
        TWO = 2

    class F(float):
        pass

    x = {Kind.AUTO: [Kind.AUTO, Level.TWO, F(0.5), F("nan"), {"k": (Kind.AUTO,)}]}
    assert dumps(x) == json.dumps(clean(x), allow_nan=False, indent=2)


def test_a_result_encoded_where_it_was_solved_is_the_same_document():
    """A worker ships `encoded_fields` (JSON text); the document is byte for byte the
    one made from the report itself, in UTF-8 and in ASCII."""
    import io
    from pathlib import Path

    from momentum_cli.report.json_out import DocumentStream, encoded_fields, result_dict
    from momentum_cli.run import Rendered, read_source, solve_source

    examples = sorted(Path(__file__).parent.parent.glob("examples/*.mom"))[:12]
    for ascii_only in (False, True):
        texts = []
        for shipped in (False, True):
            buf = io.StringIO()
            doc = DocumentStream(buf, "test", ascii_only)
            for p in examples:
                res = solve_source(read_source(str(p)))
                rep = res.report
                if shipped and rep is not None:
                    rep = Rendered("", list(rep.checks), encoded_fields(rep, ascii_only))
                doc.append(result_dict(p.name, res.status, rep, res.diagnostics))
            doc.close()
            texts.append(buf.getvalue())
        assert texts[0] == texts[1] and '"equations": [' in texts[0]


@settings(max_examples=150, deadline=None)
@given(TREES, st.dictionaries(NAMES, st.floats(min_value=-1e6, max_value=1e6)))
def test_value_and_magnitude_in_one_walk_equal_the_two_walks(e, values):
    from momentum_cli.expr import evaluate, magnitude
    from momentum_cli.report.model import value_and_magnitude

    def both():
        return evaluate(e, values), magnitude(e, values)

    def outcome(f):
        try:
            return repr(f())  # repr: nan equals nan, -0.0 differs from 0.0
        except KeyError:  # the report skips such an equation; it re-raises the others
            return "KeyError"
        except (ValueError, ZeroDivisionError, OverflowError, TypeError) as exc:
            return "error" if type(exc) is not TypeError else "complex"
    want = outcome(both)
    assume(want != "complex")  # a negative number's fractional power: not a residual
    assert outcome(lambda: value_and_magnitude(e, values)) == want
