"""What ends a phase: contacts closing or opening, slip stopping, stop conditions.

Each event is a scalar function of the state whose sign change (in its direction)
marks it. Where the phase's accelerations are constant and the function is a
polynomial of degree <= 2 in time along the path, it also gives its coefficients, so
the phase is advanced in closed form and the event time is a root of a quadratic.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

from .dynamics import Frame, contact_geometry, gap_rate, relative_velocity
from .forces import Instant, relative_spin
from .model import Model, Watch

QTY_INDEX = {"vx": 0, "vy": 1, "omega": 2}


@dataclass
class Event:
    kind: str  # contact | separate | stick | slip | lock | unlock | until | apex | drift
    what: str
    fn: Callable  # (frame, instant-or-None) -> float
    direction: int = 0
    needs_instant: bool = False
    poly: Callable | None = None  # (frame, udot) -> (c0, c1, c2), closed-form phases only


def gap_event(model: Model, w: Watch, shift: float = 0.0) -> Event:
    """The gap closing; `shift` > 0 for a contact that starts touching (it must close
    past -shift, so that resting at zero is not an event)."""
    def fn(frame, _):
        return contact_geometry(frame, w)[0] + shift

    poly = None
    if w.b is None and w.a.offset == (0.0, 0.0):  # a centre against a plane: quadratic
        def poly(frame, udot):
            b = model.by_name[w.a.body]
            n = w.normal
            if b.size == 1:
                return None
            i = b.index
            gap = contact_geometry(frame, w)[0] + shift
            vx, vy, _ = frame.twist[b.name]
            return (gap, vx * n[0] + vy * n[1], 0.5 * (udot[i] * n[0] + udot[i + 1] * n[1]))
    return Event("contact", w.label, fn, -1, poly=poly)


def separation_event(w: Watch) -> Event:
    def fn(frame, inst: Instant):
        return inst.lam.get(f"N[{w.label}]", 0.0)

    return Event("separate", w.label, fn, -1, needs_instant=True,
                 poly=lambda frame, udot: (1.0, 0.0, 0.0))


def slip_event(w: Watch) -> Event:
    def fn(frame, _):
        geo = contact_geometry(frame, w)
        v = relative_velocity(frame, w, geo)
        n = geo[1]
        return -v[0] * n[1] + v[1] * n[0]

    def poly(frame, udot):
        from .dynamics import tangent_row

        geo = contact_geometry(frame, w)
        row, beta, _ = tangent_row(frame, w, geo)
        return (fn(frame, None), float(row @ udot) + beta, 0.0)

    return Event("stick", w.label, fn, 0, poly=poly if w.ra > 0 or w.a.offset == (0.0, 0.0)
                 else None)


def stick_limit_event(w: Watch) -> Event:
    def fn(frame, inst: Instant):
        return w.spec.mu * inst.lam.get(f"N[{w.label}]", 0.0) - \
            abs(inst.lam.get(f"F_t[{w.label}]", 0.0))

    return Event("slip", w.label, fn, -1, needs_instant=True,
                 poly=lambda frame, udot: (1.0, 0.0, 0.0))


def bearing_events(model: Model, label: str, locked: bool) -> Event:
    if locked:
        torque = model.bearings[label]

        def fn(frame, inst):
            return torque - abs(inst.lam.get(f"M[{label}]", 0.0))

        return Event("unlock", label, fn, -1, needs_instant=True)

    def spin(frame, _):
        return relative_spin(frame, model, label)

    return Event("lock", label, spin, 0)


def until_qty(model: Model, u) -> Event:
    b = model.by_name[u.body]

    def fn(frame, _):
        x, y, th = frame.pose[b.name]
        vx, vy, w = frame.twist[b.name]
        return {"x": x, "y": y, "angle": th, "vx": vx, "vy": vy, "omega": w}[u.qty] - u.value

    def poly(frame, udot):
        if b.size == 1:
            return None
        i = b.index
        c0 = fn(frame, None)
        if u.qty in ("x", "y", "angle"):
            k = "xya".index(u.qty[0])
            return (c0, frame.twist[b.name][k], 0.5 * udot[i + k])
        return (c0, udot[i + QTY_INDEX[u.qty]], 0.0)

    return Event("until", f"{u.body}.{u.qty} = {u.value:.6g}", fn, 0, poly=poly)


def apex_event(model: Model) -> Event:
    """The vertical momentum (against gravity) of the whole scene goes from up to down."""
    g = model.gravity
    gn = math.hypot(*g)
    up = (-g[0] / gn, -g[1] / gn)

    def fn(frame, _):
        p = 0.0
        for b in model.bodies:
            vx, vy, _ = frame.twist[b.name]
            p += b.mass * (vx * up[0] + vy * up[1])
        return p

    def poly(frame, udot):
        if any(b.size == 1 for b in model.bodies):
            return None
        rate = sum(b.mass * (udot[b.index] * up[0] + udot[b.index + 1] * up[1])
                   for b in model.bodies)
        return (fn(frame, None), rate, 0.0)

    return Event("apex", "apex", fn, -1, poly=poly)


def touching(model: Model, frame: Frame, tol: float):
    """[(watch, geometry, normal speed)] of contacts whose gap is within tol."""
    out = []
    for w in model.watches:
        geo = contact_geometry(frame, w)
        if geo[0] <= tol:
            out.append((w, geo, gap_rate(frame, w, geo)))
    return out


def first_root(c0: float, c1: float, c2: float, direction: int, horizon: float) -> float | None:
    """The first t in (0, horizon] where c0 + c1 t + c2 t^2 crosses zero in `direction`."""
    roots = []
    if c2 == 0:
        if c1 != 0:
            roots.append(-c0 / c1)
    else:
        disc = c1 * c1 - 4 * c2 * c0
        if disc >= 0:
            sq = math.sqrt(disc)
            qv = -0.5 * (c1 + math.copysign(sq, c1))
            if qv != 0:
                roots += [qv / c2, c0 / qv]
            else:
                roots.append(0.0)
    best = None
    for t in sorted(roots):
        if t <= 0 or t > horizon:
            continue
        slope = c1 + 2 * c2 * t
        if direction and slope * direction < 0:
            continue
        if slope == 0 and c2 * c0 > 0:
            continue  # touches zero without crossing
        best = t
        break
    return best
