"""A record's fast constructor (records._positional_init) builds what the general one
builds, and refuses what it refuses."""
from __future__ import annotations

from dataclasses import FrozenInstanceError, field

import pytest

from momentum_cli.records import record


@record
class Base:
    a: int
    b: list = field(default_factory=list)


@record
class Child(Base):
    c: str = "x"
    d: int | None = None
    e: float = 1.5


@record(frozen=True)
class Pair:
    x: object
    y: object


def _fields(r) -> dict:
    return {f: getattr(r, f) for f in type(r)._fields}


def test_positional_keyword_defaults_and_inheritance():
    assert _fields(Child(1, [2], "y", 4, 2.5)) == dict(a=1, b=[2], c="y", d=4, e=2.5)
    assert _fields(Child(1)) == dict(a=1, b=[], c="x", d=None, e=1.5)
    assert _fields(Child(1, d=7)) == dict(a=1, b=[], c="x", d=7, e=1.5)
    assert _fields(Child(a=1, e=0.0, c="z")) == dict(a=1, b=[], c="z", d=None, e=0.0)
    assert Child(1).b is not Child(1).b  # a fresh list from the factory each time
    assert _fields(Pair(1, 2)) == dict(x=1, y=2) and Pair(1, 2) == Pair(y=2, x=1)


def test_refuses_what_the_general_constructor_refuses():
    with pytest.raises(TypeError, match="missing argument 'a'"):
        Child()
    with pytest.raises(TypeError, match="unexpected arguments"):
        Child(1, zork=2)
    with pytest.raises(TypeError, match="takes 5 arguments"):
        Child(1, 2, 3, 4, 5, 6)
    with pytest.raises(TypeError, match="missing argument 'y'"):
        Pair(1)
    with pytest.raises(FrozenInstanceError):
        Pair(1, 2).x = 3
