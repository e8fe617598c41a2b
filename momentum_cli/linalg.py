"""Linear solves for equation blocks: precision modes and error estimates.

A block arrives as sparse rows (column -> coefficient). It is equilibrated (rows,
then columns, scaled by their largest entry: the unknowns mix N*s, m/s and rad/s)
and solved in one of three precisions:

- `float`: float64. Blocks of up to SMALL unknowns by plain-Python Gauss-Jordan
  (importing numpy costs ~140 ms, more than such a solve), larger dense ones by
  LAPACK, sparse ones by our sparse elimination, O(n) on chains; from BIG unknowns
  (ball chains of 10^4 and more) by LAPACK's banded LU where they order into a narrow
  band (banded.py), on arrays.
- `refine`: the float solution, then iterative refinement with residuals computed
  exactly (error-free products summed by `math.fsum`), until the correction stops
  shrinking.
- `exact`: Gaussian elimination in rationals on the block's data as given (every
  float is the exact rational it is), so the answer is the correctly rounded
  solution and the difference to `float` is the solver's own error.

Every solve returns a `Quality`: the 1-norm condition number of the equilibrated
matrix, the backward error, and a forward relative error bound.
"""
from __future__ import annotations

import heapq
import math
from itertools import islice
from operator import truediv
from fractions import Fraction

from .records import record
from .two_product import _SPLIT, two_product as _two_product

SMALL = 12  # blocks up to this size are solved without numpy
BIG = 5000  # square sparse blocks from this size: LAPACK's banded LU (banded.py); below it
#   the Python elimination costs less than importing numpy and LAPACK (~0.2 s, measured
#   on chains: break-even near 5,000 unknowns)
EPS = 2.0**-53
SINGULAR_COND = 1e15  # equilibrated condition numbers beyond this are numerically singular
HADAMARD_COND = 1e12  # `_step_dense`: a condition bound below this is far from singular

Rows = list[dict[int, float]]


class SingularError(ArithmeticError):
    """The block is singular: exactly, or to working precision."""

    def __init__(self, cond: float, exact: bool = False, free: list[int] | None = None):
        super().__init__("singular matrix")
        self.cond = cond
        self.exact = exact
        self.free = free or []  # exactly singular: columns a null vector involves


@record
class Quality:
    method: str  # python | lapack | sparse-lu | exact
    precision: str
    cond: float  # 1-norm condition number after equilibration
    backward: float  # |b - A x| / (|A| |x| + |b|), residual computed exactly
    bound: float  # estimated relative forward error of x (largest over components)
    iterations: int = 0
    components: list | None = None  # the estimate for each unknown, relative to itself
    exact: list | None = None  # exact mode: the solution as rationals (for derived answers)


def _pow2(x: float) -> float:
    """The power of two nearest below |x| (scaling by it is exact in binary floats)."""
    if x == 0.0 or not math.isfinite(x):
        return 1.0
    return math.ldexp(1.0, math.frexp(x)[1] - 1)


def equilibrate(rows: Rows, b: list[float], n: int):
    """Row then column scaling by powers of two near the largest magnitude.

    Powers of two change no digit of any entry, so the exact and refined solves see
    the block's data exactly as given: (rows2, b2, r, c).
    """
    r = [_pow2(max(map(abs, row.values()), default=0.0)) for row in rows]
    c = [0.0] * n
    for row, ri in zip(rows, r):
        for j, v in row.items():
            a = abs(v) / ri
            if a > c[j]:
                c[j] = a
    c = [_pow2(x) for x in c]
    rows2 = [{j: v / r[i] / c[j] for j, v in row.items()} for i, row in enumerate(rows)]
    return rows2, [b[i] / r[i] for i in range(len(b))], r, c


def solve(rows: Rows, b: list[float], n: int, precision: str = "float"):
    """x with A x = b (A given by sparse rows), and the Quality of the solve."""
    if n == 1 and precision == "float" and len(rows) == 1 and len(rows[0]) == 1 and \
            0 in rows[0]:  # one unknown, one equation: most blocks of a large scene
        return solve_one(rows[0][0], b[0])
    return solve_rows(rows, b, n, precision)


