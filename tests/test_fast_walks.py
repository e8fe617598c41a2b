"""The expression walks with leaves handled inline (expr.affine, evaluate, variables;
bounds.derivatives, term_size) give bit-for-bit what the plain recursive walks give, and
the compiler's repeat test (`_Compiler.eq`) decides as the `principle|text` keys did.

The reference walks below are the plain recursions the fast ones replaced, written
out again here: every equation, answer and alternative form of every example and of
some generated chains is walked both ways, at the solved values, with the block of
each equation, every unknown, and none as the affine block. Floats are compared by
repr (signed zeros count)."""
from __future__ import annotations

import math

import pytest
from conftest import EXAMPLES

from momentum_cli import bounds
from momentum_cli.bench import chain_text
from momentum_cli.compile import _Compiler
from momentum_cli.diagnostics import ProblemError
from momentum_cli.expr import (
    FUNCS,
    Add,
    Const,
    Fn,
    Known,
    Mul,
    NonLinear,
    Pow,
    Var,
    _affine,
    _Reals,
    affine,
    evaluate,
    is_zero,
    variables,
)
from momentum_cli.scene import build
from momentum_cli.solve import solve_scene
from momentum_cli.source import Source
from momentum_cli.syntax import parse


# ---- the plain walks ----------------------------------------------------------------------
def ref_evaluate(e, values):
    t = type(e)
    if t is Const or t is Known:
        return e.value
    if t is Var:
        return values[e.name]
    if t is Add:
        return math.fsum(ref_evaluate(x, values) for x in e.terms)
    if t is Mul:
        for f in e.factors:
            if (type(f) is Known or type(f) is Const) and f.value == 0.0:
                return 0.0
        r = 1.0
        for f in e.factors:
            r *= ref_evaluate(f, values)
        return r
    if t is Pow:
        return ref_evaluate(e.base, values) ** e.exp
    return float(FUNCS[e.name](ref_evaluate(e.arg, values)))


def ref_variables(e, out=None):
    out = set() if out is None else out
    t = type(e)
    if t is Var:
        out.add(e.name)
    elif t is Add:
        for x in e.terms:
            ref_variables(x, out)
    elif t is Mul:
        for f in e.factors:
            if (type(f) is Const or type(f) is Known) and f.value == 0.0:
                return out
        for f in e.factors:
            ref_variables(f, out)
    elif t is Pow:
        ref_variables(e.base, out)
    elif t is Fn:
        ref_variables(e.arg, out)
    return out


def ref_grad(e, w, values, out):
    t = type(e)
    if t is Var:
        out[e.name] = out.get(e.name, 0.0) + w
    elif t is Add:
        for x in e.terms:
            ref_grad(x, w, values, out)
    elif t is Mul:
        fs = e.factors
        if any(is_zero(f) for f in fs):
            return
        vals = [ref_evaluate(f, values) for f in fs]
        for i, f in enumerate(fs):
            if type(f) is Const or type(f) is Known:
                continue
            k = w
            for j, v in enumerate(vals):
                if j != i:
                    k *= v
            ref_grad(f, k, values, out)
    elif t is Pow:
        if type(e.base) is not Const and type(e.base) is not Known:
            ref_grad(e.base, w * e.exp * ref_evaluate(e.base, values) ** (e.exp - 1.0), values,
                     out)
    elif t is Fn:
        if type(e.arg) is not Const and type(e.arg) is not Known:
            a = ref_evaluate(e.arg, values)
            d = {"sin": lambda: math.cos(a), "cos": lambda: -math.sin(a),
                 "tan": lambda: 1 / math.cos(a) ** 2, "exp": lambda: math.exp(a),
                 "asin": lambda: 1 / math.sqrt(1 - a * a),
                 "acos": lambda: -1 / math.sqrt(1 - a * a), "atan": lambda: 1 / (1 + a * a),
                 "ln": lambda: 1 / a, "log": lambda: 1 / a,
                 "abs": lambda: math.copysign(1.0, a)}[e.name]()
            ref_grad(e.arg, w * d, values, out)


