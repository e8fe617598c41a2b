"""`record`: a dataclass-like decorator for the pipeline's typed values, without `exec`.

`dataclasses` generates each method with `exec` (~0.6 ms per class on CPython 3.11);
with ~70 classes that was a sixth of a one-shot solve. A record has slots, keyword or
positional construction, defaults (and `field(default_factory=...)`), a repr,
field-wise equality, and optional immutability (`frozen=True` raises
`dataclasses.FrozenInstanceError` on assignment, as a frozen dataclass does).
A class constructed often (HOT times) then gets a compiled `__init__` (one small
`exec`, ~5x faster per call): many files in one run build ~10^2 records each.
"""
from __future__ import annotations



class FrozenEmptyList(list):
    """An empty list that cannot grow: one shared default for a field that is almost
    always empty (an unknown's hints: a fresh list each cost a 10^5-ball chain ~13 MB).
    It prints, compares and iterates as `[]`; adding to it raises, so a record whose list
    may grow gets its own."""

    __slots__ = ()

    def _frozen(self, *args, **kw):
        raise TypeError("a shared empty list: give the record its own list to add to")

    append = extend = insert = __iadd__ = __imul__ = __setitem__ = _frozen


EMPTY_LIST = FrozenEmptyList()


class _Missing:
    def __repr__(self):
        return "MISSING"


MISSING = _Missing()


class Field:
    """A record field's default (what `field` makes)."""

    __slots__ = ("default", "default_factory")

    def __init__(self, default=MISSING, default_factory=MISSING):
        self.default = default
        self.default_factory = default_factory


def field(*, default=MISSING, default_factory=MISSING) -> Field:
    """`field(default_factory=list)` for a record, as dataclasses.field for a dataclass
    (importing dataclasses, and inspect with it, cost a one-shot run ~10 ms). Not for
    real dataclasses."""
    return Field(default, default_factory)


def _is_field(v) -> bool:
    if isinstance(v, Field):
        return True
    import sys

    dc = sys.modules.get("dataclasses")  # a dataclasses.field() also works
    return dc is not None and isinstance(v, dc.Field)

HOT = 64  # constructions of a class after which its __init__ is compiled


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
            if _is_field(v):
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
    calls = [0]

    def __init__(self, *args, **kw):
        calls[0] += 1
        if calls[0] == HOT:
            _specialise(new_cls[0], __init__, all_fields, defaults, factories, frozen)
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
            from dataclasses import FrozenInstanceError  # only when it is raised

            raise FrozenInstanceError(f"cannot assign to field '{name}'")

        def __delattr__(self, name):
            from dataclasses import FrozenInstanceError

            raise FrozenInstanceError(f"cannot delete field '{name}'")

        ns["__setattr__"] = __setattr__
        ns["__delattr__"] = __delattr__
    new = type(cls)(cls.__name__, cls.__bases__, ns)
    new.__qualname__ = cls.__qualname__
    new.__module__ = cls.__module__
    new_cls.append(new)
    return new


_MISS = object()  # an argument not given (compiled __init__)


def _specialise(cls, generic, fields, defaults, factories, frozen: bool) -> None:
    """Give `cls` a compiled __init__ equal to the generic one (same parameters, same
    defaults and factories, fields set in order; frozen records through their slot
    descriptors). Left generic if anything is unusual (a field that is not a slot)."""
    if cls.__dict__.get("__init__") is not generic or \
            any(f == "self" or f.startswith("_rec_") for f in fields):
        return  # a field name that could meet the generated code's own names
    env: dict = {"_rec_MISS": _MISS, "_rec_cls": cls}
    params, body = [], []
    optional = False
    for i, f in enumerate(fields):
        if f in defaults or f in factories:
            optional = True
            params.append(f"{f}=_rec_MISS")
            if f in defaults:
                env[f"_rec_d{i}"] = defaults[f]
                body.append(f"    if {f} is _rec_MISS: {f} = _rec_d{i}")
            else:
                env[f"_rec_f{i}"] = factories[f]
                body.append(f"    if {f} is _rec_MISS: {f} = _rec_f{i}()")
        elif optional:  # a required field after a defaulted one (inherited fields)
            params.append(f"{f}=_rec_MISS")
            body.append(f"    if {f} is _rec_MISS: raise TypeError("
                        f"_rec_cls.__name__ + \"() missing argument '{f}'\")")
        else:
            params.append(f)
    direct = not frozen and cls.__setattr__ is object.__setattr__
    for i, f in enumerate(fields):
        if not direct:  # set as object.__setattr__ does, past the class's own __setattr__
            slot = next((b.__dict__[f] for b in cls.__mro__ if f in b.__dict__), None)
            if slot is None or not hasattr(slot, "__set__") or isinstance(slot, property):
                return
            env[f"_rec_s{i}"] = slot.__set__
            body.append(f"    _rec_s{i}(self, {f})")
        else:
            body.append(f"    self.{f} = {f}")
    src = f"def __init__(self, {', '.join(params)}):\n" + "\n".join(body or ["    pass"])
    exec(src, env)  # noqa: S102 (generated from the field names, nothing else)
    fast = env["__init__"]
    fast.__qualname__ = f"{cls.__qualname__}.__init__"
    cls.__init__ = fast
