"""The declared effects and constraints at one instant: accelerations, forces, energy.

Only what the file declares acts: gravity if `gravity` is declared, springs, the
simulation's dampers, forces, moments and bearing torques, and the constraint forces
of joints and of the contacts that persist in this phase.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .dynamics import (
    Frame,
    add_force,
    add_moment,
    contact_geometry,
    mass_diagonal,
    normal_row,
    tangent_row,
)
from .model import Model


@dataclass
class Phase:
    """What holds between two events: persistent contacts and the bearings' states."""

    contacts: dict = field(default_factory=dict)  # label -> "rest" | "stick" | +1.0 | -1.0
    locked: set = field(default_factory=set)  # bearing pins turning together
    bearing_sign: dict = field(default_factory=dict)  # pin -> sign of the relative rotation


@dataclass
class Instant:
    udot: np.ndarray
    lam: dict  # constraint force name -> value (N, or N*m)
    power: float  # of the forces that are not potentials (work W is its integral)


def _joint_points(frame: Frame, j):
    ra = frame.offset(j.a.body, j.a.offset)
    rb = frame.offset(j.b.body, j.b.offset) if j.b.body is not None else None
    return ra, rb


def _line(frame: Frame, j):
    """A spring's or damper's line from a to b: offsets, unit direction, length and rate
    of extension; None when its ends meet (no direction)."""
    ra, rb = _joint_points(frame, j)
    pa, pb = frame.point(j.a.body, j.a.offset), frame.point(j.b.body, j.b.offset)
    dx, dy = pb[0] - pa[0], pb[1] - pa[1]
    L = math.hypot(dx, dy)
    if L == 0:
        return None
    ex, ey = dx / L, dy / L
    va = frame.point_velocity(j.a.body, ra)
    vb = frame.point_velocity(j.b.body, rb) if rb is not None else (0.0, 0.0)
    return ra, rb, ex, ey, L, (vb[0] - va[0]) * ex + (vb[1] - va[1]) * ey


def _pull(frame: Frame, Q, j, ra, rb, tension: float, ex: float, ey: float) -> None:
    """Equal and opposite forces along the line: `tension` > 0 pulls the ends together."""
    add_force(frame, Q, j.a.body, ra, (tension * ex, tension * ey))
    add_force(frame, Q, j.b.body, rb, (-tension * ex, -tension * ey))


def _pair_rows(frame: Frame, j):
    ra, rb = _joint_points(frame, j)
    Ja, ba = frame.point_jac(j.a.body, ra)
    if rb is None:
        return Ja, np.array(ba)
    Jb, bb = frame.point_jac(j.b.body, rb)
    return Ja - Jb, np.array(ba) - np.array(bb)


def _rotation_row(frame: Frame, a: str, b: str | None):
    row = frame.jac[a][2].copy()
    if b is not None:
        row -= frame.jac[b][2]
    return row


def pin_bodies(model: Model, label: str):
    for j in model.scene.joints:
        if j.label == label:
            return j.a.body, j.b.body
    raise KeyError(label)


def relative_spin(frame: Frame, model: Model, label: str) -> float:
    a, b = pin_bodies(model, label)
    return frame.twist[a][2] - (frame.twist[b][2] if b else 0.0)


def joint_rows(frame: Frame, model: Model) -> list:
    """[(force name, velocity row, acceleration term)] of the pins, welds and links."""
    out = []
    for j in model.joints:
        J, beta = _pair_rows(frame, j)
        if j.kind == "link":
            d = j.along
            out.append((f"F[{j.label}]", d[0] * J[0] + d[1] * J[1],
                        d[0] * beta[0] + d[1] * beta[1]))
            continue
        for k, axis in enumerate("xy"):
            out.append((f"F{axis}[{j.label}]", J[k], beta[k]))
        if j.kind == "weld":
            out.append((f"M[{j.label}]", _rotation_row(frame, j.a.body, j.b.body), 0.0))
    return out