def ref_derivatives(e, values):
    out: dict = {}
    try:
        ref_grad(e, 1.0, values, out)
    except (KeyError, ValueError, ZeroDivisionError, OverflowError):
        return {v: math.inf for v in ref_variables(e)}
    return out


def ref_term_size(e, values):
    t = type(e)
    if t is Const or t is Known:
        return abs(e.value)
    if t is Var:
        return abs(values[e.name])
    if t is Add:
        return sum(ref_term_size(x, values) for x in e.terms)
    if t is Mul:
        if any(is_zero(f) for f in e.factors):
            return 0.0
        r = 1.0
        for f in e.factors:
            r *= ref_term_size(f, values)
        return r
    if t is Pow:
        if e.exp > 0:
            return ref_term_size(e.base, values) ** e.exp
        return abs(ref_evaluate(e, values))
    v = abs(ref_evaluate(e, values))
    try:
        slope = bounds._fn_slope(e, values)
    except (ValueError, ZeroDivisionError, OverflowError):
        return v
    return max(v, slope * ref_term_size(e.arg, values))


# ---- comparing ----------------------------------------------------------------------------
def outcome(f, *args):
    """f's result with floats as repr (signed zeros, nan), or the exception's type."""
    try:
        return _reprs(f(*args))
    except (KeyError, ValueError, ZeroDivisionError, OverflowError, NonLinear) as exc:
        return type(exc).__name__


def _reprs(x):
    if isinstance(x, float):
        return repr(x)
    if isinstance(x, dict):
        return [(k, _reprs(v)) for k, v in x.items()]  # the order counts too
    if isinstance(x, (tuple, list)):
        return [_reprs(v) for v in x]
    if isinstance(x, set):
        return sorted(x)
    return x


def walks_agree(e, values, blocks) -> None:
    assert outcome(evaluate, e, values) == outcome(ref_evaluate, e, values)
    assert list(variables(e)) == list(ref_variables(e))  # the same insertion order
    assert outcome(bounds.derivatives, e, values) == outcome(ref_derivatives, e, values)
    assert outcome(bounds.term_size, e, values) == outcome(ref_term_size, e, values)
    for block in blocks:
        assert outcome(affine, e, block, values) == \
            outcome(_affine, e, block, values, _Reals), (block, e)


def scenes():
    for path in sorted(EXAMPLES.glob("*.mom")):
        yield path.name, path.read_text(encoding="utf-8")
    for n in (2, 5, 30):
        yield f"chain {n}", chain_text(n)


