"""The impulse path of one planar contact with Coulomb friction, in closed form.

In: W, the 2x2 symmetric positive definite inverse-mass (Delassus) matrix of the
contact in (t, n) coordinates; v0 = (v_t, v_n), the relative velocity before the
impact (v_n < 0: approaching); e; mu (None: smooth, inf: rough); a law.
Out: an `ImpactResult`: total impulse, final relative velocity, the phases of the
path (slide / stick / reverse, compression / restitution) and the energy change.

The physics (W. J. Stronge, "Rigid body collisions with friction", Proc. R. Soc.
Lond. A 431 (1990) 169-181; Stronge, "Impact Mechanics", CUP 2000/2018, ch. 5):
during the impact the bodies do not move, only their velocities change, and the
relative velocity at the contact is affine in the contact impulse P = (P_t, P_n),

    v(P) = v0 + W P.                                                       (1)

The normal impulse P_n grows monotonically and is the path parameter. Coulomb's
law on the increments: while the contact slips (s = sign v_t != 0),
dP_t = -mu s dP_n (slide); when v_t = 0 it sticks (dv_t = 0, so
dP_t/dP_n = -W_tn/W_tt) if that ratio lies in the cone, |W_tn/W_tt| <= mu, else it
slides again in the direction s' = sign(W_tn) that Coulomb's law makes consistent
(dv_t/dP_n = W_tn - mu s' W_tt has the sign s' only then): the slip reverses. On each
piece v is linear in P_n, so the whole path is piecewise linear and exact.

Compression ends at P_c, where v_n = 0. Restitution ends by the law:
  * Poisson (kinetic):      P_n,final = (1 + e) P_c;
  * Stronge (energetic):    the work of the normal impulse in restitution is e^2 times
                            (minus) its work in compression, W_n = int v_n dP_n;
  * Newton (kinematic):     v_n,final = -e v_n0 with the total impulse obeying the
                            algebraic friction law: stick (v_t,final = 0) if
                            |P_t| <= mu P_n, else sliding P_t = -mu s P_n (the system the
                            textbooks write, and what `momentum` compiles for `newton`).

The kinetic energy change is the work of the contact impulse on the relative
velocity, dT = v . dP (the bodies' other impulses are workless), which for (1) with W
symmetric is exact on every linear piece as dP . (v_start + v_end)/2, and in total
T_after - T_before = P . v0 + P . W P / 2 whatever the path (a check used in tests).
It splits into the normal work int v_n dP_n and the tangential work int v_t dP_t; the
latter is <= 0 on a Coulomb path (v_t dP_t = -mu |v_t| dP_n sliding, 0 sticking), and
under the energetic law the former is (1 - e^2) W_c <= 0: Stronge's law never gains
energy. Newton's algebraic friction impulse has no path: it can point along the initial
slip and do positive work (Kane and Levinson, "Dynamics: Theory and Applications", 1985).
"""
from __future__ import annotations

import math

from ..records import record

LAWS = ("newton", "poisson", "energetic")
INF = math.inf


@record(frozen=True)
class Phase:
    """One linear piece of the impulse path (a `stop` piece has P_n constant)."""

    regime: str  # smooth | slide | stick | reverse | stop (rough: slip stopped at once)
    slip: int  # the sign of the slip the friction opposes (0: none)
    stage: str  # compression | restitution | newton (the algebraic law has no path)
    pn: tuple[float, float]
    pt: tuple[float, float]
    v_start: tuple[float, float]
    v_end: tuple[float, float]

    @property
    def energy(self) -> float:
        """The kinetic energy change over this piece, dP . (v_start + v_end) / 2."""
        dpt, dpn = self.pt[1] - self.pt[0], self.pn[1] - self.pn[0]
        return 0.5 * (dpt * (self.v_start[0] + self.v_end[0]) +
                      dpn * (self.v_start[1] + self.v_end[1]))

    @property
    def normal_work(self) -> float:
        """The work of the normal impulse over this piece, int v_n dP_n."""
        return 0.5 * (self.pn[1] - self.pn[0]) * (self.v_start[1] + self.v_end[1])