def solve_rows(rows: Rows, b: list[float], n: int, precision: str = "float"):
    """`solve` by the general path (equilibrate, eliminate, estimate)."""
    if precision == "exact":
        # rows may hold rationals (formed exactly): eliminate them as they are
        q = _exact(rows, b, n)
        A = equilibrate([{j: float(v) for j, v in row.items()} for row in rows],
                        [float(v) for v in b], n)[0]
        return [float(v) for v in q], Quality("exact", "exact", _cond(A, n), 0.0, 0.0, 0,
                                              [0.0] * n, q)
    if precision == "float" and n >= BIG and len(rows) == n:
        got = _big_float(rows, b, n)
        if got is not None:
            return got
    A, bs, r, c = equilibrate(rows, b, n)
    y, cond, method = _float_solve(A, bs, n)
    if precision == "float":
        y = snap_roundoff(A, bs, y)
    back = _backward(A, bs, y)
    iters = 0
    if precision == "refine":
        y, back, iters, last = _refine(A, bs, y, n)
    normwise = cond * max(back, EPS)
    comps = _componentwise(y, normwise)
    if precision == "refine" and iters:
        comps = [min(v, max(last, EPS)) for v in comps]
    x = [y[j] / c[j] for j in range(n)]
    return x, Quality(method, precision, cond, back, max(comps, default=normwise), iters, comps)


def solve_one(a: float, b: float):
    """`solve_rows` of a 1x1 block in float, step for step on scalars: the same x and
    Quality to the last bit (tests/test_fast_walks.py), without the lists and dicts the
    general path builds (a 10^4-ball chain has 10^4 such blocks)."""
    r = _pow2(abs(a))  # equilibrate: row, then column, by powers of two
    c = _pow2(abs(a) / r)
    A = a / r / c
    bs = b / r
    norm1 = abs(A)  # _gauss_jordan
    if A == 0.0:
        raise SingularError(math.inf)
    y = bs / A
    cond = norm1 * abs(1.0 / A)
    if not math.isfinite(cond) or cond > SINGULAR_COND:
        raise SingularError(cond)
    t = abs(A * y)  # snap_roundoff
    if not t > 1e-15 * (abs(bs) + t):
        y = 0.0
    p, e = _two_product(A, y)  # _backward
    num = abs(math.fsum([bs, -p, -e]))
    denom = abs(A) * abs(y) + abs(bs)
    back = num / denom if denom > 0 else num
    normwise = cond * max(back, EPS)
    comp = normwise * abs(y) / abs(y) if y != 0.0 else normwise  # _componentwise
    return [y / c], Quality("python", "float", cond, back, comp, 0, [comp])


class Factored:
    """A small float block's matrix, equilibrated and eliminated once (`factor_small`):
    the scalings, the Gauss-Jordan steps as they act on the right-hand side, and the
    condition number. Blocks of one kind (the same matrix, another right-hand side: each
    impact of a sequence) replay it (`solve_factored`) instead of eliminating again."""

    __slots__ = ("n", "r", "c", "A", "steps", "cond", "split", "norm_a")

    def __init__(self, n, r, c, A, steps, cond):
        self.n, self.r, self.c, self.A, self.steps, self.cond = n, r, c, A, steps, cond
        # `_backward`'s matrix-only parts: each entry's Veltkamp split, the row-sum norm
        self.split = [[(j, v, *_halves(v)) for j, v in row.items()] for row in A]
        self.norm_a = max((sum(abs(v) for v in row.values()) for row in A), default=0.0)


def _halves(a: float):
    """(ah, al): `two_product`'s split of one factor (the same operations)."""
    t = _SPLIT * a
    ah = t - (t - a)
    return ah, a - ah


def factor_small(rows: Rows, n: int) -> Factored:
    """`equilibrate` and `_gauss_jordan` of a square block of 2..SMALL unknowns, recorded:
    the pivots and every row operation depend on the matrix alone, so the right-hand
    side's column can be replayed (raises SingularError as `_gauss_jordan` does)."""
    A, _, r, c = equilibrate(rows, [], n)
    steps, cond = _eliminate(A, n)
    return Factored(n, r, c, A, steps, cond)


