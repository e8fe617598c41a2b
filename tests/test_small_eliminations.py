"""The small blocks' Gauss-Jordan (linalg._eliminate, bounds._abs_inverse) with their
pivots found by a loop and their rows updated by zip give what the first versions gave
(max with a key, index loops), bit for bit, on random matrices with ties, zeros, signed
zeros, huge and tiny entries, infinities and NaNs, singular ones included."""
from __future__ import annotations

import math
import random

from momentum_cli.bounds import _abs_inverse
from momentum_cli.linalg import SingularError, _eliminate


def _eliminate_reference(A, n):
    norm1 = max((sum(abs(A[i].get(j, 0.0)) for i in range(n)) for j in range(n)), default=0.0)
    M = [[A[i].get(j, 0.0) for j in range(n)] + [1.0 if k == i else 0.0 for k in range(n)]
         for i in range(n)]
    width = 2 * n
    steps = []
    for col in range(n):
        piv = max(range(col, n), key=lambda i: abs(M[i][col]))
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
                    Mi = M[i]
                    M[i] = [Mi[k] - f * rowp[k] for k in range(width)]
        steps.append((col, piv, p, tuple(ops)))
    inv_norm1 = max(sum(abs(M[i][n + j]) for i in range(n)) for j in range(n))
    cond = norm1 * inv_norm1
    if not math.isfinite(cond) or cond > 1e15:
        raise SingularError(cond)
    return tuple(steps), cond


def _abs_inverse_reference(A):
    n = len(A)
    if n == 1:
        a = float(A[0].get(0, 0.0))
        return None if a == 0.0 or not math.isfinite(a) else [[abs(1.0 / a)]]
    M = [[float(row.get(j, 0.0)) for j in range(n)] + [1.0 if i == j else 0.0 for j in range(n)]
         for i, row in enumerate(A)]
    for c in range(n):
        p = max(range(c, n), key=lambda r: abs(M[r][c]))
        if M[p][c] == 0.0 or not math.isfinite(M[p][c]):
            return None
        M[c], M[p] = M[p], M[c]
        piv = M[c][c]
        M[c] = [v / piv for v in M[c]]
        for r in range(n):
            if r != c and M[r][c] != 0.0:
                f = M[r][c]
                M[r] = [a - f * b for a, b in zip(M[r], M[c])]
    return [[abs(v) for v in M[i][n:]] for i in range(n)]


def _reprs(x):
    if isinstance(x, float):
        return repr(x) + ("-" if x == x and math.copysign(1.0, x) < 0 else "")
    if isinstance(x, (tuple, list)):
        return [_reprs(v) for v in x]
    return x


def _outcome(f, *args):
    try:
        return _reprs(f(*args))
    except SingularError as exc:
        return ("singular", _reprs(exc.cond))


def _matrix(rng, n):
    pool = [0.0, -0.0, 1.0, -1.0, 2.0, 0.5, 1e-300, -1e300, math.inf, math.nan]
    rows = []
    for _ in range(n):
        row = {}
        for j in range(n):
            r = rng.random()
            if r < 0.25:
                continue
            row[j] = rng.choice(pool) if r < 0.45 else rng.uniform(-5, 5)
        rows.append(row)
    return rows


def test_eliminations_equal_the_first_versions():
    rng = random.Random(3)
    singular = 0
    for _ in range(4000):
        n = rng.randint(1, 6)
        A = _matrix(rng, n)
        got = _outcome(_eliminate, A, n)
        assert got == _outcome(_eliminate_reference, A, n), A
        singular += got[0] == "singular"
        assert _outcome(_abs_inverse, A) == _outcome(_abs_inverse_reference, A), A
    assert 100 < singular < 3900


def _equilibrate_reference(rows, b, n):
    from momentum_cli.linalg import _pow2

    r = [_pow2(max((abs(v) for v in row.values()), default=0.0)) for row in rows]
    c = [0.0] * n
    for i, row in enumerate(rows):
        for j, v in row.items():
            a = abs(v) / r[i]
            if a > c[j]:
                c[j] = a
    c = [_pow2(x) for x in c]
    rows2 = [{j: v / r[i] / c[j] for j, v in row.items()} for i, row in enumerate(rows)]
    return rows2, [b[i] / r[i] for i in range(len(b))], r, c


def test_equilibrate_equals_the_first_version():
    from momentum_cli.linalg import equilibrate

    rng = random.Random(4)
    for _ in range(3000):
        n = rng.randint(1, 6)
        A = _matrix(rng, n)
        b = [rng.uniform(-3, 3) for _ in range(n)]
        got, want = equilibrate(A, b, n), _equilibrate_reference(A, b, n)
        assert _reprs([[list(row.items()) for row in got[0]], *got[1:]]) == \
            _reprs([[list(row.items()) for row in want[0]], *want[1:]])