@record(frozen=True)
class ImpactResult:
    law: str
    e: float
    mu: float | None
    impulse: tuple[float, float]  # (P_t, P_n), the total contact impulse on the first body
    velocity: tuple[float, float]  # (v_t, v_n) after the impact
    phases: tuple  # of Phase, in path order
    compression_end: float | None  # P_c (None for Newton's algebraic law)
    energy_change: float  # T_after - T_before
    gains_energy: bool
    work_compression: float | None  # int_0^Pc v_n dP_n (<= 0)
    work_restitution: float | None  # int_Pc^Pf v_n dP_n
    locked: bool = False  # stuck with det W = 0: restitution cannot separate the contact

    def regimes(self) -> list[str]:
        """The phases in order, merged where one regime spans compression's end."""
        out: list[str] = []
        for p in self.phases:
            if not out or out[-1] != p.regime:
                out.append(p.regime)
        return out


def delassus(bodies, normal: tuple[float, float]) -> tuple[tuple[float, float],
                                                           tuple[float, float]]:
    """W in (t, n) for free rigid bodies: `bodies` lists (m, I, r) for the first body
    and, if any, the second (I None or inf: a particle; r = contact point - G).

    An impulse P at r changes v_G by P/m and omega by (r x P)/I, so the contact
    point's velocity changes by P/m + (r x P)/I (k x r): per body
    W = (1/m) 1 + (1/I) q q^T with q = k x r, whose (t, n) components are
    (r_n, -r_t) for t = (-n_y, n_x). The relative velocity of two bodies adds both
    (the second takes -P). Returned as ((W_tt, W_tn), (W_nt, W_nn)).
    """
    n = normal
    t = (-n[1], n[0])
    wtt = wtn = wnn = 0.0
    for m, inertia, r in bodies:
        wtt += 1.0 / m
        wnn += 1.0 / m
        if inertia is None or math.isinf(inertia) or r is None:
            continue
        rt = r[0] * t[0] + r[1] * t[1]
        rn = r[0] * n[0] + r[1] * n[1]
        wtt += rn * rn / inertia
        wtn += -rn * rt / inertia
        wnn += rt * rt / inertia
    return ((wtt, wtn), (wtn, wnn))


def resolve(W, v0, e: float, mu: float | None, law: str = "newton") -> ImpactResult:
    """The impact at one contact by `law` (newton | poisson | energetic).

    W may be singular (rank 1: the contact point has one degree of freedom, a pendulum
    or a pinned rod): its velocity is then parallel to a fixed q, the slip stops when
    v = 0, and if the stick ratio is inside the cone the contact locks (no restitution;
    `locked`). Raises ValueError if W is not symmetric positive semi-definite with
    W_nn > 0, the contact is not approaching (v_n0 >= 0), or e is outside [0, 1].
    """
    a, b, c = float(W[0][0]), float(W[0][1]), float(W[1][1])
    if abs(float(W[1][0]) - b) > 1e-9 * max(abs(a), abs(c)):
        raise ValueError("W must be symmetric")
    if not c > 0:
        raise ValueError("W_nn must be positive (a normal impulse must change v_n)")
    if mu is not None and not (a >= 0 and a * c - b * b >= -1e-12 * max(a * c, b * b)):
        raise ValueError("W must be positive semi-definite")
    vt0, vn0 = float(v0[0]), float(v0[1])
    if not vn0 < 0:
        raise ValueError("the contact is not approaching (v_n >= 0)")
    if not 0.0 <= e <= 1.0:
        raise ValueError("e must be between 0 and 1")
    if mu is not None and mu < 0:
        raise ValueError("mu must be >= 0")
    if law == "newton":
        return _newton(a, b, c, vt0, vn0, e, mu)
    if law not in LAWS:
        raise ValueError(f"unknown law {law!r}")
    return _path_law(a, b, c, vt0, vn0, e, mu, law)