def _eliminate(A: Rows, n: int):
    """Gauss-Jordan with partial pivoting on [A | I], recorded: (steps, cond), each step
    (col, pivot row, pivot, ((row, factor), ...)); the inverse gives the cond. A
    right-hand side's column takes the same operations when `_replay`ed."""
    M = [[A[i].get(j, 0.0) for j in range(n)] + [1.0 if k == i else 0.0 for k in range(n)]
         for i in range(n)]
    # the columns' sums of |entries|, each down its rows in order (zip(*M): the columns)
    norm1 = max((sum(map(abs, col)) for col in islice(zip(*M), n)), default=0.0)
    steps = []
    for col in range(n):
        piv = col  # the first row of the largest |entry| (as max with a key picks it)
        big = abs(M[col][col])
        for i in range(col + 1, n):
            a = abs(M[i][col])
            if a > big:
                piv, big = i, a
        if M[piv][col] == 0.0:
            raise SingularError(math.inf)
        M[col], M[piv] = M[piv], M[col]
        p = M[col][col]
        rowp = [x / p for x in M[col]]
        M[col] = rowp
        ops = []
        for i in range(n):
            if i != col:
                f = M[i][col]
                if f != 0.0:
                    ops.append((i, f))
                    M[i] = [a - f * b for a, b in zip(M[i], rowp)]
        steps.append((col, piv, p, tuple(ops)))
    inv_norm1 = max(sum(map(abs, col)) for col in islice(zip(*M), n, None))
    cond = norm1 * inv_norm1
    if not math.isfinite(cond) or cond > SINGULAR_COND:
        raise SingularError(cond)
    return tuple(steps), cond


def _replay(steps, b: list[float]) -> list[float]:
    """The right-hand side's column through `_eliminate`'s steps: the elimination's own
    float operations on it, in their order."""
    v = list(b)
    for col, piv, p, ops in steps:
        v[col], v[piv] = v[piv], v[col]
        t = v[col] = v[col] / p
        for i, f in ops:
            v[i] = v[i] - f * t
    return v


def solve_factored(F: Factored, b: list[float]):
    """`solve_rows(rows, b, n, "float")` of a block `F` was factored from: the same floats,
    the same Quality (the right-hand side's column takes the elimination's very
    operations in their order; the rest is the general path's own code)."""
    n, r, c, A = F.n, F.r, F.c, F.A
    bs = [b[i] / r[i] for i in range(len(b))]
    v = _replay(F.steps, bs)
    y = snap_roundoff(A, bs, v)
    back = _backward_factored(F, bs, y)
    cond = F.cond
    normwise = cond * max(back, EPS)
    comps = _componentwise(y, normwise)
    x = [y[j] / c[j] for j in range(n)]
    return x, Quality("python", "float", cond, back, max(comps, default=normwise), 0, comps)


def _backward_factored(F: Factored, b: list[float], x: list[float]) -> float:
    """`_backward(F.A, b, x)` with the matrix's parts taken from F: `residual`'s
    `two_product`s split each coefficient once per kind, each x once per solve (the
    same operations on the same numbers: the same residual to the last bit)."""
    halves = [_halves(v) for v in x]
    r = []
    fsum = math.fsum
    for i, row in enumerate(F.split):
        terms = [b[i]]
        for j, a, ah, al in row:
            xj = x[j]
            bh, bl = halves[j]
            p = a * xj
            terms.append(-p)
            terms.append(-(((ah * bh - p) + ah * bl + al * bh) + al * bl))
        r.append(fsum(terms))
    denom = F.norm_a * max((abs(v) for v in x), default=0.0) + max((abs(v) for v in b),
                                                                    default=0.0)
    num = max((abs(v) for v in r), default=0.0)
    return num / denom if denom > 0 else num


def snap_roundoff(A: Rows, b: list[float], y: list[float]) -> list[float]:
    """Zero the unknowns whose every term is round-off against its equation's size.

    Compared row by row, in each equation's own units (an impulse is never measured
    against a velocity), so a true small value is never lost; goldens then show 0
    rather than 1e-17, and the componentwise error bound is not inflated by noise.
    """
    size = [abs(bi) + sum(abs(a * y[j]) for j, a in row.items()) for row, bi in zip(A, b)]
    small = [True] * len(y)
    for i, row in enumerate(A):
        for j, a in row.items():
            if abs(a * y[j]) > 1e-15 * size[i]:
                small[j] = False
    return [0.0 if small[j] else v for j, v in enumerate(y)]


