"""Compile helper: a whole impact of particles at simple contacts, without the phase layers.

In: an impact whose only actors are contacts that impact_contacts.fits, every body it moves
a particle, no joint, flow or end condition. Out: what compile._impulse_phase makes for it
(unknowns, rows, sources, losses, TransitionInfo), in its order; the why-lines and the
system laws' texts come from format strings made once per kind (why_texts.py).
"""
from __future__ import annotations

from collections import defaultdict

from . import impact_contacts
from .elements.kinds import TransitionKind
from .expr import Add, Const, Known, Mul, Var, add, add_all, mul, neg
from .system_laws import linear_laws
from .why_texts import linear_texts, why_lines

ENABLED = True  # tests switch it off to compare with compile._impulse_phase
_NAMED = (Var, Known)
_IMPACT = TransitionKind.IMPACT


def fits(comp, t) -> bool:
    """Whether impact t takes this path (see the module's docstring)."""
    if not ENABLED or t.kind is not _IMPACT or comp.joints or comp.flows is not None:
        return False
    if t.bearing_friction or t.stops or t.stops_relative or t.rolls or t.forces or \
            t.moments or t.duration_expr is not None:
        return False
    bodies = comp.scene.bodies
    for b in comp._busy[t.key]:
        if not bodies[b].is_particle:
            return False
    fit = impact_contacts.fits
    for c in t.contacts:
        if not fit(c, bodies):
            return False
    return True


def stamp(comp, t, key: str) -> None:
    """compile._impulse_phase for an impact that `fits`."""
    i, j = t.before, t.after
    group = f"{t.kind} {i} -> {j}"
    lin: dict = defaultdict(list)
    applied: list = []
    sources: list = []
    contacts_info: list = []
    one = impact_contacts.stamp
    for c in t.contacts:
        one(comp, c, i, j, key, group, False, None, applied, lin, sources, contacts_info)
    moved = comp._moved(key)
    vel, mass, eq, span = comp.vel, comp.mass, comp.eq, t.span
    for b in moved:
        v1, v2 = vel(b, i), vel(b, j)
        m = mass(b, i)
        Js = lin[b]
        named = type(m) in _NAMED
        for comp_, a1, a2, rhs in (("x", v1.x, v2.x, add_all([J.x for J in Js])),
                                   ("y", v1.y, v2.y, add_all([J.y for J in Js]))):
            if named and type(a1) in _NAMED and type(a2) in _NAMED:
                lhs = Mul((m, Add((a2, Mul((Const(-1.0), a1))))))
            else:
                lhs = mul(m, add(a2, neg(a1)))
            eq(lhs, rhs, f"linear impulse-momentum {comp_}: {b}", group, span)
    comp.sources[key] = sources
    why = why_lines(comp, sources, moved)
    energy = (comp._kinetic(i, moved), comp._kinetic(j, moved))
    texts = linear_texts(sources, moved) if len(moved) >= 2 else None
    laws = linear_laws(comp, moved, i, j, *texts) if texts is not None else []
    n = len(sources)
    for k, a in applied:
        a.what = sources[k].what if k < n else ""
    comp.transitions.append(comp.TransitionInfo(t.kind, key, i, j, span, why, contacts_info,
                                                energy, tuple(moved), laws,
                                                [a for _, a in applied]))
