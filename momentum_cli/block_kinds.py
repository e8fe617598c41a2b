"""Solve stage: small linear blocks of one kind, solved and bounded by one generated
function per kind instead of the general path's walk through rows, dicts and tables.

A sequence of impacts repeats a few kinds of block: the same rows' shapes (`rowcode`)
with the block's unknowns at the same places in them, other numbers and names (the
10^4-impact cradle: one kind of three-unknown block, two kinds of one-unknown block,
10^4 times each, one after the other: each needs the one before, so they cannot be
batched). A kind met AFTER times gets straight-line code, with locals, for its rows'
coefficients and right-hand sides (`rowcode.emit_affine`), and for its rows' slopes and
sizes in the error bounds (`rowcode.emit_gs`); a matrix met for the first time is
factored by `linalg.factor_small`, and its elimination replayed by code made once per
pattern of pivots and row operations, its numbers passed as one tuple.

In: a block (its rows' shapes), the values, and for the bounds the sizes and bounds of
the unknowns before it. Out: its BlockReport, and its unknowns' sizes and bounds, bit for
bit what `solve._solve_block`/`_solve_one` and `bounds._square`/`_one` give: the same
float operations in the same order (tests/test_block_kinds.py). None wherever that path
has more to say (a zero or non-finite coefficient, a singular matrix, a missing value,
a failing walk); it then runs as always, from the start.
"""
from __future__ import annotations

import math

from . import rowcode
from .block_memo import solve_one
from .bounds import ROUNDOFF, _matrix_parts
from .linalg import EPS, Quality, SingularError, factor_small, _SPLIT
from .rowcode import _Src, _Stop, _parse, emit_affine, emit_gs, shape_of

FUSE = True  # tests turn it off: every block takes the general path
AFTER = 64  # a kind gets its code once met this often (a small file's kinds never do)
LIMIT = 256  # kinds kept (the table is emptied when full)
MATRICES = 4096  # matrices kept per kind
FAILS = (KeyError, ValueError, ZeroDivisionError, OverflowError, TypeError)

_KINDS: dict = {}  # (ids of the rows' shape keys, where the unknowns sit) -> Kind | count
_RUNS: dict = {}  # a pattern of pivots and row operations -> its replay function


class Kind:
    """A kind of block: its rows' shape keys (held: the table is keyed by their ids),
    its generated solve and bounds, and the parts of each matrix met (by its numbers).
    `fill(shapes, names, quality, values, size, err)`: its bounds step (`bound`), for
    `bounds.propagate`, which imports nothing from here."""

    __slots__ = ("keys", "n", "solve", "bound", "mats", "parts", "cols", "rows", "next")

    def __init__(self, keys, n):
        self.keys, self.n = keys, n
        self.solve = self.bound = None  # None: this kind takes the general path
        self.mats: dict = {}  # the coefficients' floats -> (replay, its numbers) | False
        self.parts: dict = {}  # the slopes' floats -> (units, |A^-1| rows) flat | False
        self.cols = ()  # the coefficients' columns, row by row, in the rows' dict order
        self.rows = ()  # the slopes' columns, row by row, in the walk's dict order
        self.next = None  # the kind of the block after one of this kind, last time


MISS = object()  # a kind's solve: the block is not of this kind
_PREV: list = [None]  # the kind of the block solved last (its `next`: a guess)


def take(block, equations, values, report):
    """(its BlockReport, (Kind, the rows' shapes)) of a square block solved by its
    kind's code (`report`: the BlockReport class); None where the general path must
    solve it (no kind with code yet, or a number it must judge). The kind that followed
    the last block's last time is tried first (a sequence of impacts repeats its kinds
    in a period): its code checks the block is of its kind."""
    ks = block.equations
    n = len(ks)
    if n != len(block.unknowns):
        return None
    if n == 1:
        sh = shape_of(equations[ks[0]].residual)
        if sh is None:
            return None
        shapes = (sh,)
    else:
        shapes = tuple([shape_of(equations[k].residual) for k in ks])
        if None in shapes:
            return None
    prev = _PREV[0]
    kind = prev.next if prev is not None else None
    if kind is not None and kind.n != n:
        kind = None
    try:
        got = kind.solve(*shapes, block, values, kind.mats, report) \
            if kind is not None else MISS
        if got is MISS:
            kind = _find(block, shapes, report)
            if kind is None:
                _PREV[0] = None
                return None
            if prev is not None:
                prev.next = kind
            got = kind.solve(*shapes, block, values, kind.mats, report)
        _PREV[0] = kind
        if type(got) is tuple:  # a matrix met for the first time: its replay, then again
            mats = kind.mats
            if len(mats) >= MATRICES:
                mats.clear()
            mats[got] = _matrix(kind, got)
            got = kind.solve(*shapes, block, values, mats, report)
    except (*FAILS, SingularError):
        return None
    if got is None or got is MISS:
        return None
    return got, (kind, shapes)


