"""Newton's step solve on dense rows (linalg._step_dense) is bit for bit the sparse-row
path it replaces (equilibrate, then _gauss_jordan; None where that raises
SingularError), on random, scaled, sparse, singular and non-finite matrices."""
import math
import random

import pytest

from momentum_cli.linalg import SingularError, _gauss_jordan, _step_dense, equilibrate


def _reference(J, r):
    n = len(r)
    rows = [{j: v for j, v in enumerate(row) if v != 0.0} for row in J]
    A, b, _, c = equilibrate(rows, r, n)
    try:
        y, _ = _gauss_jordan(A, b, n)
    except SingularError:
        return None
    return [y[j] / c[j] for j in range(n)]


def _cases(seed: int, count: int):
    rng = random.Random(seed)
    for _ in range(count):
        n = rng.randint(1, 7)
        J = [[rng.uniform(-1, 1) * 10.0 ** rng.randint(-12, 12) if rng.random() > 0.3 else 0.0
              for _ in range(n)] for _ in range(n)]
        kind = rng.random()
        if kind < 0.15 and n > 1:  # exactly singular: a repeated row, scaled
            J[1] = [2.0 * v for v in J[0]]
        elif kind < 0.25 and n > 1:  # nearly singular
            J[1] = [v * (1 + 1e-16 * rng.random()) for v in J[0]]
        elif kind < 0.3:  # not finite
            J[rng.randrange(n)][rng.randrange(n)] = rng.choice([math.inf, -math.inf, math.nan])
        elif kind < 0.35:
            J[rng.randrange(n)] = [0.0] * n
        r = [rng.uniform(-1, 1) * 10.0 ** rng.randint(-6, 6) for _ in range(n)]
        yield J, r


@pytest.mark.parametrize("seed", range(4))
def test_dense_step_is_the_sparse_path_bit_for_bit(seed):
    for J, r in _cases(seed, 400):
        want = _reference(J, r)
        got = _step_dense(J, r, len(r))
        assert repr(got) == repr(want), (J, r)