# ---- Newton's algebraic law -------------------------------------------------------------------
def _newton(a, b, c, vt0, vn0, e, mu) -> ImpactResult:
    """v_n,final = -e v_n0; stick assumed (v_t,final = 0), sliding if |P_t| > mu P_n."""
    regime, slip = "stick", 0
    if mu is None:
        pt, pn = 0.0, -(1 + e) * vn0 / c
        regime = "smooth"
    else:
        det = a * c - b * b
        if det <= 1e-12 * a * c:
            raise ValueError("Newton's law with friction needs det W > 0 (here the contact "
                             "point has one degree of freedom)")
        rt, rn = -vt0, -e * vn0 - vn0  # W P = v_final - v0 with v_final = (0, -e vn0)
        pt, pn = (c * rt - b * rn) / det, (a * rn - b * rt) / det
        if not math.isinf(mu) and abs(pt) > mu * pn * (1 + 1e-12):
            slip = -1 if pt > 0 else 1  # friction opposes the slip: P_t = -mu s P_n
            k = -mu * slip
            den = c + b * k
            if den <= 0:
                raise ValueError("Newton's law with sliding friction has no compressive "
                                 "solution here (c - mu s W_tn <= 0)")
            pn = -(1 + e) * vn0 / den
            pt = k * pn
            regime = "slide"
    vt, vn = vt0 + a * pt + b * pn, vn0 + b * pt + c * pn
    ph = Phase(regime, slip, "newton", (0.0, pn), (0.0, pt), (vt0, vn0), (vt, vn))
    return _result("newton", e, mu, (pt, pn), (vt, vn), [ph], None, (vt0, vn0), a, b, c)


# ---- Poisson's and Stronge's laws: the impulse path -------------------------------------------
@record
class _Segment:
    regime: str
    slip: int
    p0: float  # P_n at its start
    length: float  # in P_n (inf: the last one); 0 with jump != 0
    pt0: float
    v: tuple[float, float]  # at its start
    k: float  # dP_t/dP_n
    dv: tuple[float, float]  # dv/dP_n
    jump: float = 0.0  # a `stop` segment: the tangential impulse applied at once


def _segments(a, b, c, vt0, vn0, mu) -> list[_Segment]:
    """The path as linear pieces in P_n, ending with an unbounded one."""
    tol = 1e-14 * (abs(vt0) + abs(vn0))
    segs: list[_Segment] = []
    p, pt, vt, vn = 0.0, 0.0, vt0, vn0

    def piece(regime, slip, k, length, dv=None):
        dv = dv or (a * k + b, b * k + c)
        segs.append(_Segment(regime, slip, p, length, pt, (vt, vn), k, dv))

    if mu is None:
        piece("smooth", 0, 0.0, INF)
        return segs
    if math.isinf(mu) and abs(vt) > tol:
        # rough: an unbounded friction stops the slip at once (the limit mu -> inf of a
        # slide over P_n -> 0 with P_t -> -v_t/W_tt)
        j = -vt / a
        segs.append(_Segment("stop", 1 if vt > 0 else -1, p, 0.0, pt, (vt, vn), 0.0, (0.0, 0.0),
                             j))
        pt, vt, vn = pt + j, 0.0, vn + b * j
    slid = False
    if abs(vt) > tol:
        s = 1 if vt > 0 else -1
        k = -mu * s
        dvt = a * k + b
        if s * dvt < 0:  # the slip halts
            length = -vt / dvt
            piece("slide", s, k, length)
            p, pt = p + length, pt + k * length
            vn = vn + (b * k + c) * length
            vt = 0.0
            slid = True
        else:
            piece("slide", s, k, INF)
            return segs
    if math.isinf(mu) or abs(b) <= mu * a:
        # sticking: dv_t = 0 and dv_n/dP_n = det W / W_tt (0 for a singular W: it locks)
        det = a * c - b * b
        det = 0.0 if det <= 1e-12 * a * c else det
        piece("stick", 0, -b / a if a > 0 else 0.0, INF,
              (0.0, det / a if a > 0 else c))
    else:
        s = 1 if b > 0 else -1
        piece("reverse" if slid else "slide", s, -mu * s, INF)
    return segs