def _find(block, shapes, report):
    """The Kind of a block (its rows' `shapes`) if it has code; None otherwise (counted
    towards its kind's AFTER). A kind: each row's shape key (by id, held by the Kind)
    and, at each of its name positions, the block's column there or None."""
    names = block.unknowns
    get = {v: j for j, v in enumerate(names)}.get
    key = (*[id(sh[0]) for sh in shapes], *[tuple(map(get, sh[2])) for sh in shapes])
    hit = _KINDS.get(key)
    if type(hit) is Kind:
        for a, sh in zip(hit.keys, shapes):
            if a is not sh[0]:  # another shape at a reused id: not this kind
                return None
        return hit if hit.solve is not None else None
    count = hit or 0
    if count < AFTER:
        if len(_KINDS) >= LIMIT:
            _KINDS.clear()
        _KINDS[key] = count + 1
        return None
    layouts = [[-1 if j is None else j for j in lay] for lay in key[len(shapes):]]
    kind = _make(shapes, layouts, report)
    _KINDS[key] = kind
    return kind if kind.solve is not None else None


def _make(shapes, layouts, report) -> Kind:
    """A kind's code, generated; without it (solve None) where the rows are not linear in
    the block's unknowns or a column is empty (the general path says why)."""
    kind = Kind(tuple(sh[0] for sh in shapes), len(shapes))
    try:
        kind.solve, kind.cols = _solve_code(kind, layouts, report)
        kind.bound, kind.rows = _bound_code(kind, layouts)
    except _Stop:
        kind.solve = kind.bound = None
    return kind


def _head(name: str, n: int, tail: str) -> str:
    """A generated function's head: the rows' shapes, then `tail`."""
    return f"{name}({''.join(f'sh{r}, ' for r in range(n))}{tail})"


def _unpack(s: _Src, n: int) -> None:
    s.lines += [f"    _k{r}, c{r}, n{r} = sh{r}" for r in range(n)]


def _firsts(key) -> list:
    """The name positions of a shape that first hold their name (the shape's readers
    checked that the others repeat it, and that these differ)."""
    out = []

    def walk(nd):
        if nd.kind == "v" and nd.same == nd.i:
            out.append(nd.i)
        for k in nd.kids:
            walk(k)

    walk(_parse(key)[0])
    return out


def _fits(s: _Src, kind: Kind, layouts) -> None:
    """Emit the test that the block is of this kind (else MISS): each row's shape key
    (identity), and each name of its rows in the block's column the kind has it in,
    or none of the block's unknowns."""
    n = kind.n
    s.lines.append(f"    if {' or '.join(f'sh{r}[0] is not K{r}' for r in range(n))}: "
                   "return MISS")
    _unpack(s, n)
    s.lines.append("    names = block.unknowns")
    s.lines.append(f"    {''.join(f'nm{j}, ' for j in range(n))}= names")
    tests = []
    for r, (key, lay) in enumerate(zip(kind.keys, layouts)):
        for i in _firsts(key):
            j = lay[i]
            tests += [f"n{r}[{i}] == nm{j}"] if j >= 0 else \
                [f"n{r}[{i}] != nm{jj}" for jj in range(n)]
    s.lines.append(f"    if not ({' and '.join(tests)}): return MISS")


