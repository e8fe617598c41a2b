"""Accelerations of the simulated scene at one instant, with its constraint forces.

Newton-Euler for each body, written in the bodies' coordinates q (velocities u):
    M(q) u' = Q(q, u) + B^T lambda,    A(q) u' = -beta(q, u)
where the rows of A are the velocity constraints that hold in this phase (joints,
persistent contacts, rolling, locked bearings) and beta their velocity-product terms.
A sliding contact's friction, -mu N along the slip, is carried by its normal force's
column of B, so the system stays linear in (u', lambda).
"""
from __future__ import annotations

import math

import numpy as np

from ..elements.geometry import line_of_centres
from .model import Model, Watch, centre, rot


class Frame:
    """Positions, velocities and velocity Jacobians of every body at one (q, u)."""

    def __init__(self, model: Model, q, u):
        self.model = model
        self.pose: dict[str, tuple[float, float, float]] = {}
        self.twist: dict[str, tuple[float, float, float]] = {}
        self.bias: dict[str, tuple[float, float]] = {}  # a_G terms without u'
        self.arm: dict[str, tuple[float, float]] = {}  # G - O of a pinned body
        self._jac: dict[str, np.ndarray] | None = None
        for b in model.bodies:
            i = b.index
            if b.size == 1:
                th, w = float(q[i]), float(u[i])
                c, s = math.cos(th), math.sin(th)
                px, py = b.pin_offset
                rx, ry = -(c * px - s * py), -(s * px + c * py)  # G - O
                self.pose[b.name] = (b.pivot[0] + rx, b.pivot[1] + ry, th)
                self.twist[b.name] = (-ry * w, rx * w, w)
                self.bias[b.name] = (-w * w * rx, -w * w * ry)
                self.arm[b.name] = (rx, ry)
            else:
                th = 0.0 if b.particle else float(q[i + 2])
                w = 0.0 if b.particle else float(u[i + 2])
                self.pose[b.name] = (float(q[i]), float(q[i + 1]), th)
                self.twist[b.name] = (float(u[i]), float(u[i + 1]), w)
                self.bias[b.name] = (0.0, 0.0)

    @property
    def jac(self) -> dict[str, np.ndarray]:
        """{body: 3 x n J} with (vx, vy, omega) = J u; built when a constraint needs it."""
        if self._jac is None:
            n = self.model.n
            self._jac = {}
            for b in self.model.bodies:
                J = np.zeros((3, n))
                i = b.index
                if b.size == 1:
                    rx, ry = self.arm[b.name]
                    J[0, i], J[1, i], J[2, i] = -ry, rx, 1.0
                else:
                    J[0, i] = J[1, i + 1] = 1.0
                    if not b.particle:
                        J[2, i + 2] = 1.0
                self._jac[b.name] = J
        return self._jac

    # ---- points
    def offset(self, body: str, r_body) -> tuple[float, float]:
        return rot(self.pose[body][2], r_body)

    def point(self, body: str | None, r_body) -> tuple[float, float]:
        if body is None:
            return (r_body[0], r_body[1])
        gx, gy, th = self.pose[body]
        rx, ry = rot(th, r_body)
        return (gx + rx, gy + ry)

    def point_velocity(self, body: str | None, r_world) -> tuple[float, float]:
        if body is None:
            return (0.0, 0.0)
        vx, vy, w = self.twist[body]
        return (vx - w * r_world[1], vy + w * r_world[0])

    # ---- for the elements (they do not import this module)
    def add_force(self, Q, body: str | None, r_world, F) -> None:
        add_force(self, Q, body, r_world, F)

    def normal_row(self, w: Watch, geometry):
        return normal_row(self, w, geometry)

    def tangent_row(self, w: Watch, geometry):
        return tangent_row(self, w, geometry)

    def point_jac(self, body: str | None, r_world, centripetal: bool = True):
        """(2 x n Jacobian, 2 acceleration terms without u') of a point at world offset
        r from G; `centripetal=False` for a round body's contact point, which is not a
        material point (it stays at G - R n)."""
        n = self.model.n
        if body is None:
            return np.zeros((2, n)), (0.0, 0.0)
        J = self.jac[body]
        Jp = J[:2].copy()
        Jp[0] -= r_world[1] * J[2]
        Jp[1] += r_world[0] * J[2]
        bx, by = self.bias[body]
        if centripetal:
            w = self.twist[body][2]
            bx -= w * w * r_world[0]
            by -= w * w * r_world[1]
        return Jp, (bx, by)


