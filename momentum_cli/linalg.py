"""Dense linear solves for equation blocks, with equilibration and a condition number.

Small blocks (the usual impact has 3-10 unknowns) are solved by Gaussian elimination
in plain Python: importing numpy costs ~140 ms, far more than such a solve. Larger
blocks go to numpy's LAPACK. Both report the 1-norm condition number of the
equilibrated matrix.
"""
from __future__ import annotations

import math

SMALL = 12  # blocks up to this size are solved without numpy


class SingularError(ArithmeticError):
    """The (equilibrated) matrix is singular to working precision."""

    def __init__(self, cond: float):
        super().__init__("singular matrix")
        self.cond = cond


def equilibrate(A: list[list[float]], b: list[float]):
    """Row then column scaling by the largest magnitude: returns (A2, b2, r, c)."""
    n = len(A)
    r = [max((abs(x) for x in row), default=0.0) or 1.0 for row in A]
    A1 = [[x / r[i] for x in A[i]] for i in range(n)]
    m = len(A[0]) if A else 0
    c = [max((abs(A1[i][j]) for i in range(n)), default=0.0) or 1.0 for j in range(m)]
    A2 = [[A1[i][j] / c[j] for j in range(m)] for i in range(n)]
    b2 = [b[i] / r[i] for i in range(n)]
    return A2, b2, r, c


def solve_dense(A: list[list[float]], b: list[float]) -> tuple[list[float], float]:
    """x with A x = b, and the 1-norm condition number of the equilibrated A."""
    A2, b2, r, c = equilibrate(A, b)
    n = len(A2)
    if n > SMALL:
        y, cond = _solve_numpy(A2, b2)
    else:
        y, cond = _solve_python(A2, b2)
    return [y[j] / c[j] for j in range(n)], cond


def _solve_python(A: list[list[float]], b: list[float]) -> tuple[list[float], float]:
    n = len(A)
    norm1 = max(sum(abs(A[i][j]) for i in range(n)) for j in range(n))
    # Gauss-Jordan on [A | b | I]: the inverse gives the condition number exactly
    M = [list(A[i]) + [b[i]] + [1.0 if k == i else 0.0 for k in range(n)] for i in range(n)]
    for col in range(n):
        piv = max(range(col, n), key=lambda i: abs(M[i][col]))
        if M[piv][col] == 0.0:
            raise SingularError(math.inf)
        M[col], M[piv] = M[piv], M[col]
        p = M[col][col]
        rowp = [x / p for x in M[col]]
        M[col] = rowp
        for i in range(n):
            if i != col:
                f = M[i][col]
                if f != 0.0:
                    Mi = M[i]
                    M[i] = [Mi[k] - f * rowp[k] for k in range(2 * n + 1)]
    x = [M[i][n] for i in range(n)]
    inv_norm1 = max(sum(abs(M[i][n + 1 + j]) for i in range(n)) for j in range(n))
    cond = norm1 * inv_norm1
    if not math.isfinite(cond) or cond > 1e15:
        raise SingularError(cond)
    return x, cond


def _solve_numpy(A: list[list[float]], b: list[float]) -> tuple[list[float], float]:
    import numpy as np

    An = np.array(A, dtype=float)
    cond = float(np.linalg.cond(An, 1))
    if not math.isfinite(cond) or cond > 1e15:
        raise SingularError(cond)
    x = np.linalg.solve(An, np.array(b, dtype=float))
    return [float(v) for v in x], cond


def lstsq_small(J: list[list[float]], r: list[float]) -> list[float]:
    """A least-squares step for Newton: solves J dx = r, falling back to numpy's lstsq."""
    try:
        A2, b2, rs, c = equilibrate(J, r)
        if len(J) == len(J[0]) and len(J) <= SMALL:
            y, _ = _solve_python(A2, b2)
            return [y[j] / c[j] for j in range(len(c))]
    except SingularError:
        pass
    import numpy as np

    return [float(v) for v in np.linalg.lstsq(np.array(J), np.array(r), rcond=None)[0]]
