"""The physical pendulum in closed form: a body turning about a fixed pin under gravity.

With phi the angle of G - O from the downward vertical, I_O phi'' = -m g d sin(phi).
Its energy gives the modulus k^2 = sin^2(phi/2) + phi'^2 / (4 w0^2), w0^2 = m g d / I_O;
then, with Jacobi's elliptic functions (parameter m = k^2):
    swinging (k < 1):  sin(phi/2) = k sn(w0 t + u0 | k^2),  phi' = 2 k w0 cn(w0 t + u0 | k^2)
    turning over (k > 1):  phi/2 = s am(k w0 t + u0 | 1/k^2),  phi' = 2 s k w0 dn(...)
so a swing between impacts needs no integration at all (elliptic.py computes them).
"""
from __future__ import annotations

import math

import numpy as np

from .model import Model


class PendulumFlow:
    """The motion of every pinned body of a phase in which gravity alone acts on them."""

    def __init__(self, model: Model, y0: np.ndarray):
        from .elliptic import ellipj, ellipk, ellipkinc

        self.model, self.y0, self.n = model, y0.copy(), model.n
        self.ellipj = ellipj
        g = model.gravity
        gn = math.hypot(*g)
        down = math.atan2(g[1], g[0])
        self.parts = []
        self.period = math.inf  # the longest time for any body to repeat its motion
        for b in model.bodies:
            i = b.index
            th0, w = float(y0[i]), float(y0[self.n + i])
            px, py = b.pin_offset
            d = math.hypot(px, py)
            I_O = b.inertia + b.mass * d * d
            beta = math.atan2(-py, -px)  # the arm G - O in the body frame
            w0 = math.sqrt(b.mass * gn * d / I_O) if d > 0 else 0.0
            phi0 = math.remainder(th0 + beta - down, 2 * math.pi)
            part = {"i": i, "th0": th0, "shift": down - beta, "w0": w0, "w": w, "phi0": phi0}
            if w0 == 0:
                part["kind"] = "uniform"
                self.period = min(self.period, math.inf)
            else:
                k2 = math.sin(phi0 / 2) ** 2 + w * w / (4 * w0 * w0)
                if k2 == 0:
                    part["kind"] = "rest"
                elif k2 < 1:
                    k = math.sqrt(k2)
                    s = max(-1.0, min(1.0, math.sin(phi0 / 2) / k))
                    u = ellipkinc(math.asin(s), k2)
                    if w < 0:  # cn < 0: past the quarter period
                        u = 2 * ellipk(k2) - u
                    part.update(kind="swing", k=k, m=k2, u0=u)
                    self.period = 4 * ellipk(k2) / w0
                elif k2 > 1:
                    k = math.sqrt(k2)
                    sgn = 1.0 if w > 0 else -1.0
                    m = 1 / k2
                    u = ellipkinc(sgn * phi0 / 2, m)
                    part.update(kind="turn", k=k, m=m, u0=u, sign=sgn)
                    self.period = 2 * ellipk(m) / (k * w0)
                else:
                    raise ValueError("on the separatrix")
            self.parts.append(part)

    @staticmethod
    def applies(model: Model, phase) -> bool:
        """Every body pinned to the ground, and gravity the only thing acting on them."""
        return (model.gravity is not None and all(b.size == 1 for b in model.bodies)
                and not (model.joints or model.springs or model.dampers or model.forces or
                         model.moments or model.bearings or phase.contacts))

    def state(self, t: float) -> np.ndarray:
        """The state t after the phase began."""
        y = self.y0.copy()
        if t == 0:
            return y
        n = self.n
        for p in self.parts:
            i = p["i"]
            if p["kind"] == "rest":
                continue
            if p["kind"] == "uniform":
                y[i] = p["th0"] + p["w"] * t
                continue
            if p["kind"] == "swing":
                sn, cn, dn, _ = self.ellipj(p["w0"] * t + p["u0"], p["m"])
                phi = 2 * math.asin(max(-1.0, min(1.0, p["k"] * sn)))
                dphi = 2 * p["k"] * p["w0"] * cn
            else:
                sn, cn, dn, am = self.ellipj(p["k"] * p["w0"] * t + p["u0"], p["m"])
                phi = 2 * p["sign"] * am
                dphi = 2 * p["sign"] * p["k"] * p["w0"] * dn
            # continuous angle: phi0 maps to th0, and phi changes by at most pi per half swing
            y[i] = p["th0"] + (phi - p["phi0"])
            y[n + i] = dphi
        return y