def _solve_code(kind: Kind, layouts, report):
    """f(sh0, ..., block, values, mats, report) -> the block's BlockReport, its values
    set, as `solve._solve_block` (`_solve_one`) makes them: its rows by
    `rowcode.affine` (coefficient, right-hand side -const), solved by block_memo's
    factored replay (`mats`: this kind's matrices by their coefficients) or 1x1 solve;
    None where a coefficient is 0 (the general row leaves it out) or a number is not
    finite (the general path refuses the block); MISS where the block is not of this
    kind; the coefficients where `mats` lacks them (the caller adds them, calls again)."""
    n = kind.n
    s = _Src("a")
    _fits(s, kind, layouts)
    cols, coefs, rhs = [], [], []
    for r, (key, lay) in enumerate(zip(kind.keys, layouts)):
        coef, const = emit_affine(s, key, [j >= 0 for j in lay], f"c{r}", f"n{r}")
        cols.append(tuple(lay[i] for _same, _v, i in coef))
        coefs.extend(v for _same, v, _i in coef)
        rhs.append(s.tmp(f"-{const}"))
    if any(j not in {c for row in cols for c in row} for j in range(n)):
        raise _Stop
    every = coefs + rhs
    s.lines.append(f"    if {' or '.join(f'{v} == 0.0' for v in coefs)}: return None")
    s.lines.append(f"    if ({' + '.join(f'({v} - {v})' for v in every)}) != 0.0: "
                   "return None")  # x - x is 0.0 for every finite x, NaN otherwise
    if n > 1:  # floats only (block_memo keys nothing else: another number takes linalg's)
        s.lines.append(f"    if ({''.join(f'type({v}), ' for v in every)}) != FLOATS: "
                       "return None")
    if n == 1:  # `_solve_one`: block_memo's 1x1 solve, remembered by its two numbers
        a, b = coefs[0], rhs[0]
        s.lines += [f"    x, q = solve_one({a}, {b})", "    values[nm0] = x[0]",
                    "    return REPORT(block.index, names, block.equations, 'linear', "
                    f"q.cond, 0, 0.0, [[float({a})]], [float({b})], q)"]
    else:  # the matrix's replay, by its numbers; its dense rows for the report
        it = iter(coefs)
        dense = []
        for row in cols:
            got = dict(zip(row, [next(it) for _ in row]))
            dense.append("[" + ", ".join(got.get(j, "0.0") for j in range(n)) + "]")
        s.lines += [f"    C = ({''.join(v + ', ' for v in coefs)})", "    m = mats.get(C)",
                    "    if m is None: return C", "    if m is False: return None",
                    f"    x, q = m[0](m[1], {', '.join(rhs)})",
                    *(f"    values[nm{j}] = x[{j}]" for j in range(n)),
                    "    return REPORT(block.index, names, block.equations, 'linear', "
                    f"q.cond, 0, 0.0, [{', '.join(dense)}], [{', '.join(rhs)}], q)"]
    ns = {"solve_one": solve_one, "MISS": MISS, "REPORT": report,
          "FLOATS": (float,) * len(every)}
    ns.update((f"K{r}", key) for r, key in enumerate(kind.keys))
    fn = s.function(_head("solve", n, "block, values, mats, report"), ns)
    return fn, tuple(cols)


def _bound_code(kind: Kind, layouts):
    """f(sh0, ..., values, size, err, names, comps, parts) -> True once it has written
    the block's sizes and bounds into `size` and `err` as `bounds._square` (`_one`)
    does; False (nothing written) where a slope by a block unknown is 0 or not finite
    or |A^-1| is None (the general step decides); the slopes where `parts` lacks their
    matrix (the caller adds it and calls again)."""
    n = kind.n
    s = _Src("g")
    _unpack(s, n)
    s.lines += ["    w = 1.0", "    sget = size.get", "    eget = err.get"]
    inner, rows = [], []  # the slopes by the block's unknowns; each row's columns
    for r, (key, lay) in enumerate(zip(kind.keys, layouts)):
        order: list = []  # the walk's dict order: each unknown at its first slope

        def add(i, same, w, c, nm, order=order, r=r):
            g = f"g{r}_{same}"
            if same in order:
                return f"    {g} = {g} + {w}"
            order.append(same)
            return f"    {g} = 0.0 + {w}"

        _root, mag, _val = emit_gs(s, key, f"c{r}", f"n{r}", f"x{r}_", add)
        js = []
        s.lines.append(f"    sc{r} = d{r} = 0")
        for same in order:
            g = f"g{r}_{same}"
            if lay[same] >= 0:
                js.append((lay[same], g))
                inner.append(g)
            else:  # an unknown of an earlier block: its size and bound, if it moves this row
                s.lines += [f"    a = abs({g})", "    if a:",
                            f"        sc{r} += a * sget(n{r}[{same}], 0.0)",
                            f"        d{r} += a * eget(n{r}[{same}], 0.0)"]
        rows.append(js)
        s.lines.append(f"    s{r} = {mag} + sc{r}")
        s.lines.append(f"    e{r} = d{r} + ROUNDOFF * s{r}")
    if not inner:
        raise _Stop
    s.lines.append(f"    if {' or '.join(f'{g} == 0' for g in inner)}: return False")
    s.lines.append(f"    if ({' + '.join(f'({g} - {g})' for g in inner)}) != 0.0: return False")
    s.lines += [f"    {''.join(f'nm{j}, ' for j in range(n))}= names",
                *(f"    X{j} = abs(values.get(nm{j}, 0.0))" for j in range(n))]
    if n == 1:  # `bounds._one`: its one-element maxima, minima and |A^-1|
        a = inner[0]
        s.lines += [f"    aa = abs({a})", f"    rmax = abs({a})",
                    "    unit = aa / rmax if rmax > 0 else 0.0", "    big = X0 * unit",
                    "    size[nm0] = max(X0, s0 / aa, big / unit if unit > 0 else 0.0)",
                    f"    E0 = 0 + abs(1.0 / {a}) * e0",
                    "    err[nm0] = E0 + comps[0] * X0 if E0 - E0 == 0.0 else INF",
                    "    return True"]
    else:  # `bounds._square`, its matrix's parts by the slopes' numbers
        s.lines += [f"    K = ({''.join(g + ', ' for g in inner)})", "    P = parts.get(K)",
                    "    if P is None: return K", "    if P is False: return False",
                    f"    {''.join(f'u{j}, ' for j in range(n))}"
                    f"{''.join(f'i{j}_{i}, ' for j in range(n) for i in range(n))}= P",
                    f"    big = max({', '.join(f'X{j} * u{j}' for j in range(n))})"]
        for j in range(n):
            cands = [f"s{i} / abs({g})" for i, js in enumerate(rows) for jj, g in js
                     if jj == j]
            low = cands[0] if len(cands) == 1 else f"min({', '.join(cands)})"
            s.lines.append(f"    size[nm{j}] = max(X{j}, {low}, big / u{j} if u{j} > 0 "
                           "else 0.0)")
        for j in range(n):
            terms = ", ".join(f"i{j}_{i} * e{i}" for i in range(n))
            s.lines += [f"    E{j} = sum([{terms}])",
                        f"    err[nm{j}] = E{j} + comps[{j}] * X{j} if E{j} - E{j} == 0.0 "
                        "else INF"]
        s.lines.append("    return True")
    fn = s.function(_head("bound", n, "values, size, err, names, comps, parts"),
                    {"ROUNDOFF": ROUNDOFF, "fsum": math.fsum, "INF": math.inf})
    return fn, tuple(tuple(j for j, _g in js) for js in rows)


