"""Compile helper: an impact's commonest contact stamped without the element layers.

In: a smooth contact with Newton's law and a given e between particles (or one and the
ground), and compile._impulse_phase's lists. Out: the unknowns, rows, impulses and sources
ContactElement.stamp makes, in its order (tests/test_impact_contacts.py compares them).
"""
from __future__ import annotations

from math import copysign

from .elements.base import ImpulseSource
from .elements.contacts import NewtonRestitution, RESTITUTION_LAWS, Smooth, TANGENTIAL_LAWS, \
    _along
from .elements.keys import impulse_key, parameter_key
from .elements.kinds import Component, KeyKind, Restitution, Tangential
from .expr import V2, ZERO, Const, Known, mul, neg
from .tree_template import plain_leaves, template
from .units import IMPULSE

_PLAIN = (float, int)
ZERO_V2 = V2(ZERO, ZERO)  # compile's own (an arm at G): one frozen vector for all
ENABLED = True  # tests switch it off to compare with the element's own stamp
_JN = Component.JN
_E = Component.E


_FIT: dict = {}  # (law, separation given, mode) -> whether the laws fit (a few kinds)


def _laws_fit(c) -> bool:
    """Smooth with Newton's law, as ContactElement would choose them."""
    kind = (getattr(c, "law", None), c.separation is not None, c.mode)
    hit = _FIT.get(kind)
    if hit is None:
        law = kind[0] or (Restitution.SEPARATION if kind[1] else Restitution.NEWTON)
        hit = RESTITUTION_LAWS.get(law) is NewtonRestitution and \
            TANGENTIAL_LAWS.get(Tangential(c.mode)) is Smooth
        if len(_FIT) < 64:
            _FIT[kind] = hit
    return hit


def fits(c, bodies) -> bool:
    """Whether contact c takes this path: Newton's law with a given float e, smooth, a
    float normal, and particles at both ends whose point velocity is their own."""
    if not ENABLED:
        return False
    n = c.normal
    if n is None or c.restitution_unknown or type(c.restitution) is not float or \
            type(n[0]) is not float or type(n[1]) is not float:
        return False
    for p in (c.a, c.b):
        if p is None:
            continue
        if p.body is None or p.located_by is not None:
            return False
        b = bodies[p.body]
        if not b.is_particle or (p.round_contact and b.radius and type(b.radius) not in _PLAIN):
            return False
    return _laws_fit(c)


def stamp(comp, c, i: str, j: str, key: str, group: str, pins: bool, hits, applied, lin,
          sources, contacts) -> None:
    """ContactElement(c).stamp for a contact that `fits`, with Phase.apply inlined."""
    bodies = comp.scene.bodies
    n = c.normal
    n0, n1 = n
    label = c.label
    kn = impulse_key(_JN, label, key)
    Jn = comp.unknown(kn, IMPULSE, KeyKind.IMPULSE)
    comp.unknowns[kn].hints.append((">", 0.0, c.span))
    e = c.restitution
    pa, pb = c.a, c.b
    a = pa.body
    vel = comp.vel
    E_ = Known(parameter_key(_E, label), e)
    # the unknowns in the order the element makes them: J_n, then v_a, v_b before, after
    if pb is not None:
        b = pb.body
        va1, vb1, va2, vb2 = vel(a, i), vel(b, i), vel(a, j), vel(b, j)
        leaves = (Jn, va1.x, va1.y, vb1.x, vb1.y, va2.x, va2.y, vb2.x, vb2.y, E_)
    else:
        va1, va2 = vel(a, i), vel(a, j)
        leaves = (Jn, va1.x, va1.y, va2.x, va2.y, E_)
    f = None
    if plain_leaves(*leaves):
        f = template(("contact", n0, copysign(1.0, n0), n1, copysign(1.0, n1), e,
                      copysign(1.0, e), pb is not None), _builder, len(leaves), n0, n1, e, pb)
    J, Jb, vn1, vn2, loss, rhs = (f or _builder(n0, n1, e, pb))(*leaves)
    body_a = bodies[a]
    _apply(comp, pa, body_a, J, n, 1.0, pins, hits, applied, lin, sources)
    if pb is not None:
        _apply(comp, pb, bodies[pb.body], Jb, n, -1.0, pins, hits, applied, lin, sources)
    where = f"{label}'s contact point" if pa.round_contact and body_a.radius else pa.name
    sources.append(ImpulseSource((a, pb.body if pb is not None else None), where, n, False,
                                 f"contact {label}"))
    comp.losses.setdefault(key, []).append(loss)
    comp.eq(vn2, rhs, f"restitution at {label} (Newton)", group, c.span)
    contacts.append((label, vn1, vn2))


def _builder(n0: float, n1: float, e: float, pb):
    """The contact's trees from its leaves, as the element folds them: J on a (and -J on
    b), v_n before and after, the energy loss and the restitution row's right side."""
    def trees(Jn, *rest):
        if pb is not None:
            ax1, ay1, bx1, by1, ax2, ay2, bx2, by2, E_ = rest
            r1 = V2(ax1, ay1) - V2(bx1, by1)
            r2 = V2(ax2, ay2) - V2(bx2, by2)
        else:
            ax1, ay1, ax2, ay2, E_ = rest
            r1 = V2(ax1, ay1) - V2(ZERO, ZERO)
            r2 = V2(ax2, ay2) - V2(ZERO, ZERO)
        J = V2(_along(Jn, n0, -n1), _along(Jn, n1, n0))
        nv = V2(Const(n0), Const(n1))
        vn1, vn2 = r1.dot(nv), r2.dot(nv)
        loss = mul(Const(-0.5), mul(Jn, mul(Const(1.0 - e), vn1)))
        return J, (-J if pb is not None else None), vn1, vn2, loss, mul(neg(E_), vn1)
    return trees


def _apply(comp, p, body, J, normal, sign, pins, hits, applied, lin, sources) -> None:
    """compile's `apply` for a particle: its arm (the rim along the normal, or none)."""
    r = body.radius
    if p.round_contact and r:
        arm = V2(Const(-sign * r * normal[0]), Const(-sign * r * normal[1]))
    else:
        arm = ZERO_V2
    if pins:
        hits[p.body].append((p, arm, J, None))
    applied.append((len(sources), comp.Applied(p.body, p, J, None, arm)))
    lin[p.body].append(J)
