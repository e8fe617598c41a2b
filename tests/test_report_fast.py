"""The report's fast paths against their plain versions: same text, byte for byte.

The JSON writer's records (dicts with the same keys written from shared heads) against
the json module; the plain-text table against the cell-by-cell padding; the number
cache against `fmt_num`; the whole plain and JSON output of generated big scenes
against the reports built and printed the slow way (see `slow_*` below).
"""
from __future__ import annotations

import json
import math

from hypothesis import given, settings
from hypothesis import strategies as st

from momentum_cli.numbers import fmt_num
from momentum_cli.report.json_out import clean, dumps
from momentum_cli.report.text import formatter, table

NUMBERS = st.one_of(st.floats(allow_nan=True, allow_infinity=True), st.integers(-10**6, 10**6),
                    st.sampled_from([0.0, -0.0, 1.0, -1.0, 0.1, 1e-7, 123456789.0]))
SCALARS = st.one_of(st.none(), st.booleans(), NUMBERS, st.text(max_size=6))
# few keys, so that a list holds several dicts with the same keys (the records' path)
RECORD = st.dictionaries(st.sampled_from(["a", "b", "name", "é"]), SCALARS, max_size=4)
JSONISH = st.recursive(
    st.one_of(SCALARS, RECORD),
    lambda inner: st.one_of(st.lists(inner, max_size=5), st.lists(inner, max_size=3).map(tuple),
                            st.dictionaries(st.sampled_from(["a", "b", "c"]), inner,
                                            max_size=3)),
    max_leaves=30)


@settings(max_examples=100, deadline=None)
@given(JSONISH, st.booleans(), st.sampled_from(["", "    "]))
def test_records_written_from_shared_heads_equal_the_json_module(x, ascii_only, indent):
    want = json.dumps(clean(x), allow_nan=False, indent=2, ensure_ascii=ascii_only)
    assert dumps(x, ascii_only, indent) == want.replace("\n", "\n" + indent)


def test_records_with_odd_keys_and_values_equal_the_json_module():
    import enum

    class Kind(str, enum.Enum):
        AUTO = "auto"

    x = [{"a": 1, "b": [1.5, {"c": None}]}, {"a": 2, "b": []}, {"b": 1, "a": 2},
         {1: "int key"}, {1: "again"}, {Kind.AUTO: Kind.AUTO}, {"a": True, "b": math.inf},
         {"a": {}, "b": {"a": math.nan}}, {}, {"a": (1, 2)}]
    assert dumps(x) == json.dumps(clean(x), allow_nan=False, indent=2)


def _table_slow(headers, rows, indent="  "):
    widths = [len(h) for h in headers]
    for r in rows:
        for i, c in enumerate(r):
            widths[i] = max(widths[i], len(c))

    def line(cells):
        parts = [c.ljust(widths[i]) if i < len(cells) - 1 else c for i, c in enumerate(cells)]
        return (indent + "  ".join(parts)).rstrip()

    return [line(headers), indent + "  ".join("-" * w for w in widths)] + [line(r) for r in rows]


CELL = st.text(alphabet="ab {}:-é ", max_size=7)


@settings(max_examples=80, deadline=None)
@given(st.integers(1, 4).flatmap(lambda n: st.tuples(
    st.lists(CELL, min_size=n, max_size=n),
    st.lists(st.lists(CELL, min_size=n, max_size=n), max_size=5))),
    st.sampled_from(["  ", "      "]))
def test_table_by_columns_equals_cell_by_cell(hr, indent):
    headers, rows = hr
    assert table(headers, rows, indent) == _table_slow(headers, rows, indent)


def test_table_with_short_rows_equals_cell_by_cell():
    headers, rows = ["a", "bb", "c"], [["xxx", "y"], ["1", "2", "3"], []]
    assert table(headers, rows) == _table_slow(headers, rows)


@settings(max_examples=100, deadline=None)
@given(st.lists(st.one_of(st.none(), NUMBERS), max_size=8), st.integers(1, 17))
def test_number_cache_equals_fmt_num(xs, sig):
    f = formatter(sig)
    for x in xs + xs:
        assert f(x) == ("-" if x is None else fmt_num(x, sig))


# ---- the numeric line in SI: one walk against the leaf-by-leaf substitution ----------------
from test_report_printer import NAMES, TREES, _outcome  # noqa: E402

from momentum_cli.expr import to_text  # noqa: E402
from momentum_cli.report.reader import Reader, _si_text, _Sub  # noqa: E402


def _slow_numeric(e, values, keep, sig):
    leaf = _Sub(values, keep, None, Reader("si", False), {}, {}, False).leaf
    return to_text(e, True, sig, leaf)


@settings(max_examples=150, deadline=None)
@given(TREES, st.dictionaries(NAMES, st.one_of(st.none(), NUMBERS)),
       st.sets(NAMES), st.sampled_from([6, 3, 1]))
def test_si_numeric_text_equals_substituting_leaf_by_leaf(e, values, keep, sig):
    assert _outcome(lambda: _si_text(e, values, keep, sig)[0]) == \
        _outcome(lambda: _slow_numeric(e, values, keep, sig))


# ---- every equation of the examples and of generated big scenes: fast line == slow line ----
def _slow_line(eq, values, keep, system, reader, sig):
    """`reader.numeric_line` as it was before its SI walk: every leaf through `_Sub`."""
    from momentum_cli.report.reader import _dim_down, _dim_up

    memo, slots = {}, {}
    scale = reader.system == "us"
    if scale:
        dl, dr = _dim_up(eq.lhs, system, memo), _dim_up(eq.rhs, system, memo)
        d = dl if dl is not None else dr
        _dim_down(eq.lhs, d, system, memo, slots)
        _dim_down(eq.rhs, d, system, memo, slots)
        if any(v is None for v in slots.values()):
            scale = False
    r = reader if scale else Reader("si", reader.degrees)
    leaf = _Sub(values, keep, system, r, memo, slots, scale, False).leaf
    text = f"{to_text(eq.lhs, True, sig, leaf)} = {to_text(eq.rhs, True, sig, leaf)}"
    if reader.system == "us" and not scale:
        text += "   (SI)"
    return text