def _componentwise(y: list[float], normwise: float) -> list[float]:
    """Each component's relative error bound: the normwise error |dx| <= normwise*|x|
    as seen by that component (equilibrated units). A chain of masses over 24
    decades has velocities over 24 decades: a normwise 1e-14 can be all of a small
    component. An exact zero is reported against the normwise bound."""
    big = max((abs(v) for v in y), default=0.0)
    return [normwise * big / abs(v) if v != 0.0 else normwise for v in y]


def _float_solve(A: Rows, b: list[float], n: int):
    if n <= SMALL:
        y, cond = _gauss_jordan(A, b, n)
        return y, cond, "python"
    nnz = sum(len(row) for row in A)
    if nnz > 0.2 * n * n or n < 60:
        return (*_lapack(A, b, n), "lapack")
    if n >= BIG:
        got = _banded(A, b, n)
        if got is not None:
            return (*got, "banded-lu")
    return (*_sparse_lu(A, b, n), "sparse-lu")


def _gauss_jordan(A: Rows, b: list[float], n: int):
    """Gauss-Jordan with partial pivoting on [A | b | I] (`_eliminate` on [A | I], b's
    column replayed through its steps: the same operations); the inverse gives the cond."""
    steps, cond = _eliminate(A, n)
    return _replay(steps, b), cond


def _dense(A: Rows, n: int):
    import numpy as np

    M = np.zeros((n, n))
    for i, row in enumerate(A):
        for j, v in row.items():
            M[i, j] = v
    return M


def _lapack(A: Rows, b: list[float], n: int):
    import numpy as np

    M = _dense(A, n)
    try:
        lu_cond = float(np.linalg.cond(M, 1))
    except np.linalg.LinAlgError:
        lu_cond = math.inf
    if not math.isfinite(lu_cond) or lu_cond > SINGULAR_COND:
        raise SingularError(lu_cond)
    y = np.linalg.solve(M, np.array(b))
    return [float(v) for v in y], lu_cond


def _sparse_lu(A: Rows, b: list[float], n: int):
    """Sparse elimination for large sparse blocks: O(n) for chains of contacts."""
    lu = SparseLU(A, n, exact=False)
    y = lu.solve(b)
    cond = lu.norm1 * lu.inverse_norm1_estimate()
    if not math.isfinite(cond) or cond > SINGULAR_COND or not all(map(math.isfinite, y)):
        raise SingularError(cond)
    return y, cond