def _path_law(a, b, c, vt0, vn0, e, mu, law) -> ImpactResult:
    segs = _segments(a, b, c, vt0, vn0, mu)
    # compression ends where v_n first reaches 0 (rising)
    pc = None
    zero = 1e-12 * (abs(vt0) + abs(vn0))  # v_n this small is 0 (a singular W stops at v = 0)
    for sg in segs:
        vn, g = sg.v[1], sg.dv[1]
        if sg.jump:
            if sg.v[1] + b * sg.jump >= -zero:
                pc = sg.p0
                break
            continue
        if vn >= -zero:
            pc = sg.p0
            break
        if g > 0 and vn + g * sg.length >= 0:
            pc = sg.p0 - vn / g
            break
    if pc is None:
        raise ValueError("compression does not end: with a singular W, v0 must be along "
                         "the one direction the contact point can move")
    wc = sum(ph.normal_work for ph in _clip(segs, 0.0, pc, "compression", a, b))
    if law == "poisson":
        pf = (1 + e) * pc
    else:
        pf = _energetic_end(segs, pc, e * e * abs(wc), zero)
    phases = _clip(segs, 0.0, pc, "compression", a, b) + _clip(segs, pc, pf, "restitution", a, b)
    last = phases[-1]
    pt = last.pt[1]
    vt, vn = vt0 + a * pt + b * pf, vn0 + b * pt + c * pf
    end = segs[-1]
    locked = pf >= end.p0 and end.dv == (0.0, 0.0) and e > 0
    return _result(law, e, mu, (pt, pf), (vt, vn), phases, pc, (vt0, vn0), a, b, c,
                   wc, sum(ph.normal_work for ph in phases if ph.stage == "restitution"), locked)


def _energetic_end(segs, pc: float, target: float, zero: float) -> float:
    """The P_n where int_Pc^P v_n dP_n reaches `target` (Stronge's energetic law)."""
    left = target
    for sg in segs:
        if sg.jump or sg.p0 + sg.length <= pc:
            continue
        start = max(sg.p0, pc)
        vn = sg.v[1] + sg.dv[1] * (start - sg.p0)
        vn = 0.0 if abs(vn) <= zero else vn
        g = sg.dv[1]
        length = sg.p0 + sg.length - start
        if left <= 0:
            return start
        if math.isfinite(length):
            full = vn * length + 0.5 * g * length * length
        elif g > 0 or vn > 0:
            full = INF
        else:
            return start  # locked (a singular W sticking at v = 0): no restitution work
        if full >= left:
            # g x^2 / 2 + vn x - left = 0, the root where the work first reaches `left`,
            # written without cancellation
            root = math.sqrt(max(vn * vn + 2 * g * left, 0.0))
            if vn > 0 or (vn == 0 and g <= 0):
                x = 2 * left / (vn + root) if vn + root > 0 else 0.0
            else:  # v_n ~ 0 (round-off below it) and rising: g > 0
                x = (root - vn) / g
            return start + x
        left -= full
    raise AssertionError("the last segment's work is unbounded")


def _clip(segs, lo: float, hi: float, stage: str, a: float, b: float) -> list[Phase]:
    """The path's pieces between P_n = lo and hi, as phases."""
    out = []
    for sg in segs:
        if sg.jump:
            if stage == "compression":  # a stop is at P_n = 0, always in compression
                v1 = (sg.v[0] + a * sg.jump, sg.v[1] + b * sg.jump)
                out.append(Phase("stop", sg.slip, stage, (lo, lo), (sg.pt0, sg.pt0 + sg.jump),
                                 sg.v, v1))
            continue
        s0, s1 = max(sg.p0, lo), min(sg.p0 + sg.length, hi)
        if s1 <= s0:
            continue

        def at(p, sg=sg):
            x = p - sg.p0
            return sg.pt0 + sg.k * x, (sg.v[0] + sg.dv[0] * x, sg.v[1] + sg.dv[1] * x)

        pt0, v0 = at(s0)
        pt1, v1 = at(s1)
        out.append(Phase(sg.regime, sg.slip, stage, (s0, s1), (pt0, pt1), v0, v1))
    return out


def _result(law, e, mu, P, v, phases, pc, v0, a, b, c, wc=None, wr=None,
            locked=False) -> ImpactResult:
    dT = sum(ph.energy for ph in phases)
    pt, pn = P
    scale = (abs(pt * v0[0]) + abs(pn * v0[1]) +
             0.5 * (a * pt * pt + 2 * abs(b * pt * pn) + c * pn * pn))
    return ImpactResult(law, e, mu, P, v, tuple(phases), pc, dT, dT > 1e-12 * scale, wc, wr,
                        locked)