def test_numeric_lines_of_examples_and_big_scenes_equal_the_leaf_by_leaf_lines():
    from helpers import solved_scenes

    from momentum_cli.report.reader import numeric_line, reader_for

    checked = 0
    for name, sol, keeps in solved_scenes():
        system, values = sol.system, sol.values
        for units in ("file", "si", "us"):
            reader = reader_for(units, system.scene.file_units)
            for k, e in enumerate(system.equations):
                keep = keeps.get(k, set())
                slow = _slow_line(e, values, keep, system, reader, 6)
                assert numeric_line(e, values, keep, system, reader, 6) == slow, (name, k)
                checked += 1
    assert checked > 1000


# ---- a block's matrix, column by column, against the general table ----------------------
from momentum_cli.report.text import _matrix  # noqa: E402

MATRIX_NUMBERS = st.one_of(st.none(), NUMBERS)


@settings(max_examples=100, deadline=None)
@given(st.integers(1, 4).flatmap(lambda n: st.tuples(
    st.lists(st.text(alphabet="bv.x@12J_n[c]->", min_size=1, max_size=12), min_size=n,
             max_size=n),
    st.lists(st.lists(MATRIX_NUMBERS, min_size=n, max_size=n), max_size=4))),
    st.lists(MATRIX_NUMBERS, max_size=4), st.sampled_from([6, 3]))
def test_block_matrix_by_columns_equals_the_table(names_rows, rhs, sig):
    names, matrix = names_rows
    rhs = (rhs + [0.0] * len(matrix))[:len(matrix)]
    f = formatter(sig)
    out: list = []
    _matrix(names, matrix, rhs, f, out)
    rows = [[f(x) for x in row] + ["|", f(r)] for row, r in zip(matrix, rhs)]
    assert out == table(names + ["", "rhs"], rows, indent="      ")


# ---- the impulse diagram's directions by coefficients against the two evaluations --------
from momentum_cli.elements.keys import Key  # noqa: E402
from momentum_cli.elements.kinds import KeyKind  # noqa: E402
from momentum_cli.expr import V2, Const, Known, Mul, Var, evaluate  # noqa: E402
from momentum_cli.report.diagram import _monomials  # noqa: E402

_IMPULSES = [Key("J_n[A]@1->2", KeyKind.IMPULSE), Key("J_t[A]@1->2", KeyKind.IMPULSE)]
COMPONENTS = st.one_of(
    NUMBERS.filter(lambda x: isinstance(x, float)).map(Const),
    st.sampled_from(_IMPULSES).map(Var),
    st.tuples(st.sampled_from([Const, lambda v: Known("k", v)]), NUMBERS,
              st.sampled_from(_IMPULSES), st.booleans()).map(
        lambda t: Mul((t[0](float(t[1])), Var(t[2])) if t[3] else (Var(t[2]), t[0](float(t[1]))))))


@settings(max_examples=300, deadline=None)
@given(COMPONENTS, COMPONENTS)
def test_diagram_directions_by_coefficients_equal_the_evaluations(x, y):
    J = V2(x, y)
    got = _monomials(J)
    if got is None:
        return  # not of that form: the evaluations themselves run
    for n in _IMPULSES:
        zero = {m: 0.0 for m in _IMPULSES}
        one = dict(zero)
        one[n] = 1.0
        want = (evaluate(J.x, one) - evaluate(J.x, zero), evaluate(J.y, one) - evaluate(J.y, zero))
        if n in got:
            assert repr(got[n]) == repr(want)
        else:  # an impulse it does not name: no direction (the evaluations give 0)
            assert want == (0.0, 0.0)


# ---- the residual check's value and magnitude, leaves inline, against the plain walk ------
from momentum_cli.expr import Add  # noqa: E402
from momentum_cli.report.model import value_and_magnitude  # noqa: E402


def _slow_value_and_magnitude(e, values):
    """`value_and_magnitude` as it was written first: a call per node."""
    import math as m

    t = type(e)
    if t is Add:
        vals, mags = [], []
        for x in e.terms:
            v, g = _slow_value_and_magnitude(x, values)
            vals.append(v)
            mags.append(g)
        return m.fsum(vals), sum(mags)
    if t is Mul:
        fs = e.factors
        for f in fs:
            if (type(f) is Const or type(f) is Known) and f.value == 0.0:
                return 0.0, 0.0
        sums = [f for f in fs if type(f) is Add]
        if len(sums) == 1:
            r = k = 1.0
            for f in fs:
                if f is sums[0]:
                    v, g = _slow_value_and_magnitude(f, values)
                else:
                    v = evaluate(f, values)
                    k *= v
                r *= v
            return r, abs(k) * g
    v = evaluate(e, values)
    return v, abs(v)


@settings(max_examples=200, deadline=None)
@given(TREES, st.dictionaries(NAMES, NUMBERS.filter(lambda x: isinstance(x, float))))
def test_value_and_magnitude_equals_the_walk_per_node(e, values):
    def run(f):
        try:
            return repr(f(e, values))
        except Exception as exc:  # noqa: BLE001 - the same failure, by type
            return type(exc)
    assert run(value_and_magnitude) == run(_slow_value_and_magnitude)