@pytest.mark.parametrize("name,text", [pytest.param(n, t, id=n) for n, t in scenes()])
def test_fast_walks_equal_plain_walks(name, text):
    try:
        sol = solve_scene(build(parse(Source(name, text))))
    except ProblemError:
        pytest.skip("the example is an error case")
    system, values = sol.system, sol.values
    everything = set(system.unknowns)
    of_block = {k: set(b.unknowns) for b in sol.structure.blocks for k in b.equations}
    exprs = [(e.residual, of_block.get(e.index, set())) for e in system.equations]
    exprs += [(f.expr, set()) for f in system.finds]
    exprs += [(f.alt, set()) for f in system.finds if f.alt is not None]
    partial = dict(list(values.items())[: len(values) // 2])  # some unknowns missing
    for e, block in exprs:
        walks_agree(e, values, [block, everything, set()])
        walks_agree(e, partial, [block])


def test_fast_walks_corner_cases():
    x, y = Var("x"), Var("y")
    values = {"x": -0.0, "y": 3.0}
    cases = [
        Add((Const(0.0), x, Mul((Const(-1.0), x)))),  # cancels to a signed zero
        Mul((Known("m", 2.0), Add((x, Mul((Const(-1.0), y)))))),
        Mul((Known("k", 0.0), Var("missing"))),  # a zero factor hides a missing value
        Mul((Var("missing"), Known("k", 0.0))),
        Mul((x, y)),  # not affine in {x, y}
        Add((Pow(Add((x, y)), 2.0), Fn("sin", y), Mul((Const(3.0), Fn("cos", x))))),
        Pow(Const(0.0), -1.0),
        Add((Var("missing"), Const(1.0))),
    ]
    for e in cases:
        walks_agree(e, values, [{"x"}, {"x", "y"}, set(), {"y"}])


def _compiler():
    return _Compiler(build(parse(Source("c.mom", chain_text(2)))), {})


def test_repeat_test_keeps_the_first_of_equal_equations():
    c = _compiler()
    x, y = Var("x"), Var("y")
    assert c.eq(x, y, "p", "g", None) is not None
    assert c.eq(y, x, "p", "g", None) is not None  # prints differently: kept
    assert c.eq(x, y, "p", "g", None) is None  # the same principle and text: a repeat
    assert c.eq(x, y, "q", "g", None) is not None  # another principle: kept
    assert [e.index for e in c.equations] == [0, 1, 2]


def test_repeat_test_with_a_bar_in_a_principle_uses_the_keys():
    """`principle|text` keys can meet across principles when a principle holds a `|`:
    from then on the keys decide, with every earlier equation among them."""
    c = _compiler()
    x, y = Var("x"), Var("y")
    assert c.eq(x, y, "p", "g", None) is not None
    assert c.eq(x, y, "a|b", "g", None) is not None
    assert c.eq(x, y, "p", "g", None) is None
    assert c.eq(x, y, "a|b", "g", None) is None
    assert c.eq(y, x, "p", "g", None) is not None
    assert len(c.equations) == 3


# ---- building: mul and add take shortcuts for two plain factors or terms ------------------
def ref_mul(a, b):
    """The general fold of `mul` (no shortcut beyond the 0 and 1 of a constant)."""
    from momentum_cli.expr import ZERO, keeps

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
    fs = (a.factors if ta is Mul else (a,)) + (b.factors if tb is Mul else (b,))
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


def shape(e):
    t = type(e)
    if t is Const:
        return ("C", repr(e.value))
    if t is Known:
        return ("K", e.name, repr(e.value))
    if t is Var:
        return ("V", e.name)
    if t is Add:
        return ("+", *map(shape, e.terms))
    if t is Mul:
        return ("*", *map(shape, e.factors))
    if t is Pow:
        return ("^", shape(e.base), e.exp)
    return (e.name, shape(e.arg))


def test_mul_and_add_shortcuts_build_the_general_trees():
    from momentum_cli.expr import add, mul

    x, y = Var("x"), Var("y")
    nodes = [Const(2.5), Const(1.0), Const(0.0), Const(-0.0), Const(math.nan), Const(math.inf),
             Const(-1.0), Const(0.5), Known("m", 3.0),
             Known("z", 0.0), x, Add((x, y)), Mul((Const(-1.0), x)), Mul((x, y)),
             Pow(x, 2.0), Fn("sin", y)]
    for a in nodes:
        for b in nodes:
            assert shape(mul(a, b)) == shape(ref_mul(a, b)), (a, b)
            ta, tb = type(a), type(b)
            if ta is Const and a.value == 0.0:
                want = b
            elif tb is Const and b.value == 0.0:
                want = a
            elif ta is Const and tb is Const:
                want = Const(a.value + b.value)
            else:
                want = Add((a.terms if ta is Add else (a,)) + (b.terms if tb is Add else (b,)))
            assert shape(add(a, b)) == shape(want), (a, b)


# ---- the sparse solve's back substitution ---------------------------------------------------
def ref_lu_solve(lu, b):
    """SparseLU.solve as it was: pivot rows read from their dicts on every solve."""
    rhs = [lu.conv(v) for v in b]
    for i, _j, ops in lu.steps:
        ri = rhs[i]
        if ri:
            for k, f in ops:
                rhs[k] -= f * ri
    x = {}
    for i, j, _ in reversed(lu.steps):
        row = lu.rows[i]
        s = rhs[i] - sum(v * x[c] for c, v in row.items() if c != j)
        x[j] = s / row[j]
    return [x[j] for j in range(lu.n)]


@pytest.mark.parametrize("exact", [False, True])
def test_sparse_solve_replays_as_before(exact):
    import random

    from momentum_cli.linalg import SparseLU

    rng = random.Random(7)
    for n in (1, 5, 40) if exact else (1, 5, 40, 200):
        rows = []
        for i in range(n):  # a chain with some long-range couplings and a wide scale
            row = {i: rng.uniform(0.5, 2.0) * 10 ** rng.randint(-8, 8)}
            for c in (i - 1, i + 1, rng.randrange(n)):
                if 0 <= c < n and c != i:
                    row[c] = rng.uniform(-1.0, 1.0) * 10 ** rng.randint(-8, 8)
            rows.append(row)
        lu = SparseLU(rows, n, exact=exact)
        for _ in range(3):
            b = [rng.uniform(-1.0, 1.0) for _ in range(n)]
            got, want = lu.solve(b), ref_lu_solve(lu, b)
            assert got == want if exact else [repr(v) for v in got] == [repr(v) for v in want]


# ---- one unknown, one equation --------------------------------------------------------------
def _solved(f, *args):
    from momentum_cli.linalg import SingularError

    try:
        x, q = f(*args)
    except SingularError as exc:
        return ("singular", repr(exc.cond))
    return [repr(v) for v in x], [(k, _reprs(getattr(q, k))) for k in q._fields]


def test_one_by_one_blocks_solve_as_the_general_path():
    import random

    from momentum_cli.linalg import solve, solve_rows

    rng = random.Random(11)
    specials = [0.0, -0.0, 1.0, -1.0, 3.0, 1e-300, -5e-324, 1e300, -1.7e308, 0.1, 2.0**-1074,
                math.inf, -math.inf, math.nan]
    values = specials + [rng.uniform(-1, 1) * 10 ** rng.randint(-300, 300) for _ in range(400)]
    for a in values:
        for b in rng.sample(values, 12) + [0.0, -0.0, a, -a, a * (1 + 2**-52)]:
            assert _solved(solve, [{0: a}], [b], 1) == \
                _solved(solve_rows, [{0: a}], [b], 1), (a, b)


def test_abs_inverse_of_one_entry():
    """bounds._abs_inverse of a 1x1 matrix: what its Gauss-Jordan gives, |(1/a)/... |, or
    None when the entry is 0 or not finite."""
    for a in (3.0, -0.1, 1e-300, -1e300, 2.0**-1074, 0.0, -0.0, math.inf, math.nan):
        got = bounds._abs_inverse([{0: a}])
        piv_row = [a / a, 1.0 / a] if a != 0.0 and math.isfinite(a) else None
        want = None if piv_row is None else [[abs(piv_row[1])]]
        assert _reprs(got) == _reprs(want), a
    assert bounds._abs_inverse([{}]) is None


# ---- the scene's unit walk, and unit readings ----------------------------------------------
def ref_units(root, limit=200):
    """unit_system._units as it was: every node's fields, spans included."""
    from momentum_cli.unit_system import _LEAF

    out, stack = [], [(root, 0)]
    while stack:
        node, depth = stack.pop()
        if depth < 0:
            out.append(node)
            continue
        if depth > limit or node is None or isinstance(node, _LEAF):
            continue
        if isinstance(node, (list, tuple)):
            stack.extend((x, depth + 1) for x in reversed(node))
            continue
        for f in reversed(getattr(type(node), "_fields", None) or ()):
            v = getattr(node, f, None)
            if f == "unit" and isinstance(v, str):
                stack.append((v, -1))
            elif v is not None and not isinstance(v, _LEAF):
                stack.append((v, depth + 1))
    return out


@pytest.mark.parametrize("name,text", [pytest.param(n, t, id=n) for n, t in scenes()])
def test_unit_walk_finds_what_the_full_walk_finds(name, text):
    from momentum_cli.unit_system import _units

    try:
        doc = parse(Source(name, text))
    except ProblemError:
        pytest.skip("not parsed")
    assert _units(doc) == ref_units(doc)


def test_unit_readings_are_fresh_lists():
    from momentum_cli.units import parse_unit

    first = parse_unit("lb*ft/s^2")
    first.append("changed")
    assert parse_unit("lb*ft/s^2") == first[:-1] and len(first[:-1]) == 2
