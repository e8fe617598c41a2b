"""The declared effects and constraints at one instant: accelerations, forces, energy.

Only what the file declares acts: gravity if `gravity` is declared, springs, the
simulation's dampers, forces, moments and bearing torques, and the constraint forces
of joints and of the contacts that persist in this phase.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .dynamics import (
    Frame,
    add_force,
    add_moment,
    contact_geometry,
    mass_diagonal,
)
from .model import Model


@dataclass
class Phase:
    """What holds between two events: persistent contacts and the bearings' states."""

    contacts: dict = field(default_factory=dict)  # label -> Regime.REST | STICK | +1.0 | -1.0
    locked: set = field(default_factory=set)  # bearing pins turning together
    bearing_sign: dict = field(default_factory=dict)  # pin -> sign of the relative rotation


@dataclass
class Instant:
    udot: np.ndarray
    lam: dict  # constraint force name -> value (N, or N*m)
    power: float  # of the forces that are not potentials (work W is its integral)


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
    """The velocity rows (SimRow) of the pins, welds and links, each from its element."""
    return [r for j in model.joints for r in j.constraint(frame)]


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
    for j in model.springs + model.dampers:
        power += j.sim_force(frame, Q)
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
    constraints = joint_rows(frame, model)
    sliding = []
    for w in model.watches:
        mode = phase.contacts.get(w.label)
        if mode is None:
            continue
        geo = contact_geometry(frame, w)
        if mode in (1.0, -1.0):
            sliding.append((w, geo, len(constraints)))
        constraints += w.element.constraint(frame, w, geo, mode)
    for r in constraints:
        rows.append(r.row)
        cols.append(r.row if r.col is None else r.col)
        betas.append(r.beta)
        names.append(r.name)
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
        power += w.element.tangential.sim_power(x[n + k], v[0] * t[0] + v[1] * t[1],
                                                phase.contacts[w.label])
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
        E += j.sim_energy(frame)
    return E


def kinetic(model: Model, frame: Frame) -> float:
    T = 0.0
    for b in model.bodies:
        vx, vy, w = frame.twist[b.name]
        T += 0.5 * b.mass * (vx * vx + vy * vy) + (0.0 if b.particle else 0.5 * b.inertia * w * w)
    return T
