"""Identities of unknowns and named knowns: `rod.omega@3`, `J_n[A]@2->3`, `t@1->2`.

A Key is a `str` (dicts keyed by name, sorting and printed text are unchanged) that also
carries what it names as fields, so no module parses a name back. Keys are made only by
the constructors below.
"""
from __future__ import annotations

from .kinds import Component, KeyKind


class Key(str):
    """A name with its structure: kind, body, qty, state, transition, label, comp.
    Slotted: a big scene makes ~6 keys per body, and a per-key __dict__ cost 300 bytes."""

    __slots__ = ("kind", "body", "qty", "state", "transition", "label", "comp")
    kind: KeyKind
    body: str | None
    qty: str | None
    state: str | None
    transition: str | None
    label: str | None
    comp: Component | None

    def __new__(cls, text: str, kind: KeyKind, body: str | None = None, qty: str | None = None,
                state: str | None = None, transition: str | None = None,
                label: str | None = None, comp: Component | None = None) -> "Key":
        k = super().__new__(cls, text)
        k.kind, k.body, k.qty, k.state = kind, body, qty, state
        k.transition, k.label, k.comp = transition, label, comp
        return k

    def __reduce__(self):
        return (Key, (str(self), self.kind, self.body, self.qty, self.state, self.transition,
                      self.label, self.comp))

    @property
    def local(self) -> str:
        """The name without its transition: `J_n[A]` for `J_n[A]@2->3`."""
        if self.comp is not None and self.label is not None:
            return f"{self.comp}[{self.label}]"
        return str(self)


_str_new = str.__new__  # a Key made without Key.__new__'s keywords: 4x faster


def _key(text: str, kind: KeyKind, body, qty, state, transition, label, comp) -> Key:
    """What `Key(text, kind, ...)` makes, for the constructors below (a big scene makes
    ~6 keys a body)."""
    k = _str_new(Key, text)
    k.kind = kind
    k.body = body
    k.qty = qty
    k.state = state
    k.transition = transition
    k.label = label
    k.comp = comp
    return k


def state_key(body: str, qty: str, sid: str) -> Key:
    """A body's state quantity: `rod.omega@3`."""
    return _key(f"{body}.{qty}@{sid}", KeyKind.STATE, body, qty, sid, None, None, None)


def impulse_key(comp: Component, label: str, transition: str) -> Key:
    """A reaction's impulse in a transition: `J_n[A]@2->3`, `M[O]@1->2`."""
    kind = KeyKind.ANGULAR_IMPULSE if comp is Component.M else KeyKind.IMPULSE
    # comp's word as str(comp) gives it (its value), without the enum's __str__
    return _key(f"{comp._value_}[{label}]@{transition}", kind, None, None, None, transition,
                label, comp)


def duration_key(transition: str) -> Key:
    """An interval's duration: `t@1->2`."""
    return Key(f"t@{transition}", KeyKind.DURATION, transition=transition)


def parameter_key(comp: Component, label: str) -> Key:
    """A contact's parameter: `e[A]`, `v_sep[A]`."""
    kind = KeyKind.RESTITUTION if comp is Component.E else KeyKind.PARAMETER
    return _key(f"{comp._value_}[{label}]", kind, None, None, None, None, label, comp)


def named_key(name: str, kind: KeyKind) -> Key:
    """A name the file chose (a declared unknown, `e` of a contact given one)."""
    return Key(name, kind)


def key_fields(name: str) -> Key | None:
    """The Key behind a name, or None for a plain string (a name built elsewhere)."""
    return name if isinstance(name, Key) else None
