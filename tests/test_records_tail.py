"""`records.record`: a call with leading positional arguments and no keywords (filled
from defaults by a remembered list) builds what the keyword call builds."""
from __future__ import annotations

from dataclasses import field

import pytest

from momentum_cli.records import record


@record
class Base:
    a: int
    b: list = field(default_factory=list)
    c: str = "c"


@record
class Child(Base):
    d: float = 1.5
    e: dict = field(default_factory=dict)


def fields(x):
    return [(f, getattr(x, f)) for f in type(x)._fields]


def test_positional_prefix_fills_defaults_and_fresh_factories():
    for k in range(1, 6):
        args = [1, [2], "z", 2.5, {"k": 1}][:k]
        got = Child(*args)
        want = Child(**dict(zip(Child._fields, args)))
        assert fields(got) == fields(want)
    x, y = Child(1), Child(1)
    assert x.b is not y.b and x.e is not y.e  # a factory is called for each record


def test_missing_and_extra_arguments_still_fail():
    with pytest.raises(TypeError, match="missing argument 'a'"):
        Child()
    with pytest.raises(TypeError, match="takes 5 arguments"):
        Child(1, 2, 3, 4, 5, 6)