# ---- the solve ---------------------------------------------------------------------------
def _rows(kind: Kind, coefs):
    """The coefficients as `solve._solve_block`'s row dicts (column -> value)."""
    it = iter(coefs)
    return [{j: next(it) for j in cols} for cols in kind.cols]


def _matrix(kind: Kind, coefs):
    """(replay function, its numbers) of a matrix met for the first time; False where it
    is singular (the general path raises for it)."""
    n = kind.n
    try:
        F = factor_small(_rows(kind, coefs), n)
    except SingularError:
        return False
    pattern = (n, tuple(tuple(row) for row in F.A),
               tuple((col, piv, tuple(i for i, _f in ops)) for col, piv, _p, ops in F.steps))
    run = _RUNS.get(pattern)
    if run is None:
        run = _replay_code(F)
        if len(_RUNS) >= LIMIT:
            _RUNS.clear()
        _RUNS[pattern] = run
    nums = [*F.r, *F.c]
    for _col, _piv, p, ops in F.steps:
        nums.append(p)
        nums.extend(f for _i, f in ops)
    for row in F.split:
        for _j, a, ah, al in row:
            nums += (a, ah, al)
    nums += (F.norm_a, F.cond)
    return run, tuple(nums)


def _replay_code(F):
    """f(K, b0, ...) -> (x, Quality): `linalg.solve_factored(F, b)` for every matrix of
    F's pattern, its numbers K, in straight lines: `_replay`, `snap_roundoff`,
    `_backward_factored` and `_componentwise`, the same operations in the same order."""
    n = F.n
    lines = []
    k = [0]

    def num() -> str:
        k[0] += 1
        return f"k{k[0] - 1}"

    r = [num() for _ in range(n)]
    c = [num() for _ in range(n)]
    bs = [f"s{i}" for i in range(n)]
    lines += [f"    {bs[i]} = b{i} / {r[i]}" for i in range(n)]
    pos = list(bs)  # the variable at each position of `_replay`'s list
    t = [0]

    def tmp(expr: str) -> str:
        t[0] += 1
        lines.append(f"    v{t[0]} = {expr}")
        return f"v{t[0]}"

    for col, piv, _p, ops in F.steps:
        pos[col], pos[piv] = pos[piv], pos[col]
        p = num()
        tc = pos[col] = tmp(f"{pos[col]} / {p}")
        for i, _f in ops:
            f = num()
            pos[i] = tmp(f"{pos[i]} - {f} * {tc}")
    v = pos
    entries = []  # (row, col, a, ah, al) of F.split, in its order
    for i, row in enumerate(F.split):
        for j, _a, _ah, _al in row:
            entries.append((i, j, num(), num(), num()))
    norm_a, cond = num(), num()
    # snap_roundoff(A, bs, v): each row's size, then each column's round-off test
    for i in range(n):
        terms = [f"abs({a} * {v[j]})" for ii, j, a, _h, _l in entries if ii == i]
        lines.append(f"    z{i} = abs({bs[i]}) + sum([{', '.join(terms)}])")
    y = [f"y{j}" for j in range(n)]
    for j in range(n):
        tests = [f"abs({a} * {v[j]}) > 1e-15 * z{i}" for i, jj, a, _h, _l in entries
                 if jj == j]
        lines.append(f"    {y[j]} = {v[j]} if {' or '.join(tests) or 'False'} else 0.0")
    # _backward_factored(F, bs, y)
    for j in range(n):
        lines += [f"    q{j} = SPLIT * {y[j]}", f"    h{j} = q{j} - (q{j} - {y[j]})",
                  f"    l{j} = {y[j]} - h{j}"]
    for i in range(n):
        terms = [bs[i]]
        for e, (ii, j, a, ah, al) in enumerate(entries):
            if ii != i:
                continue
            lines.append(f"    p{e} = {a} * {y[j]}")
            terms += [f"-p{e}", f"-((({ah} * h{j} - p{e}) + {ah} * l{j} + {al} * h{j}) + "
                                f"{al} * l{j})"]
        lines.append(f"    r{i} = fsum([{', '.join(terms)}])")
    ay = ", ".join(f"abs({v})" for v in y)
    lines.append(f"    denom = {norm_a} * max({ay}) + max({', '.join(f'abs({b})' for b in bs)})")
    lines.append(f"    num = max({', '.join(f'abs(r{i})' for i in range(n))})")
    lines.append("    back = num / denom if denom > 0 else num")
    lines.append(f"    normwise = {cond} * max(back, EPS)")
    lines.append(f"    big = max({ay})")  # _componentwise
    for j in range(n):
        lines.append(f"    m{j} = normwise * big / abs({y[j]}) if {y[j]} != 0.0 else normwise")
    comps = ", ".join(f"m{j}" for j in range(n))
    xs = ", ".join(f"{y[j]} / {c[j]}" for j in range(n))
    lines.append(f"    return [{xs}], Quality('python', 'float', {cond}, back, "
                 f"max([{comps}]), 0, [{comps}])")
    head = f"def run(K, {''.join(f'b{i}, ' for i in range(n))}):\n"
    src = head + f"    {''.join(f'k{i}, ' for i in range(k[0]))}= K\n" + "\n".join(lines) + "\n"
    ns = {"SPLIT": _SPLIT, "EPS": EPS, "Quality": Quality, "fsum": math.fsum}
    exec(compile(src, "<block_kinds replay>", "exec"), ns)
    return ns["run"]


