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



def _outcome(f, *args):
    try:
        x, q = f(*args)
    except Exception as exc:  # the same error, the same way
        return [type(exc).__name__, repr(getattr(exc, "cond", None)),
                getattr(exc, "exact", None), getattr(exc, "free", None)]
    return [[repr(v) + ("-" if math.copysign(1, v) < 0 else "") for v in x],
            [repr(getattr(q, f)) for f in q._fields]]


def test_blocks_of_one_kind_replay_the_factorization_bit_for_bit():
    """Many right-hand sides per matrix (a sequence of impacts of one kind): the replayed
    elimination gives what a fresh solve gives, singular and ill-conditioned ones too."""
    rng = random.Random(11)
    block_memo._solves.clear(), block_memo._factors.clear()
    mats = []
    for _ in range(60):
        rows, _ = _block(rng, rng.randint(2, 6))
        mats.append(rows)
    mats.append([{0: 1.0, 1: 2.0}, {0: 2.0, 1: 4.0}])  # singular
    mats.append([{0: 1.0, 1: 1.0}, {0: 1.0, 1: 1.0 + 1e-16 * 3}])  # singular to float64
    mats.append([{0: 1.0, 1: 1.0}, {0: 1.0, 1: 1.0 + 2.0**-40}])  # ill-conditioned
    mats.append([{1: 3.0, 0: 0.5}, {0: -0.0, 1: 2.0}, {2: 1e-300, 0: 1e300}])
    mats.append([{0: 0.1, 1: -0.1, 2: 1.0}, {0: 1.0, 2: -1.0}, {1: 1.0, 2: 1.0}])  # a cradle's
    for rows in mats:
        n = len(rows)
        for _ in range(6):
            rhs = [rng.choice([0.0, -0.0, 1.0, 2.0, rng.uniform(-5, 5), rng.uniform(-1e-9, 1e-9)])
                   for _ in range(n)]
            assert _outcome(block_memo.solve, rows, rhs, n) == _outcome(fresh_solve, rows, rhs, n)
    assert block_memo._factors  # the kinds were factored once and replayed


def test_remembered_one_unknown_solve_equals_a_fresh_one():
    """block_memo.solve_one against linalg.solve_one: x and every Quality field, the sign
    of a zero x too (0.0 and -0.0 right sides are equal keys of a dict: the key tells
    them apart), a singular block raising every time."""
    from momentum_cli.linalg import SingularError
    from momentum_cli.linalg import solve_one as fresh_one

    rng = random.Random(11)
    block_memo._ones.clear()
    block_memo._one_skip[:] = [0, 0]
    cases = [(a, b) for a in (1.0, -0.1, 3e-300, 2.5e300, rng.uniform(-2, 2))
             for b in (0.0, -0.0, 1.0, -1e-308, rng.uniform(-1, 1))]
    cases += [(a, b) for a, b in cases]  # every pair twice: the second read remembered
    cases += [(1, 2.0), (2.0, 0), (0.0, 1.0), (1e-320, 1.0)]
    rng.shuffle(cases)
    for a, b in cases:
        try:
            want = fresh_one(a, b)
        except SingularError as exc:
            with pytest.raises(SingularError) as got:
                block_memo.solve_one(a, b)
            assert _same(got.value.args[0] if got.value.args else None,
                         exc.args[0] if exc.args else None)
            continue
        x, q = block_memo.solve_one(a, b)
        assert _same(x, want[0]), (a, b)
        assert type(x[0]) is type(want[0][0])
        for f in ("method", "precision", "cond", "backward", "bound", "iterations",
                  "components", "exact"):
            assert _same(getattr(q, f), getattr(want[1], f)), (a, b, f)
    assert len(block_memo._ones) < len(cases)


def test_one_unknown_table_turns_off_where_rows_do_not_repeat(monkeypatch):
    """MISSES new rows in a row: the next OFF solves skip the table (the same answers)."""
    from momentum_cli.linalg import solve_one as fresh_one

    monkeypatch.setattr(block_memo, "MISSES", 4)
    monkeypatch.setattr(block_memo, "OFF", 3)
    block_memo._ones.clear()
    block_memo._one_skip[:] = [0, 0]
    for k in range(4):
        block_memo.solve_one(1.0 + k, 2.0)
    assert block_memo._one_skip == [3, 0]
    for k in range(3):
        x, q = block_memo.solve_one(1.0, 2.0)
        assert _same(x, fresh_one(1.0, 2.0)[0])
    assert block_memo._one_skip == [0, 0] and len(block_memo._ones) == 4
    block_memo.solve_one(1.0, 2.0)  # on again: remembered
    assert block_memo._one_skip == [0, 0]
