"""Remembered block solves (block_memo) give what a fresh solve gives, bit for bit."""
from __future__ import annotations

import math
import random
from fractions import Fraction

import pytest

from momentum_cli import block_memo
from momentum_cli.bounds import _abs_inverse
from momentum_cli.linalg import solve as fresh_solve

def _block(rng: random.Random, n: int):
    rows = [{j: rng.choice([1.0, -1.0, 0.1, 2.5, rng.uniform(-3, 3)])
             for j in rng.sample(range(n), rng.randint(1, n))} for _ in range(n)]
    for i in range(n):  # a diagonal: rarely singular
        rows[i][i] = rows[i].get(i, 0.0) + 4.0
    return rows, [rng.choice([0.0, -0.0, 1.0, rng.uniform(-1, 1)]) for _ in range(n)]


def _same(a, b) -> bool:
    """Equal bit for bit (the sign of a zero too)."""
    if isinstance(a, float) and isinstance(b, float):
        return a == b and math.copysign(1, a) == math.copysign(1, b) or (a != a and b != b)
    if isinstance(a, list) and isinstance(b, list):
        return len(a) == len(b) and all(_same(x, y) for x, y in zip(a, b))
    return a == b


@pytest.mark.parametrize("precision", ["float", "refine"])
def test_remembered_solve_equals_a_fresh_one(precision):
    rng = random.Random(7)
    block_memo._solves.clear()
    for _ in range(200):
        rows, rhs = _block(rng, rng.randint(1, 5))
        n = len(rows)
        want_x, want_q = fresh_solve(rows, rhs, n, precision)
        for _ in range(2):  # the first call fills the table, the second reads it
            x, q = block_memo.solve(rows, rhs, n, precision)
            assert _same(x, want_x)
            for f in ("method", "precision", "cond", "backward", "bound", "iterations",
                      "components", "exact"):
                assert _same(getattr(q, f), getattr(want_q, f)), f
        x2, q2 = block_memo.solve(rows, rhs, n, precision)
        assert x2 is not x and q2.components is not q.components  # nothing shared


def test_key_tells_signed_zeros_and_column_order_apart():
    assert block_memo.block_key([{0: 1.0}], [0.0]) != block_memo.block_key([{0: 1.0}], [-0.0])
    assert block_memo.block_key([{0: 1.0, 1: 2.0}]) != block_memo.block_key([{1: 2.0, 0: 1.0}])
    assert block_memo.block_key([{0: Fraction(1, 2)}]) is None  # exact mode: never shared
    assert block_memo.block_key([{0: 1}]) is None  # an int is not a float's bits


def test_remembered_abs_inverse_equals_a_fresh_one():
    rng = random.Random(3)
    block_memo._inverses.clear()
    for _ in range(100):
        A, _ = _block(rng, rng.randint(1, 4))
        want = _abs_inverse(A)
        assert _same(block_memo.abs_inverse(A, _abs_inverse), want)
        got = block_memo.abs_inverse(A, _abs_inverse)
        assert _same(got, want)
    assert block_memo.abs_inverse([{0: 0.0}], _abs_inverse) is None  # singular, remembered