# ---- the bounds --------------------------------------------------------------------------
def bound(kind: Kind, shapes, names, q, values, size: dict, err: dict) -> bool:
    """`bounds._square`'s (`_one`'s) sizes and bounds of a block of `kind` (not exact),
    into `size` and `err`; False (nothing written) where the general step must decide.
    (`Kind.fill`: what `bounds.propagate` calls.)"""
    comps = q.components if q is not None and q.components else [0.0] * kind.n
    try:
        done = kind.bound(*shapes, values, size, err, names, comps, kind.parts)
        if type(done) is tuple:  # a matrix met for the first time: its parts, then again
            parts = kind.parts
            if len(parts) >= MATRICES:
                parts.clear()
            parts[done] = _parts(kind, done)
            done = kind.bound(*shapes, values, size, err, names, comps, parts)
    except FAILS:
        return False
    return done is True


Kind.fill = bound


def _parts(kind: Kind, slopes):
    """`bounds._square`'s `make` for these slopes: (each column's unit, then |A^-1| row by
    row) flat; False where |A^-1| is None (the general step bounds by the condition)."""
    A = [{} for _ in kind.rows]
    cols: list = [[] for _ in range(kind.n)]
    it = iter(slopes)
    for i, js in enumerate(kind.rows):
        Ai = A[i]
        for j in js:
            s = next(it)
            Ai[j] = s
            cols[j].append((i, abs(s)))
    _rmax, unit, inv = _matrix_parts(A, cols, True)
    return False if inv is None else (*unit, *[v for row in inv for v in row])


def enabled() -> bool:
    """Whether this solve's blocks may take their kinds' code (a small solve shapes no tree)."""
    return FUSE and rowcode.ENABLED and not rowcode._PLAIN[0]
