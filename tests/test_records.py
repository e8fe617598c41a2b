"""A record's compiled __init__ (records.HOT constructions on) builds the same objects,
and refuses the same bad calls, as the generic one it replaces."""
from dataclasses import FrozenInstanceError, field

import pytest

from momentum_cli import records
from momentum_cli.records import record


def _classes():
    """Fresh classes of every shape: required, defaulted, factory, frozen, inherited
    (a required field after a defaulted one)."""
    @record
    class Plain:
        a: int
        b: str
        c: float = 1.5
        d: list = field(default_factory=list)

    @record(frozen=True)
    class Frozen:
        x: int
        y: tuple = ()

    @record
    class Base:
        p: int
        q: int = 7

    @record
    class Child(Base):
        r: str

    return Plain, Frozen, Base, Child


CALLS = [  # (class index, args, kwargs)
    (0, (1, "s"), {}), (0, (1, "s", 2.5), {}), (0, (1,), {"b": "t", "d": [1]}),
    (0, (), {"a": 3, "b": "u", "c": 0.0}), (0, (1, "s", 2.0, [9]), {}),
    (1, (4,), {}), (1, (4, (1, 2)), {}), (1, (), {"x": 5}),
    (2, (1,), {}), (2, (1, 2), {}), (3, (1, 2, "r"), {}), (3, (1,), {"r": "z"}),
]
BAD = [(0, (), {}), (0, (1, "s", 1.0, [], 5), {}), (0, (1, "s"), {"e": 1}),
       (1, (), {}), (3, (1,), {}), (3, (1, 2), {"q": 3, "r": "x"})]


def _build(cls_index, args, kw):
    classes = _classes()
    return classes, classes[cls_index](*args, **kw)


def _compiled(classes):
    for cls in classes:  # pass the threshold with a valid call of each class
        generic = cls.__init__
        for _ in range(records.HOT):
            cls(1, "s") if cls.__name__ == "Plain" else cls(1, 2, "r") \
                if cls.__name__ == "Child" else cls(1)
        assert cls.__init__ is not generic
    return classes


@pytest.mark.parametrize("case", CALLS)
def test_compiled_init_builds_the_same_record(case):
    i, args, kw = case
    _, slow = _build(i, args, kw)
    classes = _compiled(_classes())
    fast = classes[i](*args, **kw)
    assert repr(fast) == repr(slow)
    assert [getattr(fast, f) for f in fast._fields] == [getattr(slow, f) for f in slow._fields]


def test_factories_give_a_new_object_each_time():
    Plain = _compiled(_classes())[0]
    a, b = Plain(1, "s"), Plain(1, "s")
    assert a.d == [] and a.d is not b.d


def test_frozen_stays_frozen():
    Frozen = _compiled(_classes())[1]
    r = Frozen(3)
    with pytest.raises(FrozenInstanceError):
        r.x = 4
    assert hash(r) == hash(Frozen(3)) and r == Frozen(3)


@pytest.mark.parametrize("case", BAD)
def test_compiled_init_refuses_the_same_calls(case):
    i, args, kw = case
    with pytest.raises(TypeError):
        _build(i, args, kw)
    classes = _compiled(_classes())
    with pytest.raises(TypeError):
        classes[i](*args, **kw)


# ---- what any constructor (generic or compiled) builds and how it refuses ----------------
@record
class _Base:
    a: int
    b: list = field(default_factory=list)
    c: str = "x"


@record
class _Child(_Base):
    d: int | None = None
    e: float = 1.5


@record(frozen=True)
class _Pair:
    x: object
    y: object


def _values(r) -> dict:
    return {f: getattr(r, f) for f in type(r)._fields}


def test_positional_keyword_defaults_and_inheritance():
    assert _values(_Child(1, [2], "y", 4, 2.5)) == dict(a=1, b=[2], c="y", d=4, e=2.5)
    assert _values(_Child(1)) == dict(a=1, b=[], c="x", d=None, e=1.5)
    assert _values(_Child(1, d=7)) == dict(a=1, b=[], c="x", d=7, e=1.5)
    assert _values(_Child(a=1, e=0.0, c="z")) == dict(a=1, b=[], c="z", d=None, e=0.0)
    assert _Child(1).b is not _Child(1).b  # a fresh list from the factory each time
    assert _values(_Pair(1, 2)) == dict(x=1, y=2) and _Pair(1, 2) == _Pair(y=2, x=1)


def test_a_positional_prefix_is_the_keyword_call():
    for k in range(1, 6):
        args = [1, [2], "z", 4, 2.5][:k]
        assert _values(_Child(*args)) == _values(_Child(**dict(zip(_Child._fields, args))))


def test_refusals_name_what_is_wrong():
    with pytest.raises(TypeError, match="missing argument 'a'"):
        _Child()
    with pytest.raises(TypeError, match="unexpected arguments"):
        _Child(1, zork=2)
    with pytest.raises(TypeError, match="takes 5 arguments"):
        _Child(1, 2, 3, 4, 5, 6)
    with pytest.raises(TypeError, match="missing argument 'y'"):
        _Pair(1)
    with pytest.raises(FrozenInstanceError):
        _Pair(1, 2).x = 3
