"""Constraint drift: joints and persistent contacts held to a stated tolerance.

Integrating accelerations keeps the constraints only to the integrator's accuracy.
An event fires when the largest violation (a pin's gap, a weld's angle, a link's
stretch, a resting contact's gap) exceeds `tolerance(rtol)` of the scene's size
(the integration tolerance, and never looser than FIXED_STEP_DRIFT with fixed steps);
positions are then projected back (Gauss-Newton, mass-weighted), velocities with them.
"""
from __future__ import annotations

import numpy as np

from .dynamics import Frame, contact_geometry, mass_diagonal, normal_row, tangent_row
from .events import Event
from .forces import Phase, joint_rows
from ..elements.kinds import Regime
from .model import Model

FLOOR = 1e-9  # the tightest drift tolerance, of the length scale
FIXED_STEP_DRIFT = 1e-6  # with --dt, which has no rtol


def tolerance(rtol: float | None) -> float:
    """The drift allowed, as a fraction of the length scale."""
    return FIXED_STEP_DRIFT if rtol is None else max(FLOOR, rtol)


def reference(model: Model, frame: Frame) -> dict:
    """What each weld's angle and each link's length along its line are at the start."""
    ref = {}
    for j in model.joints:
        r = j.sim_reference(frame)
        if r is not None:
            ref[j.label] = r
    return ref


def residuals(model: Model, phase: Phase, frame: Frame, ref: dict) -> list[float]:
    """Position constraint values, in the order of `rows` (lengths, and angles times the
    length scale)."""
    out = []
    L = model.length_scale
    for j in model.joints:
        out += j.sim_residuals(frame, ref, L)
    for w in model.watches:
        if w.label in phase.contacts:
            out.append(contact_geometry(frame, w)[0])
    return out


def rows(model: Model, phase: Phase, frame: Frame, velocity: bool = False) -> list:
    """Jacobian rows of `residuals` (angles scaled by L); with `velocity`, also the
    rolling contacts' tangential rows (a velocity constraint only)."""
    L = model.length_scale
    out = []
    for r in joint_rows(frame, model):
        out.append(r.row * L if r.angular else r.row)
    for w in model.watches:
        mode = phase.contacts.get(w.label)
        if mode is None:
            continue
        geo = contact_geometry(frame, w)
        out.append(normal_row(frame, w, geo)[0])
    if velocity:
        for w in model.watches:
            if phase.contacts.get(w.label) == Regime.STICK:
                out.append(tangent_row(frame, w, contact_geometry(frame, w))[0])
    return out


def _correct(A: np.ndarray, r: np.ndarray, minv: np.ndarray) -> np.ndarray | None:
    Minv_At = A.T * minv[:, None]
    try:
        return Minv_At @ np.linalg.lstsq(A @ Minv_At, r, rcond=None)[0]
    except np.linalg.LinAlgError:
        return None


def project(model: Model, phase: Phase, y: np.ndarray, ref: dict,
            drift: float) -> tuple[float, float]:
    """Project positions, then velocities, onto the constraints (in place); return the
    largest position violation before and after (after: what double precision allows
    at these coordinates, at best)."""
    n = model.n
    frame = Frame(model, y[:n], y[n:2 * n])
    worst = max((abs(c) for c in residuals(model, phase, frame, ref)), default=0.0)
    tol = 1e-3 * drift * model.length_scale
    for _ in range(5):
        c = np.array(residuals(model, phase, frame, ref))
        if not c.size or np.max(np.abs(c)) <= tol:
            break
        minv = 1.0 / np.array(mass_diagonal(frame, model))
        dq = _correct(np.array(rows(model, phase, frame)), c, minv)
        if dq is None:
            break
        y[:n] -= dq
        frame = Frame(model, y[:n], y[n:2 * n])
    after = max((abs(c) for c in residuals(model, phase, frame, ref)), default=0.0)
    A = rows(model, phase, frame, velocity=True)
    if A:
        A = np.array(A)
        r = A @ y[n:2 * n]
        if np.any(r):
            minv = 1.0 / np.array(mass_diagonal(frame, model))
            du = _correct(A, r, minv)
            if du is not None:
                y[n:2 * n] -= du
    return worst, after


def drift_event(model: Model, phase: Phase, ref: dict, drift: float) -> Event | None:
    if not model.joints and not phase.contacts:
        return None
    tol = drift * model.length_scale

    def fn(frame, _):
        return max((abs(c) for c in residuals(model, phase, frame, ref)), default=0.0) - tol

    # in a closed-form phase the constraints' rows are constant and hold exactly
    return Event("drift", "constraints", fn, 1, poly=lambda frame, udot: (-1.0, 0.0, 0.0))