# ---- contact geometry -----------------------------------------------------------------
def contact_geometry(frame: Frame, w: Watch):
    """(gap, unit normal on a, world contact point, offset of that point from a's G,
    from b's G (None for a plane))."""
    pa = centre(frame.pose, w.a)
    if w.b is None:
        n = w.normal
        gap = (pa[0] - w.plane[0]) * n[0] + (pa[1] - w.plane[1]) * n[1] - w.ra - w.gap0
        pb = None
    else:
        pb = centre(frame.pose, w.b)
        if w.normal is not None:
            n = w.normal
            gap = (pa[0] - pb[0]) * n[0] + (pa[1] - pb[1]) * n[1] - w.ra - w.rb - w.gap0
        else:
            n, d = line_of_centres(pa, pb)
            n = n or (0.0, 1.0)
            gap = d - w.ra - w.rb - w.gap0
    c = (pa[0] - w.ra * n[0], pa[1] - w.ra * n[1])
    ga = frame.pose[w.a.body]
    ra = (c[0] - ga[0], c[1] - ga[1])
    rb = None
    if w.b is not None and w.b.body is not None:
        gb = frame.pose[w.b.body]
        rb = (c[0] - gb[0], c[1] - gb[1])
    return gap, n, c, ra, rb


def relative_velocity(frame: Frame, w: Watch, geometry) -> tuple[float, float]:
    """Velocity of a's contact point relative to b's (material points)."""
    _, _, _, ra, rb = geometry
    va = frame.point_velocity(w.a.body, ra)
    vb = frame.point_velocity(w.b.body, rb) if rb is not None else (0.0, 0.0)
    return (va[0] - vb[0], va[1] - vb[1])


def gap_rate(frame: Frame, w: Watch, geometry) -> float:
    """d(gap)/dt: the normal component of the relative velocity of the contact points."""
    v = relative_velocity(frame, w, geometry)
    n = geometry[1]
    return v[0] * n[0] + v[1] * n[1]


def normal_row(frame: Frame, w: Watch, geometry):
    """Row and acceleration term of d2(gap)/dt2 (centres for round bodies)."""
    gap, n, c, ra, rb = geometry
    pa_off = frame.offset(w.a.body, w.a.offset)
    Ja, ba = frame.point_jac(w.a.body, pa_off)
    row = n[0] * Ja[0] + n[1] * Ja[1]
    beta = n[0] * ba[0] + n[1] * ba[1]
    if w.b is not None and w.b.body is not None:
        pb_off = frame.offset(w.b.body, w.b.offset)
        Jb, bb = frame.point_jac(w.b.body, pb_off)
        row = row - (n[0] * Jb[0] + n[1] * Jb[1])
        beta -= n[0] * bb[0] + n[1] * bb[1]
        if w.normal is None:  # the normal turns as the centres move round each other
            va = frame.point_velocity(w.a.body, pa_off)
            vb = frame.point_velocity(w.b.body, pb_off)
            rvx, rvy = va[0] - vb[0], va[1] - vb[1]
            vn = rvx * n[0] + rvy * n[1]
            d = gap + w.ra + w.rb + w.gap0
            if d > 0:
                beta += (rvx * rvx + rvy * rvy - vn * vn) / d
    return row, beta


def tangent_row(frame: Frame, w: Watch, geometry):
    """Row and acceleration term of the slip rate along t = (-n_y, n_x): a's contact
    point relative to b's (the ground's is still). Between two bodies the turning of
    the normal is left out of the acceleration term: exact for a fixed normal."""
    gap, n, c, ra, rb = geometry
    t = (-n[1], n[0])
    Ja, ba = frame.point_jac(w.a.body, ra, centripetal=not w.ra > 0)
    row, beta = t[0] * Ja[0] + t[1] * Ja[1], t[0] * ba[0] + t[1] * ba[1]
    if rb is not None:
        Jb, bb = frame.point_jac(w.b.body, rb, centripetal=not w.rb > 0)
        row = row - (t[0] * Jb[0] + t[1] * Jb[1])
        beta -= t[0] * bb[0] + t[1] * bb[1]
    return row, beta, t


# ---- forces -----------------------------------------------------------------------------
def add_force(frame: Frame, Q, body: str | None, r_world, F) -> None:
    """Add force F acting at world offset r from G of `body` to the generalized forces."""
    if body is None:
        return
    b = frame.model.by_name[body]
    i = b.index
    if b.size == 1:
        ax, ay = frame.arm[body]
        Q[i] += (ax + r_world[0]) * F[1] - (ay + r_world[1]) * F[0]
        return
    Q[i] += F[0]
    Q[i + 1] += F[1]
    if b.size == 3:
        Q[i + 2] += r_world[0] * F[1] - r_world[1] * F[0]


def add_moment(frame: Frame, Q, body: str | None, M: float) -> None:
    if body is None:
        return
    b = frame.model.by_name[body]
    if not b.particle:
        Q[b.index + b.size - 1] += M


def mass_diagonal(frame: Frame, model: Model) -> list[float]:
    """The mass matrix, which is diagonal: every body has its own coordinates (x, y with
    m; the angle with I; a pinned body's angle with I about its pin)."""
    d = [0.0] * model.n
    for b in model.bodies:
        i = b.index
        if b.size == 1:
            ax, ay = frame.arm[b.name]
            d[i] = b.inertia + b.mass * (ax * ax + ay * ay)
            continue
        d[i] = d[i + 1] = b.mass
        if b.size == 3:
            d[i + 2] = b.inertia if b.inertia > 0 else 1.0  # a massless-inertia body: no moment
    return d

