"""banded.order (one list of flags per walk, the probe's cleared after it) against the
breadth-first walk it replaced (sets for the probe, an index into the queue): the same
row and column orders on chains and random sparse blocks of several components."""
from __future__ import annotations

import random

import pytest

from momentum_cli import banded


def _walk_ref(A, col_rows, start, seen_r, seen_c, rows_out, cols_out):
    flags = isinstance(seen_r, list)
    queue = [start]
    if flags:
        seen_r[start] = True
    else:
        seen_r.add(start)
    last = start
    k = 0
    while k < len(queue):
        i = queue[k]
        k += 1
        last = i
        rows_out.append(i)
        for j in A[i]:
            if (seen_c[j]) if flags else (j in seen_c):
                continue
            if flags:
                seen_c[j] = True
            else:
                seen_c.add(j)
            cols_out.append(j)
            for r in col_rows[j]:
                if (seen_r[r]) if flags else (r in seen_r):
                    continue
                if flags:
                    seen_r[r] = True
                else:
                    seen_r.add(r)
                queue.append(r)
    return last


def _order_ref(A, n):
    col_rows = [[] for _ in range(n)]
    for i, row in enumerate(A):
        if not row:
            return None
        for j in row:
            col_rows[j].append(i)
    if not all(col_rows):
        return None
    rows_out, cols_out = [], []
    seen_r = [False] * n
    seen_c = [False] * n
    for s in range(n):
        if seen_r[s]:
            continue
        far = _walk_ref(A, col_rows, s, set(), set(), [], [])
        _walk_ref(A, col_rows, far, seen_r, seen_c, rows_out, cols_out)
    return rows_out, cols_out


def _random_rows(rng, n):
    """Rows as dicts (keys in no sorted order) over several chains and random links."""
    perm = list(range(n))
    rng.shuffle(perm)
    A = [dict() for _ in range(n)]
    for i in range(n):
        for j in rng.sample(range(max(0, i - 2), min(n, i + 3)), rng.randint(1, 3)):
            A[perm[i]][perm[j]] = 1.0
        if rng.random() < 0.05:
            A[perm[i]][rng.randrange(n)] = 2.0
    cut = rng.sample(range(n), 3)  # separate components: rows keep only their own band
    for i in cut:
        A[perm[i]] = {perm[i]: 1.0}
    return A


@pytest.mark.parametrize("seed", range(12))
def test_order_is_the_reference_walk(seed):
    rng = random.Random(seed)
    n = rng.randint(5, 400)
    A = _random_rows(rng, n)
    assert banded.order(A, n) == _order_ref(A, n)


def test_an_empty_row_or_column_is_no_order():
    assert banded.order([{0: 1.0}, {}], 2) is None
    assert banded.order([{0: 1.0}, {0: 1.0}], 2) is None