def instant(model: Model, phase: Phase, frame: Frame) -> Instant:
    """Solve [[M, -B^T], [A, 0]] [u', lambda] = [Q, -beta] at this frame."""
    mdiag = mass_diagonal(frame, model)
    Q = [0.0] * model.n
    power = 0.0
    g = model.gravity
    if g is not None:
        for b in model.bodies:
            add_force(frame, Q, b.name, (0.0, 0.0), (b.mass * g[0], b.mass * g[1]))
    for F, p, _ in model.forces:
        r = frame.offset(p.body, p.offset)
        add_force(frame, Q, p.body, r, F)
        v = frame.point_velocity(p.body, r)
        power += F[0] * v[0] + F[1] * v[1]
    for Mo, body, _ in model.moments:
        add_moment(frame, Q, body, Mo)
        power += Mo * frame.twist[body][2]
    for j in model.springs:
        line = _line(frame, j)
        if line is not None:
            ra, rb, ex, ey, L, _ = line
            _pull(frame, Q, j, ra, rb, j.stiffness * (L - j.length), ex, ey)
    for j in model.dampers:
        line = _line(frame, j)
        if line is not None:
            ra, rb, ex, ey, _, rate = line
            _pull(frame, Q, j, ra, rb, j.stiffness * rate, ex, ey)
            power -= j.stiffness * rate * rate
    rows, betas, cols, names = [], [], [], []
    for label, torque in model.bearings.items():
        a, b = pin_bodies(model, label)
        if label in phase.locked:
            r = _rotation_row(frame, a, b)
            rows.append(r)
            cols.append(r)
            betas.append(0.0)
            names.append(f"M[{label}]")
        else:
            s = phase.bearing_sign.get(label, 0.0)
            add_moment(frame, Q, a, -torque * s)
            add_moment(frame, Q, b, torque * s)
            power -= torque * abs(relative_spin(frame, model, label))
    for name, r, beta in joint_rows(frame, model):
        rows.append(r)
        cols.append(r)
        betas.append(beta)
        names.append(name)
    sliding = []
    for w in model.watches:
        mode = phase.contacts.get(w.label)
        if mode is None:
            continue
        geo = contact_geometry(frame, w)
        rn, bn = normal_row(frame, w, geo)
        col = rn
        if mode in (1.0, -1.0):
            rt, _, t = tangent_row(frame, w, geo)
            col = rn - w.spec.mu * mode * rt
            sliding.append((w, geo, len(rows)))
        rows.append(rn)
        cols.append(col)
        betas.append(bn)
        names.append(f"N[{w.label}]")
        if mode == "stick":
            rt, bt, _ = tangent_row(frame, w, geo)
            rows.append(rt)
            cols.append(rt)
            betas.append(bt)
            names.append(f"F_t[{w.label}]")
    m = len(rows)
    if m == 0:
        return Instant(np.array([q / m for q, m in zip(Q, mdiag)]), {}, power)
    # u' = M^-1 (Q + B^T lam), A u' = -beta  =>  (A M^-1 B^T) lam = -beta - A M^-1 Q
    A = np.array(rows)
    mdiag = np.array(mdiag)
    Bt_scaled = np.array(cols).T / mdiag[:, None]
    MiQ = np.array(Q) / mdiag
    S_ = A @ Bt_scaled
    rhs = -np.array(betas) - A @ MiQ
    try:
        lam_v = np.linalg.solve(S_, rhs)
    except np.linalg.LinAlgError:
        lam_v = np.linalg.lstsq(S_, rhs, rcond=None)[0]
    udot = MiQ + Bt_scaled @ lam_v
    x = np.concatenate([udot, lam_v])
    n = model.n
    lam = dict(zip(names, x[n:].tolist()))
    for w, geo, k in sliding:
        from .dynamics import relative_velocity

        v = relative_velocity(frame, w, geo)
        t = (-geo[1][1], geo[1][0])
        power -= w.spec.mu * max(x[n + k], 0.0) * abs(v[0] * t[0] + v[1] * t[1])
    return Instant(x[:n], lam, power)


def energy(model: Model, frame: Frame) -> float:
    """Kinetic energy plus the potentials of gravity and springs."""
    E = 0.0
    g = model.gravity
    for b in model.bodies:
        vx, vy, w = frame.twist[b.name]
        E += 0.5 * b.mass * (vx * vx + vy * vy)
        if not b.particle:
            E += 0.5 * b.inertia * w * w
        if g is not None:
            gx, gy, _ = frame.pose[b.name]
            E -= b.mass * (g[0] * gx + g[1] * gy)
    for j in model.springs:
        pa, pb = frame.point(j.a.body, j.a.offset), frame.point(j.b.body, j.b.offset)
        L = math.hypot(pb[0] - pa[0], pb[1] - pa[1])
        E += 0.5 * j.stiffness * (L - j.length) ** 2
    return E


def kinetic(model: Model, frame: Frame) -> float:
    T = 0.0
    for b in model.bodies:
        vx, vy, w = frame.twist[b.name]
        T += 0.5 * b.mass * (vx * vx + vy * vy) + (0.0 if b.particle else 0.5 * b.inertia * w * w)
    return T
