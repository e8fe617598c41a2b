"""`record`: a dataclass-like decorator for the pipeline's typed values, without `exec`.

`dataclasses` generates each method with `exec` (~0.6 ms per class on CPython 3.11);
with ~70 classes that was a sixth of a one-shot solve. A record has slots, keyword or
positional construction, defaults (and `field(default_factory=...)`), a repr,
field-wise equality, and optional immutability (`frozen=True` raises
`dataclasses.FrozenInstanceError` on assignment, as a frozen dataclass does).
"""
from __future__ import annotations

from dataclasses import MISSING, Field, FrozenInstanceError


def record(cls=None, *, frozen: bool = False, identity: bool = False):
    """Turn a class with annotated fields into a slotted record.

    `identity=True` keeps object identity for == and hash (expression nodes).
    """
    def wrap(c):
        return _build(c, frozen, identity)
    return wrap if cls is None else wrap(cls)


def _build(cls, frozen: bool, identity: bool):
    own = cls.__dict__.get("__annotations__", {})
    # the nearest record base already lists its own ancestors' fields
    inherited = next((b.__dict__["_fields"] for b in cls.__mro__[1:] if "_fields" in b.__dict__),
                     ())
    fields = tuple(f for f in own if own[f] != "ClassVar")
    all_fields = inherited + fields
    defaults: dict = {}
    factories: dict = {}
    for base in reversed(cls.__mro__[1:]):
        defaults.update(getattr(base, "_defaults", {}))
        factories.update(getattr(base, "_factories", {}))
    ns = {}
    for k, v in cls.__dict__.items():
        if k in ("__dict__", "__weakref__"):
            continue
        if k in fields:
            if isinstance(v, Field):
                if v.default_factory is not MISSING:
                    factories[k] = v.default_factory
                elif v.default is not MISSING:
                    defaults[k] = v.default
            else:
                defaults[k] = v
            continue
        ns[k] = v
    ns["__slots__"] = fields
    ns["_fields"] = all_fields
    ns["_defaults"] = defaults
    ns["_factories"] = factories
    n = len(all_fields)
    setter = object.__setattr__
    new_cls: list = []

    def __init__(self, *args, **kw):
        if not kw and len(args) == n:  # the common call: every field, in order
            for name, v in zip(all_fields, args):
                setter(self, name, v)
            return
        if len(args) > n:
            raise TypeError(f"{cls.__name__}() takes {n} arguments, got {len(args)}")
        for name, v in zip(all_fields, args):
            setter(self, name, v)
        for name in all_fields[len(args):]:
            if name in kw:
                v = kw.pop(name)
            elif name in defaults:
                v = defaults[name]
            elif name in factories:
                v = factories[name]()
            else:
                raise TypeError(f"{cls.__name__}() missing argument '{name}'")
            setter(self, name, v)
        if kw:
            raise TypeError(f"{cls.__name__}() got unexpected arguments {sorted(kw)}")

    def __repr__(self):
        inner = ", ".join(f"{f}={getattr(self, f)!r}" for f in all_fields)
        return f"{cls.__name__}({inner})"

    def __eq__(self, other):
        if other.__class__ is not self.__class__:
            return NotImplemented
        return all(getattr(self, f) == getattr(other, f) for f in all_fields)

    def __reduce__(self):  # pickling (worker processes): rebuild through __init__
        return (new_cls[0], tuple(getattr(self, f) for f in all_fields))

    ns.setdefault("__init__", __init__)
    ns.setdefault("__reduce__", __reduce__)
    ns.setdefault("__repr__", __repr__)
    if "__eq__" not in ns and not identity:
        ns["__eq__"] = __eq__
        if frozen:
            ns["__hash__"] = lambda self: hash(tuple(getattr(self, f) for f in all_fields))
        else:
            ns["__hash__"] = None
    if frozen:
        def __setattr__(self, name, value):
            raise FrozenInstanceError(f"cannot assign to field '{name}'")

        def __delattr__(self, name):
            raise FrozenInstanceError(f"cannot delete field '{name}'")

        ns["__setattr__"] = __setattr__
        ns["__delattr__"] = __delattr__
    new = type(cls)(cls.__name__, cls.__bases__, ns)
    if ns["__init__"] is __init__:
        new.__init__ = _positional_init(new, all_fields, __init__, defaults, factories)
    new.__qualname__ = cls.__qualname__
    new.__module__ = cls.__module__
    new_cls.append(new)
    return new


_NO = object()


def _positional_init(cls, fields: tuple, general, defaults: dict, factories: dict):
    """`general`, faster: the commonest call (every field, by position) unrolled into the
    slots' own setters, and keywords matched against a precomputed table. A record is
    built ~10^6 times in a 10^4-impact file; the general loop over (name, value) pairs
    cost two to three times this. A call `general` would refuse goes to it (its error)."""
    sets = []
    for f in fields:
        d = getattr(cls, f, None)
        if type(d).__name__ != "member_descriptor":  # not a plain slot: the general path
            return general
        sets.append(d.__set__)
    n = len(sets)
    table = tuple((f, s, defaults.get(f, _NO), factories.get(f)) for f, s in zip(fields, sets))
    # the fields after the first k given by position, when every one has a default
    tails = [None if any(d is _NO and fac is None for _, _, d, fac in table[k:]) else
             tuple((s, d, fac) for _, s, d, fac in table[k:]) for k in range(n + 1)]

    def fill(self, args, kw):
        na = len(args)
        if na > n:
            return general(self, *args, **kw)
        for s, v in zip(sets, args):
            s(self, v)
        if not kw and tails[na] is not None:  # the leading fields by position, defaults
            for s, d, factory in tails[na]:
                s(self, d if factory is None else factory())
            return
        used = 0
        for name, s, default, factory in table[na:]:
            if name in kw:
                s(self, kw[name])
                used += 1
            elif default is not _NO:
                s(self, default)
            elif factory is not None:
                s(self, factory())
            else:
                return general(self, *args, **kw)
        if used != len(kw):
            return general(self, *args, **kw)

    if n == 1:
        (s0,) = sets

        def __init__(self, *args, **kw):
            if kw or len(args) != 1:
                return fill(self, args, kw)
            s0(self, args[0])
    elif n == 2:
        s0, s1 = sets

        def __init__(self, *args, **kw):
            if kw or len(args) != 2:
                return fill(self, args, kw)
            a0, a1 = args
            s0(self, a0)
            s1(self, a1)
    elif n == 3:
        s0, s1, s2 = sets

        def __init__(self, *args, **kw):
            if kw or len(args) != 3:
                return fill(self, args, kw)
            a0, a1, a2 = args
            s0(self, a0)
            s1(self, a1)
            s2(self, a2)
    elif n == 4:
        s0, s1, s2, s3 = sets

        def __init__(self, *args, **kw):
            if kw or len(args) != 4:
                return fill(self, args, kw)
            a0, a1, a2, a3 = args
            s0(self, a0)
            s1(self, a1)
            s2(self, a2)
            s3(self, a3)
    else:
        def __init__(self, *args, **kw):
            if kw or len(args) != n:
                return fill(self, args, kw)
            for s, v in zip(sets, args):
                s(self, v)
    return __init__
