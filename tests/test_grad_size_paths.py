"""bounds._grad_size's written-out steps (a product of two leaves, a product of numbers
and one sum of leaves and leaf products, taken without evaluating the sum) give what
the two reference walks give (derivatives and _mag: tests/test_bounds_fused.py), bit
for bit and in order, on rows of that form with values that make the sums fail: a
missing unknown, an fsum's intermediate overflow, an inf minus an inf, NaNs."""
from __future__ import annotations

import math
import random

from test_bounds_fused import _bits

from momentum_cli.bounds import _mag, derivatives, derivatives_and_size
from momentum_cli.expr import Add, Const, Known, Mul, Var

NUMBERS = [0.0, -0.0, 1.0, -2.5, 1e-300, 1e300, -1e308, 3.0]
VALUES = {"x": 2.0, "y": -0.5, "z": 0.0, "big": 1e308, "nbig": -1e308, "inf": math.inf,
          "ninf": -math.inf, "nan": math.nan}


def _leaf(rng):
    k = rng.randrange(3)
    if k == 0:
        return Const(rng.choice(NUMBERS))
    if k == 1:
        return Known("m", rng.choice(NUMBERS))
    return Var(rng.choice(list(VALUES) + ["missing"]))


def _row(rng):
    """A sum of numbers times sums of leaves and leaf products (a row's usual form)."""
    terms = []
    for _ in range(rng.randint(1, 4)):
        inner = Add(tuple(_leaf(rng) if rng.random() < 0.5 else
                          Mul(tuple(_leaf(rng) for _ in range(rng.randint(2, 3))))
                          for _ in range(rng.randint(2, 4))))
        numbers = [Const(rng.choice(NUMBERS)) for _ in range(rng.randint(1, 2))]
        numbers.insert(rng.randrange(len(numbers) + 1), inner)
        terms.append(Mul(tuple(numbers)) if rng.random() < 0.8 else
                     Mul((_leaf(rng), _leaf(rng))))
    return Add(tuple(terms))


def test_written_out_steps_equal_the_reference_walks():
    rng = random.Random(8)
    failed = 0
    for _ in range(4000):
        e = _row(rng)
        dv, mag = derivatives_and_size(e, VALUES)
        want = derivatives(e, VALUES)
        assert list(dv) == list(want), e
        assert [_bits(v) for v in dv.values()] == [_bits(v) for v in want.values()], e
        assert _bits(mag) == _bits(_mag(e, VALUES)), e
        failed += any(v == math.inf for v in want.values())
    assert failed > 100  # the failing sums were exercised


def test_an_overflowing_sum_fails_as_its_evaluation_does():
    # 1e308 + 1e308 overflows inside fsum: the general step's evaluation fails there
    e = Mul((Const(2.0), Add((Var("big"), Var("big"), Mul((Const(-1.0), Var("big")))))))
    dv, mag = derivatives_and_size(e, VALUES)
    assert dv == derivatives(e, VALUES) == {"big": math.inf}
    assert _bits(mag) == _bits(_mag(e, VALUES))
