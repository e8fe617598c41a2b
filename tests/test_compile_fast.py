"""The compile's shortcuts equal its general paths: the direct stamp of a smooth contact
with a given e (elements/contacts.py), a particle's point velocity (compile.py) and the
short printing of small rows (compile._short_text), on every example and on generated
big scenes, node for node (tests/structure_dump.py) and character for character.
"""
from __future__ import annotations

from pathlib import Path

import pytest

from momentum_cli.bench import chain_text
from structure_dump import system_lines
from test_hard import cradle_text

ROOT = Path(__file__).resolve().parent.parent


def _texts():
    out = [(str(p.relative_to(ROOT)), p.read_text(encoding="utf-8"))
           for p in sorted((ROOT / "examples").glob("*.mom"))]
    out += [("chain", chain_text(40)), ("cradle", cradle_text(30, "sequence")),
            ("cradle together", cradle_text(12, "simultaneous"))]
    return out


def _compile(text: str, name: str):
    from momentum_cli.compile import compile_scene
    from momentum_cli.diagnostics import ProblemError
    from momentum_cli.scene import build
    from momentum_cli.source import Source
    from momentum_cli.syntax import parse

    try:
        return compile_scene(build(parse(Source(name, text))))
    except ProblemError as exc:
        return f"error {exc}"


def _lines(system) -> list[str]:
    if isinstance(system, str):
        return [system]
    out = system_lines(system)
    out += [f"{e.principle}: {e.text()}" for e in system.equations]
    out += [repr(list(system.unknowns))]
    return out


def _general_paths(monkeypatch) -> None:
    """Turn the shortcuts off: contacts stamp through their rows and laws, every point
    velocity through its arm and w x r, every row prints through to_text."""
    import momentum_cli.compile as C
    from momentum_cli.elements.contacts import ContactElement
    from momentum_cli.expr import V2, ZERO, omega_cross

    general_stamp = ContactElement.stamp

    def point_velocity(self, p, sid, normal=None, sign=1.0):
        if p is None or p.body is None:
            return V2(ZERO, ZERO)
        r = self.arm(p, sid, normal, sign)
        v = self.vel(p.body, sid)
        w = self.sv(p.body, "omega", sid)
        if w is ZERO and C._plain_const(r.x) and C._plain_const(r.y):
            return v
        return v + omega_cross(w, r)

    monkeypatch.setattr(ContactElement, "stamp", _unshortcut_stamp(general_stamp))
    monkeypatch.setattr(C._Compiler, "point_velocity", point_velocity)
    monkeypatch.setattr(C, "_short_text", lambda e: None)


def _unshortcut_stamp(general_stamp):
    """ContactElement.stamp with its shortcut's condition made false: the tangential
    law's exact-type test fails for a subclass that changes nothing else."""
    from momentum_cli.elements import contacts as K

    class SmoothAgain(K.Smooth):
        pass

    def stamp(self, phase, compiler):
        if type(self.tangential) is K.Smooth:
            self.tangential = SmoothAgain(self.c)
        return general_stamp(self, phase, compiler)

    return stamp


@pytest.mark.parametrize("name,text", _texts(), ids=[n for n, _ in _texts()])
def test_shortcuts_equal_the_general_paths(name, text, monkeypatch):
    fast = _lines(_compile(text, name))
    with monkeypatch.context() as m:
        _general_paths(m)
        slow = _lines(_compile(text, name))
    assert fast == slow


def test_short_text_prints_as_to_text():
    from momentum_cli.compile import _short_text
    from momentum_cli.expr import Add, Const, Known, Mul, Var, to_text

    a, b, m = Var("b.vx@2"), Known("b.vx@1", 2.0), Known("m_b", 3.0)
    trees = [a, m, Mul((Const(-1.0), a)), Mul((m, Add((a, Mul((Const(-1.0), b)))))),
             Mul((Const(-2.0), a)), Mul((m, Add((a, Mul((Const(-1.0), Const(3.0))))))),
             Mul((m, Add((a, b)))), Add((a, b)), Const(-1.0), Mul((a, a))]
    short = 0
    for t in trees:
        s = _short_text(t)
        if s is not None:
            short += 1
            assert s == to_text(t)
    assert short == 4


def test_key_constructors_make_what_key_makes():
    """state_key, impulse_key and parameter_key build their Key without Key.__new__:
    the same text, class and fields (and the same after pickling) as Key(...) gives."""
    import pickle

    from momentum_cli.elements.keys import Key, impulse_key, parameter_key, state_key
    from momentum_cli.elements.kinds import Component, KeyKind

    def fields(k):
        return (str(k), type(k), k.kind, k.body, k.qty, k.state, k.transition, k.label,
                k.comp)

    pairs = [(state_key("b", "vx", "3"),
              Key("b.vx@3", KeyKind.STATE, body="b", qty="vx", state="3"))]
    for comp in Component:
        kind = KeyKind.ANGULAR_IMPULSE if comp is Component.M else KeyKind.IMPULSE
        pairs.append((impulse_key(comp, "A", "1->2"),
                      Key(f"{comp}[A]@1->2", kind, label="A", transition="1->2", comp=comp)))
        kind = KeyKind.RESTITUTION if comp is Component.E else KeyKind.PARAMETER
        pairs.append((parameter_key(comp, "A"), Key(f"{comp}[A]", kind, label="A", comp=comp)))
    for fast, slow in pairs:
        assert fields(fast) == fields(slow)
        assert fields(pickle.loads(pickle.dumps(fast))) == fields(slow)


def test_a_smooth_contacts_impulse_folds_as_mul_and_add():
    """contacts._along gives the tree add(mul(J_n, a), mul(0, b)) gives, for zeros of
    either sign, ones, infinities, NaN and ints."""
    import itertools
    import math

    from momentum_cli.elements.contacts import _along
    from momentum_cli.expr import ZERO, Const, Var, add, mul
    from structure_dump import node

    J = Var("J_n[A]@1->2")
    values = [0.0, -0.0, 1.0, -1.0, 0.6, -0.8, 1e-300, 2.0, math.inf, -math.inf, math.nan,
              1, 2, 0]
    for a, b in itertools.product(values, values):
        fast, slow = [], []
        node(_along(J, a, b), fast)
        node(add(mul(J, Const(a)), mul(ZERO, Const(b))), slow)
        assert fast == slow, (a, b)
