"""Contact geometry shared by solve and simulate: where a point is, and the normal the
shapes fix (the line of centres of two round bodies, or a round body's centre to the
point it touches). In: poses {body: (x, y, angle)} and PointOn; out: points and normals.
"""
from __future__ import annotations

import math

from ..expr import hypot


def rot(theta: float, r: tuple[float, float]) -> tuple[float, float]:
    c, s = math.cos(theta), math.sin(theta)
    return (c * r[0] - s * r[1], s * r[0] + c * r[1])


def centre(frame_pose, p) -> tuple[float, float]:
    """World position of point `p` from poses {body: (x, y, angle)}."""
    if p.body is None:
        return (p.offset[0], p.offset[1])
    gx, gy, th = frame_pose[p.body]
    rx, ry = rot(th, p.offset)
    return (gx + rx, gy + ry)


def line_of_centres(pa: tuple[float, float], pb: tuple[float, float]):
    """(unit normal on a, distance) from b's centre (or point) to a's: the normal of two
    round bodies, or of a round body and a point it touches. None for coincident points."""
    dx, dy = pa[0] - pb[0], pa[1] - pb[1]
    d = hypot(dx, dy)  # math.hypot, also for a sweep's traced numbers
    if d == 0 or not math.isfinite(d):
        return None, d
    return (dx / d, dy / d), d