# |A^-1|_1 is estimated from solves with these right-hand sides (LINPACK style)
PATTERNS = (lambda k, n: 1.0, lambda k, n: (-1.0) ** k, lambda k, n: (-1.0) ** (k // 2),
            lambda k, n: 1.0 + k / n)


def _big_float(rows: Rows, b: list[float], n: int):
    """`solve_rows` in float of a large block that orders into a narrow band, on arrays
    (banded.solve_float), or None to take the general path."""
    from . import banded

    if sum(len(row) for row in rows) > 0.2 * n * n:
        return None  # dense: LAPACK's general solve, as _float_solve chooses
    got = banded.solve_float(rows, b, n, PATTERNS, EPS)
    if got is None:
        return None
    x, cond, back, comps = got
    if not math.isfinite(cond) or cond > SINGULAR_COND:
        raise SingularError(cond)
    normwise = cond * max(back, EPS)
    return x, Quality("banded-lu", "float", cond, back, max(comps, default=normwise), 0, comps)


def _banded(A: Rows, b: list[float], n: int):
    """`_sparse_lu` by LAPACK's banded LU where the block orders into a narrow band (the
    same condition estimate, from the same patterns); None otherwise."""
    from . import banded

    got = banded.solve(A, b, n, PATTERNS)
    if got is None:
        return None
    y, inv = got
    cond = _norm1(A, n) * inv
    if not math.isfinite(cond) or cond > SINGULAR_COND or not all(map(math.isfinite, y)):
        raise SingularError(cond)
    return y, cond


def _cond(A: Rows, n: int) -> float:
    """The 1-norm condition number (for the exact mode's report), or inf if singular."""
    try:
        if n <= SMALL:
            return _gauss_jordan(A, [0.0] * n, n)[1]
        return _float_solve(A, [0.0] * n, n)[1]
    except SingularError as exc:
        return exc.cond


# ---- exact residuals -------------------------------------------------------------------------


def residual(A: Rows, b: list[float], x: list[float]) -> list[float]:
    """b - A x, each component correctly rounded from the exact value."""
    out = []
    for i, row in enumerate(A):
        terms = [b[i]]
        for j, v in row.items():
            p, e = _two_product(v, x[j])
            terms.append(-p)
            terms.append(-e)
        out.append(math.fsum(terms))
    return out


def _backward(A: Rows, b: list[float], x: list[float]) -> float:
    r = residual(A, b, x)
    norm_a = max((sum(abs(v) for v in row.values()) for row in A), default=0.0)
    denom = norm_a * max((abs(v) for v in x), default=0.0) + max((abs(v) for v in b),
                                                                  default=0.0)
    num = max((abs(v) for v in r), default=0.0)
    return num / denom if denom > 0 else num


def _refine(A: Rows, b: list[float], y: list[float], n: int):
    """Iterative refinement with exact residuals, until the componentwise correction
    |d_i|/|y_i| reaches rounding level or stops shrinking."""
    prev = math.inf
    last = math.inf
    iters = 0
    for _ in range(30):
        r = residual(A, b, y)
        if not any(r):
            last = 0.0
            break
        d, _, _ = _float_solve(A, r, n)
        size = max((abs(e) / max(abs(v), abs(v + e)) if e != 0.0 else 0.0
                    for e, v in zip(d, y)), default=0.0)
        iters += 1
        if iters > 1 and size >= prev / 2 and size > EPS:
            break  # no longer converging
        y = [a + e for a, e in zip(y, d)]
        prev = size
        last = size
        if size <= EPS:
            break
    return y, _backward(A, b, y), iters, last


# ---- sparse elimination (floats or exact rationals) ------------------------------------------
class SparseLU:
    """Gaussian elimination on sparse rows with a Markowitz-style pivot order.

    The column with the fewest remaining entries is eliminated first (little fill-in:
    a chain of contacts stays O(n)); among its rows the shortest whose pivot is at
    least a tenth of the column's largest entry (threshold pivoting; any non-zero in
    exact arithmetic). The recorded steps replay on any right-hand side.
    """

    def __init__(self, A: Rows, n: int, exact: bool):
        conv = Fraction if exact else float
        rows = [{j: conv(v) for j, v in row.items() if v != 0.0} for row in A]
        self.n = n
        self.norm1 = max((sum(abs(float(r.get(j, 0.0))) for r in A) for j in range(n)),
                         default=0.0) if n <= SMALL else _norm1(A, n)
        col_rows: dict[int, set[int]] = {j: set() for j in range(n)}
        for i, row in enumerate(rows):
            for j in row:
                col_rows[j].add(i)
        self.steps: list[tuple[int, int, list[tuple[int, object]]]] = []
        self.leftover = set(range(len(rows)))
        # columns by how many rows still hold them: a heap with lazy deletion
        heap = [(len(col_rows[c]), c) for c in col_rows]
        heapq.heapify(heap)

        def touch(c):
            heapq.heappush(heap, (len(col_rows[c]), c))

        for _ in range(n):
            j = None
            while heap:
                cnt, c = heapq.heappop(heap)
                if c in col_rows and len(col_rows[c]) == cnt and cnt > 0:
                    j = c
                    break
            if j is None:
                free = list(col_rows)
                raise SingularError(math.inf, exact=exact,
                                    free=_null_support(rows, [(i, c) for i, c, _ in self.steps],
                                                       free) if exact else free)
            cands = col_rows[j]
            if exact:
                i = min(cands, key=lambda k: len(rows[k]))
            else:
                big = max(abs(rows[k][j]) for k in cands)
                i = min((k for k in cands if abs(rows[k][j]) >= 0.1 * big),
                        key=lambda k: (len(rows[k]), -abs(rows[k][j])))
            piv_row, piv = rows[i], rows[i][j]
            self.leftover.discard(i)
            ops = []
            for k in list(cands):
                if k == i:
                    continue
                f = rows[k][j] / piv
                rk = rows[k]
                for c, v in piv_row.items():
                    nv = rk.get(c, 0) - f * v
                    if c == j or not nv:
                        if c in rk:
                            del rk[c]
                            col_rows[c].discard(k)
                            if c != j:
                                touch(c)
                    else:
                        if c not in rk:
                            col_rows[c].add(k)
                            touch(c)
                        rk[c] = nv
                ops.append((k, f))
            for c in piv_row:
                if c != j:
                    col_rows[c].discard(i)
                    touch(c)
            del col_rows[j]
            self.steps.append((i, j, ops))
        self.rows = rows
        self._back = None  # solve's pivot rows, made on the first solve
        self.zero = Fraction(0) if exact else 0.0
        self.conv = conv

    def solve(self, b):
        rhs = [self.conv(v) for v in b]
        for i, _j, ops in self.steps:
            ri = rhs[i]
            if ri:
                for k, f in ops:
                    rhs[k] -= f * ri
        back = self._back
        if back is None:  # each pivot row without its pivot, in its order (replayed often)
            back = self._back = [(i, j, [(c, v) for c, v in self.rows[i].items() if c != j],
                                  self.rows[i][j]) for i, j, _ in reversed(self.steps)]
        x = [None] * self.n  # every column is some step's pivot
        for i, j, off, piv in back:
            x[j] = (rhs[i] - sum([v * x[c] for c, v in off])) / piv
        for k in self.leftover:  # equations beyond n must hold exactly
            if rhs[k] - sum(v * x[c] for c, v in self.rows[k].items()) != 0:
                raise SingularError(math.inf, exact=True)
        return x

    def inverse_norm1_estimate(self) -> float:
        """A lower estimate of |A^-1|_1 from a few solves (LINPACK style)."""
        best = 0.0
        n = self.n
        for pattern in PATTERNS:
            b = [pattern(k, n) for k in range(n)]
            x = self.solve(b)
            best = max(best, sum(abs(v) for v in x) / sum(abs(v) for v in b))
        return best


def _norm1(A: Rows, n: int) -> float:
    cols = [0.0] * n
    for row in A:
        for j, v in row.items():
            cols[j] += abs(v)
    return max(cols, default=0.0)


def _exact(A: Rows, b: list[float], n: int) -> list[Fraction]:
    """Gaussian elimination in rationals: the exact solution of the block's data."""
    return SparseLU(A, n, exact=True).solve(b)


def _null_support(rows, order, free: list[int]) -> list[int]:
    """Columns that some null vector involves: the unknowns the block cannot determine."""
    support = set(free)
    for f in free:
        x: dict[int, Fraction] = {c: Fraction(0) for c in free}
        x[f] = Fraction(1)
        for i, j in reversed(order):
            s = -sum(v * x.get(c, 0) for c, v in rows[i].items() if c != j)
            x[j] = s / rows[i][j]
            if x[j]:
                support.add(j)
    return sorted(support)


def exact_rank_test(rows: Rows, b: list[float], n: int) -> list[int]:
    """[] if the block is exactly non-singular, else the columns it cannot determine."""
    A, bs, _, _ = equilibrate(rows, b, n)
    try:
        _exact(A, bs, n)
    except SingularError as exc:
        return exc.free or list(range(n))
    return []


def lstsq_small(J: list[list[float]], r: list[float]) -> list[float]:
    """A Newton step: solves J dx = r (equilibrated elimination, no error analysis);
    numpy's least squares if J is singular or not square."""
    n = len(r)
    if n == 1 and len(J[0]) == 1:
        if J[0][0] != 0.0:
            return [r[0] / J[0][0]]
    elif len(J) == len(J[0]) and n <= SMALL:
        x = _step_dense(J, r, n)
        if x is not None:
            return x
    import numpy as np

    return [float(v) for v in np.linalg.lstsq(np.array(J), np.array(r), rcond=None)[0]]


def _step_dense(J: list[list[float]], r: list[float], n: int) -> list[float] | None:
    """lstsq_small's square solve: `equilibrate` then `_gauss_jordan` on the dense rows,
    the very same float operations in the same order (bit-identical x; None where
    _gauss_jordan raises SingularError), without building sparse rows: Newton takes
    thousands of these steps on 3- and 5-unknown blocks.

    The inverse is not formed: Gauss-Jordan on [A | b] (every column takes its own
    operations, so b's are those of [A | b | I]; a column once eliminated is dropped, its
    entries are read no more). Equilibrated, every |a_ij| < 2, so ||A||_1 < 2n and, by
    Hadamard's inequality on the cofactors, ||A^-1||_1 <= n (2 sqrt(n))^(n-1) / |det A|,
    det A the product of the pivots. A condition bound below HADAMARD_COND (1000 times
    under SINGULAR_COND: the computed det and the computed inverse of a matrix that well
    conditioned are off by far less) means `_gauss_jordan` would not call it singular
    either; otherwise, or if J holds inf or nan, the long way decides (`_step_dense_full`)."""
    if not math.isfinite(sum(map(sum, J))):
        return _step_dense_full(J, r, n)
    frexp, ldexp = math.frexp, math.ldexp
    # row scales, then column scales: `_pow2` of the largest magnitude (equilibrate)
    R = [ldexp(1.0, frexp(m)[1] - 1) if m != 0.0 else 1.0
         for m in [max(map(abs, row)) for row in J]]
    C = [ldexp(1.0, frexp(m)[1] - 1) if m != 0.0 else 1.0
         for m in [max(map(truediv, map(abs, col), R)) for col in zip(*J)]]
    M = [[v / ri / cj if v != 0.0 else 0.0 for v, cj in zip(row, C)] + [rv / ri]
         for row, ri, rv in zip(J, R, r)]
    det = 1.0
    for col in range(n):  # Gauss-Jordan with partial pivoting; M's rows hold columns col..n
        piv, best = col, abs(M[col][0])
        for i in range(col + 1, n):
            a = abs(M[i][0])
            if a > best:  # max(): the first of equal magnitudes
                piv, best = i, a
        Mc = M[piv]
        p = Mc[0]
        if p == 0.0:
            return None
        M[piv] = M[col]
        det *= p
        rowp = [x / p for x in Mc]
        del rowp[0]
        for i in range(n):
            if i != col:
                Mi = M[i]
                f = Mi[0]
                if f != 0.0:
                    M[i] = [a - f * b for a, b in zip(Mi[1:], rowp)]
                else:
                    del Mi[0]
        M[col] = rowp
    if n <= SMALL and _HADAMARD[n] <= HADAMARD_COND * abs(det) < math.inf:
        return [row[0] / cj for row, cj in zip(M, C)]
    return _step_dense_full(J, r, n)


_HADAMARD = [math.inf] + [2.0 * n * n * (2.0 * math.sqrt(n)) ** (n - 1) * (1 + 1e-9)
                          for n in range(1, SMALL + 1)]  # the bound's numerator, by n


def _step_dense_full(J: list[list[float]], r: list[float], n: int) -> list[float] | None:
    """`_step_dense` the long way: Gauss-Jordan on [A | b | I], the inverse's 1-norm for
    the condition number (`_step_dense` falls back to it when its bound is not enough)."""
    R = []
    for row in J:  # row scales: the largest nonzero entry (equilibrate)
        vals = [abs(v) for v in row if v != 0.0]
        R.append(_pow2(max(vals)) if vals else 1.0)
    C = [0.0] * n
    for i, row in enumerate(J):
        ri = R[i]
        for j, v in enumerate(row):
            if v != 0.0:
                a = abs(v) / ri
                if a > C[j]:
                    C[j] = a
    C = [_pow2(x) for x in C]
    A = [[v / R[i] / C[j] if v != 0.0 else 0.0 for j, v in enumerate(row)]
         for i, row in enumerate(J)]
    # column sums in row order, as `_cond` adds them (zip and map: no Python-level loop)
    norm1 = max([sum(map(abs, col)) for col in zip(*A)], default=0.0)
    M = [A[i] + [r[i] / R[i]] + [1.0 if k == i else 0.0 for k in range(n)] for i in range(n)]
    for col in range(n):  # Gauss-Jordan with partial pivoting on [A | b | I]
        piv, best = col, abs(M[col][col])
        for i in range(col + 1, n):
            a = abs(M[i][col])
            if a > best:  # max(): the first of equal magnitudes
                piv, best = i, a
        if M[piv][col] == 0.0:
            return None
        M[col], M[piv] = M[piv], M[col]
        p = M[col][col]
        rowp = [x / p for x in M[col]]
        M[col] = rowp
        for i in range(n):
            if i != col:
                Mi = M[i]
                f = Mi[col]
                if f != 0.0:
                    M[i] = [a - f * b for a, b in zip(Mi, rowp)]
    inv_norm1 = max([sum(map(abs, col)) for col in zip(*M)][n + 1:])
    cond = norm1 * inv_norm1
    if not math.isfinite(cond) or cond > SINGULAR_COND:
        return None
    return [M[j][n] / C[j] for j in range(n)]


# ---- rank-revealing elimination: structure and numbers agree ---------------------------------
@record
class RankReveal:
    """What a set of rows determines, found by elimination in a chosen row order.

    `basis`: the rows kept (independent), each with its pivot column; `dependent`: the
    rows that are combinations of earlier ones, each with its left null vector (row ->
    coefficient, the row itself included) and its right-hand side's remainder (0 when
    it is consistent); `free`: the columns some null vector involves (not determined).
    """

    basis: list[tuple[int, int]]  # (row, pivot column)
    dependent: list[tuple[int, dict, float]]  # (row, left null vector, rhs remainder)
    free: list[int]


def rank_reveal(rows: Rows, b: list[float], n: int, exact: bool = False) -> RankReveal:
    """Gaussian elimination row by row, in the given order, with the largest remaining
    entry as pivot. A row that eliminates to nothing is dependent on the rows before
    it. In float an entry is nothing when it is round-off of the terms that formed it
    (each entry carries the size of those terms), never because it is small: masses 12
    decades apart are not a dependency. With `exact`, in rationals: exactly zero."""
    A, bs, _, _ = equilibrate(rows, b, n)
    conv = Fraction if exact else float
    zero = conv(0)
    tiny = 0 if exact else 256 * EPS
    # kept: row, pivot, entries {col: (value, size of its terms)}, rhs, comb
    kept: list[tuple[int, int, dict, object, dict]] = []
    dependent = []
    for i, row in enumerate(A):
        r = {j: (conv(v), abs(conv(v))) for j, v in row.items() if v != 0.0}
        rhs = conv(bs[i])
        comb: dict[int, object] = {i: conv(1)}
        for _k, p, entries, krhs, kcomb in kept:
            if p not in r:
                continue
            f = r[p][0] / entries[p][0]
            for j, (v, m) in entries.items():
                if j == p:
                    r.pop(j)
                    continue
                old, om = r.get(j, (zero, zero))
                nv, nm = old - f * v, om + abs(f) * m
                if nv == 0 or abs(nv) <= tiny * nm:
                    r.pop(j, None)
                else:
                    r[j] = (nv, nm)
            rhs -= f * krhs
            for q, c in kcomb.items():
                comb[q] = comb.get(q, zero) - f * c
        if not r:
            big = max(abs(c) for c in comb.values())
            dependent.append((i, {q: float(c) for q, c in comb.items()
                                  if c != 0 and abs(c) > tiny * big}, float(rhs)))
            continue
        p = max(r, key=lambda j: (abs(r[j][0]), -j))
        kept.append((i, p, r, rhs, comb))
    # null vectors: one per non-pivot column (set to 1), by back-substitution
    pivots = {p for _, p, _, _, _ in kept}
    used = {j for row in A for j in row}
    free: set[int] = set()
    for f in sorted(used - pivots):
        x: dict[int, object] = {f: conv(1)}
        for _, p, entries, _, _ in reversed(kept):
            terms = [v * x[j] for j, (v, _m) in entries.items() if j != p and j in x]
            if not terms:
                continue
            s = -sum(terms, zero) if exact else -math.fsum(terms)
            if s and abs(s) > tiny * sum(abs(t) for t in terms):
                x[p] = s / entries[p][0]
        free.update(j for j, v in x.items() if v != 0)
    return RankReveal([(i, p) for i, p, _, _, _ in kept], dependent, sorted(free))
