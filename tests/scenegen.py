"""Random impact scenes as problem TEXT, and an independent dense solve of each.

Stage: test support. In: a seed (and which categories to draw). Out: a `Scene`
(bodies, contacts, joints, redundant true statements), its rendering in the problem
language, and `dense_solve(scene)`: the impact equations assembled here with numpy
from the generated parameters (Newton-Euler impulse equations per body, Newton's
restitution, the tangential laws, joint constraints), independent of momentum's
compiler. `run_one` solves the text through the real pipeline and compares.

Every scene is well-posed by construction: the impact system has full rank, every
contact is closing, a friction contact slips before the impact and exactly one
stick/slide combination satisfies Coulomb's law (stick inside the cone, a sliding
contact's slip not reversed), joints form a forest with the ground (no closed loop).

Run `python tests/scenegen.py --count 10000 --shrink 2` for the large run with the
failures shrunk (`--gated NAME` opens a gate below); the CI test is tests/test_generated.py.
"""
from __future__ import annotations

import argparse
import itertools
import math
import random
import sys
import time
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

# Gates: scene features that fail on the current main for a reason another branch fixes.
# A gated feature is never drawn in the CI budget; tests/test_generated.py runs it as an
# expected failure (strict: when the fix lands the test XPASSes and fails, so the gate is
# flipped, not forgotten). Flip a gate after merging the branch that fixes it.
#
# Joints that form in the impact (`pin a to b from 2` with `impact 1 -> 2`) must exert an
# impulse in it (issue 9, reproduction 3; the compile.py element refactor fixes it).
FORMING_JOINTS_FIXED = True
# A true redundant statement (or `equation`) in a scene whose friction regime must switch
# from the first assumption (stick) is refused "inconsistent": solve.py checks redundant
# equations in the first regime round and raises before the regimes settle.
REGIME_CHECK_FIXED = True
# Several friction contacts in one impact (or friction with `restitution ?`): the regimes
# that stick-first iteration settles on are re-checked against Coulomb's law (no slip
# reversal, J_n >= 0, a found e in [0, 1]); when they break it, every stick/slide
# combination is tried (momentum_cli/regime_search.py). With `restitution ?` the program
# always tries every combination, so an unknown_e scene is drawn only when its stated
# quantity admits one regime with e in [0, 1] (`_e_regimes`), else it is ambiguous.
SLIDE_SIGN_FIXED = True

# `equation Q = value` true to round-off is refused "inconsistent": a true 0 written as
# the dense solve's 1e-17 m/s, a value off by 3e-14 relative (the float dense solve's
# round-off, or an angular statement true only to the round-off of the positions), since
# the check's tolerance scales with the residual's own terms, not the problem's quantities
# (issue 9, reproduction 2; solve.py's checks fix it). Until then values are solved
# exactly, a round-off 0 is written as 0, and no `equation` stands beside an angular one.
CHECK_TOLERANCE_FIXED = True
# `restitution ?` together with a redundant stated principle (`conserve momentum ...`):
# the structural matching takes the stated row and leaves a numerically singular block
# ("rank-deficient" / "singular in float64") (issue 9, "structure and numbers agree";
# analyse.py / solve.py numerics fix it).
STRUCTURE_RANK_FIXED = True

FEW_ULPS = 16 * 2.0 ** -53  # a float value written for a true one is off by at most this

# the gates by name: fixed (True) or not
GATES = {"forming": FORMING_JOINTS_FIXED, "regime_check": REGIME_CHECK_FIXED,
         "slide_sign": SLIDE_SIGN_FIXED, "check_tolerance": CHECK_TOLERANCE_FIXED,
         "structure_rank": STRUCTURE_RANK_FIXED}
CATEGORIES = ("free", "ground", "joints", "friction", "unknown_e", "redundant", "pendulum",
              "forming", "friction_stated", "friction_multi")
# categories that exist only to exercise one gate (drawn only when it is open)
GATED = {"forming": "forming", "friction_stated": "regime_check",
         "friction_multi": "slide_sign"}


def opened(gated) -> frozenset:
    """The gates open for a draw: the fixed ones, plus those asked for (True: all)."""
    asked = set(GATES) if gated is True else set(gated or ())
    return frozenset(g for g, fixed in GATES.items() if fixed or g in asked)


def categories(gated=False) -> list[str]:
    op = opened(gated)
    return [c for c in CATEGORIES if c not in GATED or GATED[c] in op]

NAMES = ("alpha", "bravo", "cart", "dolly", "echo", "fox", "hub", "ink", "jet", "kilo",
         "lima", "mike", "nova", "oak", "puck", "quill", "zed", "arm", "beam", "cog")
KINDS = ("particle", "rod", "disk", "sphere", "plate", "rigid")

REL_TOL = 1e-8      # answers against the dense solve, relative to the scene's scale
LAW_TOL = 1e-9      # conservation laws, relative to the momentum / energy scale


# ---- the scene model ---------------------------------------------------------------------------

@dataclass
class Body:
    name: str
    kind: str
    mass: float
    dims: tuple = ()           # rod (L,), disk/sphere (r,), plate (w, h), rigid (I,)
    angle: float = 0.0
    pos: tuple = (0.0, 0.0)
    v1: tuple = (0.0, 0.0, 0.0)  # vx, vy, omega before the impact (consistent with joints)

    @property
    def particle(self) -> bool:
        return self.kind == "particle"

    @property
    def inertia(self) -> float:
        m, d, k = self.mass, self.dims, self.kind
        if k == "rod":
            return m * d[0] ** 2 / 12
        if k == "disk":
            return m * d[0] ** 2 / 2
        if k == "sphere":
            return 2 * m * d[0] ** 2 / 5
        if k == "plate":
            return m * (d[0] ** 2 + d[1] ** 2) / 12
        if k == "rigid":
            return d[0]
        return 0.0

    @property
    def radius(self) -> float | None:
        return self.dims[0] if self.kind in ("disk", "sphere") else None

    @property
    def ndof(self) -> int:
        return 2 if self.particle else 3


@dataclass
class Pt:
    """A point of a body: `offset` from G in the body frame; `round`: the rim (G - r n)."""
    body: str | None
    offset: tuple = (0.0, 0.0)
    ref: str = ""              # how the file names it
    decl: str | None = None    # its `point` line, if it needs one
    round: bool = False


@dataclass
class Contact:
    label: str
    a: Pt
    b: Pt | None               # None: the ground or a surface
    normal: tuple              # the impulse direction on a (unit)
    nint: tuple                # the normal as written (integers)
    e: float
    e_unknown: bool = False
    mode: str = "smooth"       # smooth | rough | friction
    mu: float = 0.0
    surface: str | None = None  # a declared surface instead of `ground normal (..)`


@dataclass
class Joint:
    kind: str                  # pin | weld | link
    label: str
    a: Pt
    b: Pt | None               # None: the ground
    along: tuple = (1.0, 0.0)
    aint: tuple = (1, 0)
    ground_at: tuple = (0.0, 0.0)
    forming: bool = False      # `from 2`: holds only after the impact


@dataclass
class Scene:
    seed: int
    category: str
    bodies: list
    contacts: list
    joints: list
    statements: list = field(default_factory=list)  # ("momentum", set, dir) | ("angular", set, Pt) | ("equation", qty)
    e_given: dict = field(default_factory=dict)     # label of a `?` contact -> the quantity given
    open: frozenset = frozenset()                   # the gates open when it was drawn


# ---- kinematics shared by the generator and the dense solve ------------------------------------

def rot(v, th):
    c, s = math.cos(th), math.sin(th)
    return (c * v[0] - s * v[1], s * v[0] + c * v[1])


def cross(a, b):
    return a[0] * b[1] - a[1] * b[0]


def arm(body: Body, p: Pt, n=None, sign=1.0):
    """World vector from G to the point (a round body's rim is -sign r n)."""
    if p.round and body.radius is not None and n is not None:
        return (-sign * body.radius * n[0], -sign * body.radius * n[1])
    if body.particle:
        return (0.0, 0.0)
    return rot(p.offset, body.angle)


def point_vel_row(scene: Scene, p: Pt | None, idx, n=None, sign=1.0):
    """Coefficients {column: (cx, cy)} of a point's velocity in the body's columns."""
    if p is None or p.body is None:
        return {}
    b = bodymap(scene)[p.body]
    r = arm(b, p, n, sign)
    cols = {idx[(b.name, 0)]: (1.0, 0.0), idx[(b.name, 1)]: (0.0, 1.0)}
    if not b.particle:
        cols[idx[(b.name, 2)]] = (-r[1], r[0])
    return cols


def bodymap(scene: Scene) -> dict:
    return {b.name: b for b in scene.bodies}


def point_vel1(scene: Scene, p: Pt | None, n=None, sign=1.0):
    if p is None or p.body is None:
        return (0.0, 0.0)
    b = bodymap(scene)[p.body]
    r = arm(b, p, n, sign)
    w = b.v1[2] if not b.particle else 0.0
    return (b.v1[0] - w * r[1], b.v1[1] + w * r[0])


def point_world(scene: Scene, p: Pt | None, n=None, sign=1.0):
    if p is None or p.body is None:
        return None
    b = bodymap(scene)[p.body]
    r = arm(b, p, n, sign)
    return (b.pos[0] + r[0], b.pos[1] + r[1])


# ---- the independent dense solve ----------------------------------------------------------------

@dataclass
class Dense:
    v2: dict          # (body, 'vx'|'vy'|'omega') -> value
    impulses: dict    # answer name -> value
    regimes: dict     # contact label -> stick | slide
    pull: list        # labels of contacts with J_n < 0
    rank_ok: bool
    cond: float


def _velocity_columns(scene: Scene):
    idx, k = {}, 0
    for b in scene.bodies:
        for c in range(b.ndof):
            idx[(b.name, c)] = k
            k += 1
    return idx, k


def joint_rows(scene: Scene, joints, idx, ncols):
    """Velocity constraint rows of joints: pin/weld points together, weld turns, link along."""
    rows = []
    bm = bodymap(scene)
    for jt in joints:
        ca = point_vel_row(scene, jt.a, idx)
        cb = point_vel_row(scene, jt.b, idx)
        dirs = [(1.0, 0.0), (0.0, 1.0)] if jt.kind in ("pin", "weld") else [jt.along]
        for d in dirs:
            row = np.zeros(ncols)
            for col, (cx, cy) in ca.items():
                row[col] += cx * d[0] + cy * d[1]
            for col, (cx, cy) in cb.items():
                row[col] -= cx * d[0] + cy * d[1]
            rows.append(row)
        if jt.kind == "weld" and not _has_particle(jt, bm):
            row = np.zeros(ncols)
            row[idx[(jt.a.body, 2)]] = 1.0
            if jt.b is not None and jt.b.body is not None:
                row[idx[(jt.b.body, 2)]] -= 1.0
            rows.append(row)
    return rows


def _has_particle(jt: Joint, bm) -> bool:
    return any(p is not None and p.body is not None and bm[p.body].particle for p in (jt.a, jt.b))


def _impact_system(scene: Scene, regimes: dict):
    """A x = rhs over [state-2 velocities, impulses]; names of the impulse columns."""
    bm = bodymap(scene)
    idx, nv = _velocity_columns(scene)
    imp = []  # (name, body-effects [(pt, dir or None for moment, n, sign, factor)])
    for c in scene.contacts:
        n = c.normal
        t = (-n[1], n[0])
        imp.append((f"J_n[{c.label}]@1->2", c, n, "n"))
        if c.mode != "smooth":
            imp.append((f"J_t[{c.label}]@1->2", c, t, "t"))
    for jt in scene.joints:
        if jt.kind == "link":
            imp.append((f"J[{jt.label}]@1->2", jt, jt.along, "l"))
        else:
            imp.append((f"Jx[{jt.label}]@1->2", jt, (1.0, 0.0), "x"))
            imp.append((f"Jy[{jt.label}]@1->2", jt, (0.0, 1.0), "y"))
            if jt.kind == "weld" and not _has_particle(jt, bm):
                imp.append((f"M[{jt.label}]@1->2", jt, None, "m"))
    names = [x[0] for x in imp]
    ncols = nv + len(imp)
    A_rows, rhs = [], []
    # Newton-Euler per body: m dv = sum J, I dw = sum r x J (+ moments)
    lin = {(b.name, c): np.zeros(ncols) for b in scene.bodies for c in range(b.ndof)}
    for b in scene.bodies:
        for c in range(b.ndof):
            m = b.mass if c < 2 else b.inertia
            lin[(b.name, c)][idx[(b.name, c)]] = m
    for k, (name, el, d, what) in enumerate(imp):
        col = nv + k
        if isinstance(el, Contact):
            sides = [(el.a, 1.0)] + ([(el.b, -1.0)] if el.b is not None else [])
            n = el.normal
        else:
            sides = [(el.a, 1.0)] + ([(el.b, -1.0)] if el.b is not None and el.b.body else [])
            n = None
        for p, sign in sides:
            if p.body is None:
                continue
            b = bm[p.body]
            if d is None:  # a weld's moment
                if not b.particle:
                    lin[(b.name, 2)][col] -= sign
                continue
            r = arm(b, p, n, sign)
            lin[(b.name, 0)][col] -= sign * d[0]
            lin[(b.name, 1)][col] -= sign * d[1]
            if not b.particle:
                lin[(b.name, 2)][col] -= sign * cross(r, d)
    for b in scene.bodies:
        for c in range(b.ndof):
            m = b.mass if c < 2 else b.inertia
            A_rows.append(lin[(b.name, c)])
            rhs.append(m * b.v1[c])
    # contact laws
    for c in scene.contacts:
        n = c.normal
        t = (-n[1], n[0])
        ca = point_vel_row(scene, c.a, idx, n, 1.0)
        cb = point_vel_row(scene, c.b, idx, n, -1.0)
        va, vb = point_vel1(scene, c.a, n, 1.0), point_vel1(scene, c.b, n, -1.0)
        rel1 = (va[0] - vb[0], va[1] - vb[1])
        vn1 = rel1[0] * n[0] + rel1[1] * n[1]
        vt1 = rel1[0] * t[0] + rel1[1] * t[1]

        def vrow(d):
            row = np.zeros(ncols)
            for col, (cx, cy) in ca.items():
                row[col] += cx * d[0] + cy * d[1]
            for col, (cx, cy) in cb.items():
                row[col] -= cx * d[0] + cy * d[1]
            return row
        A_rows.append(vrow(n))
        rhs.append(-c.e * vn1)
        if c.mode == "rough" or (c.mode == "friction" and regimes.get(c.label) == "stick"):
            A_rows.append(vrow(t))
            rhs.append(0.0)
        elif c.mode == "friction":
            row = np.zeros(ncols)
            row[nv + names.index(f"J_t[{c.label}]@1->2")] = 1.0
            row[nv + names.index(f"J_n[{c.label}]@1->2")] = math.copysign(c.mu, vt1)
            A_rows.append(row)
            rhs.append(0.0)
    # joints: constraints after the impact (forming joints included: they hold at state 2)
    for row in joint_rows(scene, scene.joints, idx, ncols):
        A_rows.append(row)
        rhs.append(0.0)
    return np.array(A_rows), np.array(rhs), idx, nv, names


def _regime_solve(scene: Scene, regimes: dict) -> Dense:
    """The impact solved in given stick/slide regimes (rank_ok False: singular)."""
    A, rhs, idx, nv, names = _impact_system(scene, regimes)
    if A.shape[0] != A.shape[1]:
        return Dense({}, {}, regimes, [], False, math.inf)
    cond = np.linalg.cond(A)
    if not math.isfinite(cond) or cond > 1e8:
        return Dense({}, {}, regimes, [], False, cond)
    x = np.linalg.solve(A, rhs)
    v2 = {}
    for b in scene.bodies:
        for c, q in enumerate(("vx", "vy", "omega")[:b.ndof]):
            v2[(b.name, q)] = float(x[idx[(b.name, c)]])
    imps = {nm: float(x[nv + k]) for k, nm in enumerate(names)}
    return Dense(v2, imps, regimes, [c.label for c in scene.contacts
                                     if imps[f"J_n[{c.label}]@1->2"] < 0], True, cond)


def _e_regimes(sc: Scene, c: Contact, q) -> int:
    """How many stick/slide combinations keep Coulomb's law with c's e unknown and found
    from the stated value of q (in [0, 1]): a well-posed `restitution ?` scene has one.
    x is linear in e in a fixed regime, so two solves give e for each regime."""
    fr = [x for x in sc.contacts if x.mode == "friction"]
    e0, target = c.e, dense_solve(sc).v2[q]
    count = 0
    try:
        for combo in itertools.product(("stick", "slide"), repeat=len(fr)):
            regimes = {x.label: r for x, r in zip(fr, combo)}
            c.e = 0.0
            d0 = _regime_solve(sc, regimes)
            c.e = 1.0
            d1 = _regime_solve(sc, regimes)
            if not (d0.rank_ok and d1.rank_ok):
                continue
            slope = d1.v2[q] - d0.v2[q]
            if abs(slope) <= 1e-9 * (1 + abs(target)):
                continue  # e not determined by q in this regime: refused there
            e = (target - d0.v2[q]) / slope
            if not -1e-9 <= e <= 1 + 1e-9:
                continue
            c.e = e
            d = _regime_solve(sc, regimes)
            if d.rank_ok and _coulomb_ok(sc, d):
                count += 1
    finally:
        c.e = e0
    return count


def dense_solve(scene: Scene) -> Dense:
    """Solve the impact with every Coulomb regime combination; keep the admissible one."""
    fr = [c for c in scene.contacts if c.mode == "friction"]
    admissible = []
    last = None
    for combo in itertools.product(("stick", "slide"), repeat=len(fr)):
        d = _regime_solve(scene, {c.label: r for c, r in zip(fr, combo)})
        if not d.rank_ok:
            return d
        last = d
        if _coulomb_ok(scene, d):
            admissible.append(d)
    if len(admissible) != 1:
        if last is not None:
            last.rank_ok = False  # no, or more than one, Coulomb solution: not generated
            return last
        return Dense({}, {}, {}, [], False, math.inf)
    return admissible[0]


def exact_v2(scene: Scene, d: Dense) -> dict:
    """The state-2 velocities of the admissible regime, solved in exact rationals on the
    same float data (the correctly rounded solution: what a true statement states)."""
    from fractions import Fraction

    A, rhs, idx, nv, _names = _impact_system(scene, d.regimes)
    n = len(rhs)
    M = [[Fraction(float(A[i, j])) for j in range(n)] + [Fraction(float(rhs[i]))]
         for i in range(n)]
    for col in range(n):
        piv = max(range(col, n), key=lambda r: abs(M[r][col]))
        M[col], M[piv] = M[piv], M[col]
        p = M[col][col]
        M[col] = [x / p for x in M[col]]
        for r in range(n):
            if r != col and M[r][col]:
                f = M[r][col]
                M[r] = [a - f * b for a, b in zip(M[r], M[col])]
    out = {}
    for b in scene.bodies:
        for c, q in enumerate(("vx", "vy", "omega")[:b.ndof]):
            out[(b.name, q)] = float(M[idx[(b.name, c)]][n])
    return out


def _coulomb_ok(scene: Scene, d: Dense) -> bool:
    scale = 1e-12 * (1 + max((abs(v) for v in d.impulses.values()), default=0))
    for c in scene.contacts:
        if c.mode != "friction":
            continue
        jn, jt = d.impulses[f"J_n[{c.label}]@1->2"], d.impulses[f"J_t[{c.label}]@1->2"]
        if jn < 0:
            return False  # a pulling contact has no Coulomb regime
        if d.regimes[c.label] == "stick":
            if abs(jt) > c.mu * jn + scale:
                return False
        else:
            n = c.normal
            t = (-n[1], n[0])
            vt1 = _rel(scene, c, None, t)
            vt2 = _rel(scene, c, d.v2, t)
            if vt2 * math.copysign(1.0, vt1) < -1e-12 * (abs(vt1) + 1):
                return False  # friction against the slip reversed it: not this regime
    return True


def _rel(scene: Scene, c: Contact, v2, d):
    """Relative velocity of a over b at the contact along d (state 1, or v2's state)."""
    out = 0.0
    for p, sign in ((c.a, 1.0), (c.b, -1.0)):
        if p is None or p.body is None:
            continue
        b = bodymap(scene)[p.body]
        r = arm(b, p, c.normal, sign)
        if v2 is None:
            vx, vy = b.v1[0], b.v1[1]
            w = b.v1[2] if not b.particle else 0.0
        else:
            vx, vy = v2[(b.name, "vx")], v2[(b.name, "vy")]
            w = v2.get((b.name, "omega"), 0.0)
        out += sign * ((vx - w * r[1]) * d[0] + (vy + w * r[0]) * d[1])
    return out


# ---- generation ------------------------------------------------------------------------------------

def _num(rng: random.Random, lo: float, hi: float, digits: int = 3) -> float:
    return float(f"{rng.uniform(lo, hi):.{digits}g}")


def _logu(rng: random.Random, lo: float, hi: float) -> float:
    return float(f"{math.exp(rng.uniform(math.log(lo), math.log(hi))):.3g}")


def _direction(rng: random.Random):
    """A direction written with small integers (axis-aligned a third of the time)."""
    if rng.random() < 0.35:
        a = rng.choice([(1, 0), (0, 1), (-1, 0), (0, -1)])
    else:
        while True:
            a = (rng.randint(-5, 5), rng.randint(-5, 5))
            if a != (0, 0):
                break
    n = math.hypot(*a)
    return a, (a[0] / n, a[1] / n)


def _make_body(rng: random.Random, name: str, kind: str) -> Body:
    m = _logu(rng, 0.2, 10.0)
    dims = {"particle": (), "rod": (_num(rng, 0.3, 2.0, 2),), "disk": (_num(rng, 0.05, 0.5, 2),),
            "sphere": (_num(rng, 0.05, 0.5, 2),),
            "plate": (_num(rng, 0.1, 1.0, 2), _num(rng, 0.1, 1.0, 2)),
            "rigid": (_logu(rng, 0.01, 2.0),)}[kind]
    ang = 0.0 if kind == "particle" else rng.choice([0.0, _num(rng, -3.0, 3.0, 3)])
    return Body(name, kind, m, dims, ang)


class _Points:
    """Named points of the bodies, declared as the file needs them."""

    def __init__(self, rng: random.Random):
        self.rng, self.k = rng, 0

    def on(self, b: Body, for_contact: bool) -> Pt:
        rng = self.rng
        if b.particle:
            return Pt(b.name, (0.0, 0.0), b.name)
        if b.kind in ("disk", "sphere"):
            if for_contact and rng.random() < 0.7:
                # the body, or its centre, at a contact: the rim (G - r n)
                return Pt(b.name, (0.0, 0.0), rng.choice((b.name, f"{b.name}.center")),
                          round=True)
            if rng.random() < 0.5:
                if not for_contact:
                    return Pt(b.name, (0.0, 0.0), rng.choice((b.name, f"{b.name}.center")))
                return self._named(b, (0.0, 0.0))  # a named point at G is not the rim
            r = b.dims[0]
            return self._named(b, (_num(rng, -r, r, 2), _num(rng, -r, r, 2)))
        if b.kind == "rod":
            L = b.dims[0]
            if rng.random() < 0.5:
                s = rng.choice("+-")
                return Pt(b.name, ((L / 2) * (1 if s == "+" else -1), 0.0), f"{b.name}.end({s})")
            return self._named(b, (_num(rng, -L / 2, L / 2, 2), 0.0))
        if b.kind == "plate":
            w, h = b.dims
            if rng.random() < 0.5:
                return self._named(b, (rng.choice([-w / 2, w / 2]), rng.choice([-h / 2, h / 2])))
            return self._named(b, (_num(rng, -w / 2, w / 2, 2), _num(rng, -h / 2, h / 2, 2)))
        return self._named(b, (_num(rng, -0.8, 0.8, 2), _num(rng, -0.8, 0.8, 2)))

    def _named(self, b: Body, off) -> Pt:
        self.k += 1
        nm = f"P{self.k}"
        return Pt(b.name, off, nm, f"point {nm} = {b.name} at ({_f(off[0])} m, {_f(off[1])} m)")


def generate(seed: int, category: str | None = None, gated=False) -> Scene:
    """A well-posed random scene of the category (drawn from the seed when None).

    gated: open these gates (names of GATES, or True for all) as well as the fixed ones:
    draw the features they keep out.
    """
    rng = random.Random(seed)
    op = opened(gated)
    cat = category or rng.choice(categories(gated))
    for _attempt in range(200):
        sc = _draw(rng, seed, cat, op)
        if sc is not None:
            return sc
    raise RuntimeError(f"no well-posed scene drawn for seed {seed} ({cat})")


def _draw(rng: random.Random, seed: int, cat: str, op: frozenset) -> Scene | None:
    nb = rng.randint(1 if cat in ("ground", "joints", "friction") else 2, 4)
    if cat == "pendulum" and nb == 4:
        nb = 3
    names = rng.sample(NAMES, nb)
    bodies = [_make_body(rng, nm, rng.choice(KINDS)) for nm in names]
    pts = _Points(rng)
    joints: list[Joint] = []
    contacts: list[Contact] = []
    # joints: a forest with the ground (each body joined to at most one earlier body or ground)
    if cat in ("joints", "forming", "redundant") or rng.random() < 0.25:
        for i, b in enumerate(bodies):
            if rng.random() < (0.6 if cat in ("joints", "forming") else 0.3):
                kind = rng.choice(("pin", "pin", "weld", "link"))
                other = rng.choice([None] + bodies[:i]) if i else None
                a = pts.on(b, False)
                bp = pts.on(other, False) if other is not None else None
                ad, along = _direction(rng)
                forming = (cat == "forming" and other is not None and kind != "link"
                           and not any(j.forming for j in joints))
                joints.append(Joint(kind, f"j{len(joints) + 1}", a, bp, along, ad,
                                    forming=forming))
        if cat == "forming" and not any(j.forming for j in joints):
            if len(bodies) < 2:
                return None
            a, b = bodies[-1], rng.choice(bodies[:-1])
            if any(j.a.body == a.name for j in joints):
                return None
            joints.append(Joint(rng.choice(("pin", "weld")), f"j{len(joints) + 1}",
                                pts.on(a, False), pts.on(b, False), forming=True))
    if cat == "pendulum":  # one body on a ground pin, struck by free bodies
        if bodies[0].particle:
            bodies[0] = _make_body(rng, bodies[0].name, rng.choice(KINDS[1:]))
        joints = [Joint("pin", "j1", pts.on(bodies[0], False), None)]
        if nb > 2 and rng.random() < 0.4:
            joints.append(Joint(rng.choice(("pin", "weld")), "j2", pts.on(bodies[1], False),
                                pts.on(bodies[0], False)))
    joined = {frozenset((j.a.body, j.b.body if j.b else None)) for j in joints}
    # contacts
    ncont = rng.randint(1, 3 if cat != "forming" else 2)
    for k in range(ncont):
        a = rng.choice(bodies)
        others = [b for b in bodies if b is not a and frozenset((a.name, b.name)) not in joined]
        to_ground = cat in ("ground", "friction") and rng.random() < 0.6 or not others \
            or rng.random() < 0.2 and cat != "pendulum"
        if cat == "pendulum" and not others:
            return None
        nint, n = _direction(rng)
        mode = rng.choice(("smooth", "smooth", "rough", "friction"))
        if cat in ("friction",) and k == 0:
            mode = "friction"
        if cat in ("friction_multi", "friction_stated") and k < (2 if cat == "friction_multi"
                                                                 else 1):
            mode = "friction"
        if mode == "friction" and (cat == "free" or "slide_sign" not in op and
                                   any(x.mode == "friction" for x in contacts)):
            mode = "smooth"
        c = Contact(f"k{k + 1}", pts.on(a, True), None, n, nint,
                    rng.choice([0.0, 1.0, _num(rng, 0.0, 1.0, 2)]), mode=mode,
                    mu=_num(rng, 0.05, 0.8, 2))
        if not to_ground:
            c.b = pts.on(rng.choice(others), True)
        elif rng.random() < 0.4:
            c.surface = f"wall{k + 1}"
        contacts.append(c)
    if cat == "free":
        for c in contacts:
            if c.b is None:
                return None
    friction = any(c.mode == "friction" for c in contacts)
    if cat == "unknown_e":
        if friction and "slide_sign" not in op:
            return None
        rng.choice(contacts).e_unknown = True
    sc = Scene(seed, cat, bodies, contacts, joints)
    if not _velocities(rng, sc) or not _place(rng, sc):
        return None
    d = dense_solve(sc)
    if not d.rank_ok:
        return None
    if d.pull and rng.random() < 0.75:
        return None  # some pulling contacts (warned), mostly physical impacts
    sc.open = op
    want = cat in ("redundant", "friction_stated", "pendulum") or \
        cat == "unknown_e" and "structure_rank" in op and rng.random() < 0.5 or rng.random() < 0.3
    if want and (not friction or "regime_check" in op) and \
            (cat != "unknown_e" or "structure_rank" in op):
        _statements(rng, sc, d)
        if cat == "friction_stated" and not sc.statements:
            return None
    for c in contacts:
        if c.e_unknown:
            q = _sensitive(sc, c)
            if q is None or _e_regimes(sc, c, q) != 1:
                return None  # e not found from q, or Coulomb admits two answers
            sc.e_given[c.label] = q
    return sc


def _velocities(rng: random.Random, sc: Scene) -> bool:
    """State-1 velocities consistent with the joints that hold at state 1; contacts closing."""
    idx, nv = _velocity_columns(sc)
    rows = joint_rows(sc, [j for j in sc.joints if not j.forming], idx, nv)
    rows2 = joint_rows(sc, sc.joints, idx, nv)
    if rows2 and np.linalg.matrix_rank(np.array(rows2)) < len(rows2):
        return False  # over-constrained joints
    q = np.array([_num(rng, -5.0, 5.0, 3) for _ in range(nv)])
    if rows:
        C = np.array(rows)
        # project onto the null space of C (exactly consistent floats come from givens below)
        _, s, vt = np.linalg.svd(C)
        r = int((s > 1e-10 * s[0]).sum())
        N = vt[r:].T
        q = N @ (N.T @ q)
    for b in sc.bodies:
        b.v1 = tuple(float(q[idx[(b.name, c)]]) for c in range(b.ndof)) + \
            ((0.0,) if b.particle else ())
    scale = max(1.0, float(np.abs(q).max()))
    for c in sc.contacts:
        vn1 = _rel(sc, c, None, c.normal)
        if abs(vn1) < 0.05 * scale:
            return False
        if vn1 > 0:  # make it closing: the impulse on a points the other way
            c.normal = (-c.normal[0], -c.normal[1])
            c.nint = (-c.nint[0], -c.nint[1])
        if c.mode == "friction":
            t = (-c.normal[1], c.normal[0])
            if abs(_rel(sc, c, None, t)) < 0.05 * scale:
                return False
    return True


def _place(rng: random.Random, sc: Scene) -> bool:
    """Positions: joint points coincide (ground pins where their body puts them); contact
    points coincide along a spanning tree of the remaining interactions."""
    bm = bodymap(sc)
    for b in sc.bodies:
        b.pos = (_num(rng, -3, 3, 3), _num(rng, -3, 3, 3))
    # joints first (a forest: each joint's a-side body is placed from its b side); bodies
    # carried along with a joint parent move with it: one pass per joint, and one more
    for _ in range(len(sc.joints) + 1):
        for jt in sc.joints:
            if jt.b is not None and jt.b.body is not None:
                pb = point_world(sc, jt.b)
                r = arm(bm[jt.a.body], jt.a)
                bm[jt.a.body].pos = (pb[0] - r[0], pb[1] - r[1])
        for jt in sc.joints:
            if jt.b is None:
                jt.ground_at = point_world(sc, jt.a)
    # joint groups: contacts place unjointed groups against each other where they can
    group = {b.name: b.name for b in sc.bodies}

    def root(x):
        while group[x] != x:
            x = group[x]
        return x
    grounded = set()
    for jt in sc.joints:
        if jt.b is None or jt.b.body is None:
            grounded.add(jt.a.body)
        else:
            group[root(jt.a.body)] = root(jt.b.body)
    grounded = {root(x) for x in grounded}
    for c in sc.contacts:
        if c.b is None or c.b.body is None:
            continue
        ra, rb = root(c.a.body), root(c.b.body)
        if ra == rb or (ra in grounded and rb in grounded):
            continue
        pa = point_world(sc, c.a, c.normal, 1.0)
        pb = point_world(sc, c.b, c.normal, -1.0)
        dx, dy = pb[0] - pa[0], pb[1] - pa[1]
        if ra in grounded:  # move b's group onto a instead
            ra, rb, dx, dy = rb, ra, -dx, -dy
        for b in sc.bodies:
            if root(b.name) == ra:
                b.pos = (b.pos[0] + dx, b.pos[1] + dy)
        group[ra] = rb
        if ra in grounded or rb in grounded:
            grounded.add(rb)
    return True


def _sensitive(sc: Scene, c: Contact):
    """The state-2 quantity that depends most on e at contact c (to determine e)."""
    e0 = c.e
    d0 = dense_solve(sc)
    c.e = e0 + 0.1 if e0 < 0.5 else e0 - 0.1
    d1 = dense_solve(sc)
    c.e = e0
    if not (d0.rank_ok and d1.rank_ok):
        return None
    best, bs = None, 0.0
    for k, v in d0.v2.items():
        s = abs(d1.v2[k] - v)
        if s > bs:
            best, bs = k, s
    scale = max(abs(v) for v in d0.v2.values()) + 1.0
    return best if bs > 1e-3 * scale else None


def external(sc: Scene, group: set):
    """Impulse directions from outside `group` on it: ([direction or 'plane'], ground pins)."""
    dirs, pins = [], []
    for c in sc.contacts:
        inside = [p is not None and p.body in group for p in (c.a, c.b)]
        if inside.count(True) == 1:
            dirs.append(c.normal if c.mode == "smooth" else "plane")
    for jt in sc.joints:
        inside = [p is not None and p.body in group for p in (jt.a, jt.b)]
        if inside.count(True) == 1:
            if jt.kind == "link":
                dirs.append(jt.along)
            else:
                dirs.append("plane")
                if jt.b is None and jt.kind == "pin":
                    pins.append(jt)
                else:
                    pins.append(None)
    return dirs, pins


def free_direction(dirs):
    """A direction no external impulse has a component along (None if there is none)."""
    if any(d == "plane" for d in dirs):
        return None
    if not dirs:
        return "xy"
    M = np.array(dirs)
    if np.linalg.matrix_rank(M, tol=1e-12) > 1:
        return None
    d = dirs[0]
    return (-d[1], d[0])


def _statements(rng: random.Random, sc: Scene, d: Dense) -> None:
    """Redundant true statements: momentum where it holds, equations with true values."""
    names = [b.name for b in sc.bodies]
    for _ in range(rng.randint(1, 3)):
        kind = rng.choice(("momentum", "angular", "equation"))
        if sc.category == "pendulum" and not any(x[0] == "angular" for x in sc.statements):
            kind = "angular"
        # an angular statement holds to the round-off of the positions (contact points
        # coincide to 1e-16 m); with an exact `equation` as well, the solve may use it in
        # place of Newton-Euler and miss the exact value by that round-off: gate
        # check_tolerance (seed 6922 of the pendulum category)
        mixed = {"equation": "angular", "angular": "equation"}.get(kind)
        if "check_tolerance" not in sc.open and any(x[0] == mixed for x in sc.statements):
            continue
        if kind == "equation":
            keys = sorted(d.v2)
            scale = 1.0 + max(abs(v) for v in d.v2.values())
            zeros = [k for k in keys if abs(d.v2[k]) < 1e-12 * scale]
            if zeros and "check_tolerance" in sc.open:
                keys = zeros  # a true value of 0, as the dense solve's round-off
            sc.statements.append(("equation", rng.choice(keys)))
            continue
        comps = components(sc)
        if rng.random() < 0.6:
            group = set(rng.choice(comps))
        else:
            group = set(rng.sample(names, rng.randint(1, len(names))))
        if kind == "angular":  # prefer a group held by one ground pin
            held = [c for c in comps if _one_pin(sc, set(c))]
            if held:
                group = set(rng.choice(held))
        dirs, pins = external(sc, group)
        if kind == "momentum":
            f = free_direction(dirs)
            if f is None:
                continue
            if f == "xy":
                sc.statements.append(("momentum", group, rng.choice(("x", "y"))))
            else:
                sc.statements.append(("momentum", group, f))
        elif len(pins) == 1 and pins[0] is not None and len(dirs) == 1 and \
                _colocated(sc, group):
            sc.statements.append(("angular", group, pins[0]))


def components(sc: Scene) -> list[list[str]]:
    """Bodies connected by contacts and joints between bodies."""
    parent = {b.name: b.name for b in sc.bodies}

    def root(x):
        while parent[x] != x:
            x = parent[x]
        return x
    for el in list(sc.contacts) + list(sc.joints):
        if el.b is not None and el.b.body is not None:
            parent[root(el.a.body)] = root(el.b.body)
    out: dict[str, list[str]] = {}
    for b in sc.bodies:
        out.setdefault(root(b.name), []).append(b.name)
    return list(out.values())


def _one_pin(sc: Scene, group: set) -> bool:
    dirs, pins = external(sc, group)
    return len(pins) == 1 and pins[0] is not None and len(dirs) == 1


def _colocated(sc: Scene, group: set) -> bool:
    """Internal impulse pairs of the group act at one point (so they cancel in moments)."""
    for c in sc.contacts:
        if c.b is not None and c.a.body in group and c.b.body in group:
            pa = point_world(sc, c.a, c.normal, 1.0)
            pb = point_world(sc, c.b, c.normal, -1.0)
            if math.dist(pa, pb) > 1e-9:
                return False
    for jt in sc.joints:
        if jt.b is not None and jt.b.body is not None and jt.a.body in group and \
                jt.b.body in group:
            if math.dist(point_world(sc, jt.a), point_world(sc, jt.b)) > 1e-9:
                return False
    return True


# ---- rendering -----------------------------------------------------------------------------------

def _f(x: float) -> str:
    return repr(float(x))


def _given_columns(sc: Scene, rows, cols):
    """Which columns the file leaves unknown so the joint rows determine them (greedy)."""
    if not rows:
        return set()
    C = np.array(rows)
    target = np.linalg.matrix_rank(C)
    chosen: list[int] = []
    for c in cols:
        trial = chosen + [c]
        if np.linalg.matrix_rank(C[:, trial], tol=1e-10) == len(trial):
            chosen = trial
            if len(chosen) == target:
                break
    return set(chosen)


def _position_rows(sc: Scene):
    """Linear rows (in x, y of each body) of the pin and weld position constraints."""
    bm = bodymap(sc)
    cols = {}
    for b in sc.bodies:
        cols[(b.name, "x")] = len(cols)
        cols[(b.name, "y")] = len(cols)
    rows = []
    for jt in sc.joints:
        if jt.kind == "link":
            continue
        for k, q in enumerate(("x", "y")):
            row = np.zeros(len(cols))
            row[cols[(jt.a.body, q)]] += 1
            if jt.b is not None and jt.b.body is not None:
                row[cols[(jt.b.body, q)]] -= 1
            rows.append(row)
    del bm
    return rows, cols


def render(sc: Scene) -> str:
    bm = bodymap(sc)
    L = [f'problem "generated scene {sc.seed} ({sc.category})"']
    for b in sc.bodies:
        m = f"mass = {_f(b.mass)} kg"
        d = [_f(x) for x in b.dims]
        if b.kind == "rod":
            args = f"{m}, length = {d[0]} m"
        elif b.kind in ("disk", "sphere"):
            args = f"{m}, radius = {d[0]} m"
        elif b.kind == "plate":
            args = f"{m}, width = {d[0]} m, height = {d[1]} m"
        elif b.kind == "rigid":
            args = f"{m}, inertia = {d[0]} kg*m^2"
        else:
            args = m
        L.append(f"body {b.name}: {b.kind}({args})")
    decls = []
    for c in sc.contacts:
        for p in (c.a, c.b):
            if p is not None and p.decl and p.decl not in decls:
                decls.append(p.decl)
    for jt in sc.joints:
        for p in (jt.a, jt.b):
            if p is not None and p.decl and p.decl not in decls:
                decls.append(p.decl)
    L += decls
    for c in sc.contacts:
        if c.surface:
            L.append(f"surface {c.surface} normal ({c.nint[0]}, {c.nint[1]})")
    for jt in sc.joints:
        frm = " from 2" if jt.forming else ""
        if jt.kind == "link":
            other = jt.b.ref if jt.b is not None else "ground"
            L.append(f"link {jt.label}: {jt.a.ref} to {other} along ({jt.aint[0]}, {jt.aint[1]})")
        elif jt.b is None:
            if jt.kind == "pin":
                gx, gy = jt.ground_at
                L.append(f"pin {jt.label}: {jt.a.ref} to ground at ({_f(gx)} m, {_f(gy)} m)"
                         + frm)
            else:
                gx, gy = jt.ground_at
                L.append(f"point G{jt.label} = ground at ({_f(gx)} m, {_f(gy)} m)")
                L.append(f"weld {jt.label}: {jt.a.ref} to G{jt.label}{frm}")
        else:
            L.append(f"{jt.kind} {jt.label}: {jt.a.ref} to {jt.b.ref}{frm}")
    # state 1: angles, the positions and velocities the joints do not determine
    idx, nv = _velocity_columns(sc)
    vrows = joint_rows(sc, [j for j in sc.joints if not j.forming], idx, nv)
    order = []
    for jt in sc.joints:
        if not jt.forming:
            for c in range(bm[jt.a.body].ndof):
                order.append(idx[(jt.a.body, c)])
    order += [k for k in range(nv) if k not in order]
    vfree = _given_columns(sc, vrows, order)
    prows, pcols = _position_rows(sc)
    porder = []
    for jt in sc.joints:
        if jt.kind != "link":
            porder += [pcols[(jt.a.body, "x")], pcols[(jt.a.body, "y")]]
    porder += [k for k in range(len(pcols)) if k not in porder]
    pfree = _given_columns(sc, prows, porder)
    items = []
    for b in sc.bodies:
        if not b.particle:
            items.append(f"{b.name}.angle = {_f(b.angle)} rad")
        for q, k in (("x", 0), ("y", 1)):
            if pcols[(b.name, q)] not in pfree:
                items.append(f"{b.name}.{q} = {_f(b.pos[k])} m")
        for c, (q, u) in enumerate((("vx", "m/s"), ("vy", "m/s"), ("omega", "rad/s"))[:b.ndof]):
            if idx[(b.name, c)] not in vfree:
                items.append(f"{b.name}.{q} = {_f(b.v1[c])} {u}")
    L.append('state 1 "just before":')
    for it in items:
        L.append(f"    {it}")
    L.append('state 2 "just after"')
    L.append("impact 1 -> 2:")
    for c in sc.contacts:
        target = c.b.ref if c.b is not None else (c.surface or "ground")
        normal = "" if c.surface else f" normal ({c.nint[0]}, {c.nint[1]})"
        e = "?" if c.e_unknown else _f(c.e)
        law = {"smooth": "smooth", "rough": "rough", "friction": f"friction {_f(c.mu)}"}[c.mode]
        L.append(f"    contact {c.label}: {c.a.ref} with {target}{normal}: restitution {e}, {law}")
    d = dense_solve(sc)
    vscale = 1.0 + max(abs(v) for v in d.v2.values())

    exact = exact_v2(sc, d) if sc.statements or sc.e_given else {}

    def value(key):
        """A true value: exact (round-off of 0 written as 0), or with the gate
        check_tolerance open the dense solve's float, off by its round-off -- where that
        is round-off (a few ulps of the scene's speeds); an ill-conditioned dense solve
        (cond 1e3: 1e-13 m/s from a true 0) misses by more, and is no true statement."""
        if "check_tolerance" in sc.open and abs(d.v2[key] - exact[key]) <= FEW_ULPS * vscale:
            return d.v2[key]
        return 0.0 if abs(exact[key]) < 1e-12 * vscale else exact[key]
    for lab, (b, q) in sc.e_given.items():
        u = "rad/s" if q == "omega" else "m/s"
        L.append(f"equation {b}.{q}@2 = {_f(value((b, q)))} {u}")
    for st in sc.statements:
        if st[0] == "equation":
            b, q = st[1]
            u = "rad/s" if q == "omega" else "m/s"
            L.append(f"equation {b}.{q}@2 = {_f(value((b, q)))} {u}")
        elif st[0] == "momentum":
            ax = st[2] if isinstance(st[2], str) else f"({_f(st[2][0])}, {_f(st[2][1])})"
            L.append(f"conserve momentum {ax} of {{{', '.join(sorted(st[1]))}}} over 1 -> 2")
        else:
            L.append(f"conserve angular momentum of {{{', '.join(sorted(st[1]))}}} about "
                     f"{st[2].a.ref}"
                     " over 1 -> 2")
    L.append("find " + ", ".join(finds(sc)))
    return "\n".join(L) + "\n"


def finds(sc: Scene) -> list[str]:
    out = []
    for b in sc.bodies:
        out += [f"{b.name}.{q}@2" for q in ("vx", "vy", "omega")[:b.ndof]]
    out += list(dense_impulse_names(sc))
    out += [f"e[{c.label}]" for c in sc.contacts if c.e_unknown]
    return out


def dense_impulse_names(sc: Scene):
    _A, _r, _i, _n, names = _impact_system(sc, {c.label: "stick" for c in sc.contacts})
    return names


# ---- one scene through the program, and the comparison -----------------------------------------

@dataclass
class Outcome:
    seed: int
    category: str
    status: str            # ok | refused | pull-refused | crash | mismatch | law
    detail: str = ""
    text: str = ""
    pull: bool = False
    seconds: float = 0.0


def program_answers(text: str):
    """Solve the text through the real pipeline: (answers {name: SI}, Solution)."""
    from momentum_cli.scene import build
    from momentum_cli.solve import solve_scene
    from momentum_cli.source import Source
    from momentum_cli.syntax import parse

    sol = solve_scene(build(parse(Source("generated.mom", text))))
    return {n: si for n, _v, _u, si in sol.answers}, sol


def run_one(seed: int, category: str | None = None, scene: Scene | None = None,
            gated=False) -> Outcome:
    from momentum_cli.diagnostics import ProblemError

    t0 = time.perf_counter()
    sc = scene or generate(seed, category, gated)
    text = render(sc)
    d = dense_solve(sc)
    out = Outcome(seed, sc.category, "ok", text=text, pull=bool(d.pull))
    try:
        ans, sol = program_answers(text)
    except ProblemError as exc:
        msg = exc.diagnostics[0].message if exc.diagnostics else str(exc)
        out.status = "pull-refused" if d.pull else "refused"
        out.detail = msg
        out.seconds = time.perf_counter() - t0
        return out
    except Exception as exc:  # noqa: BLE001 - any crash is a finding
        out.status, out.detail = "crash", f"{type(exc).__name__}: {exc}"
        out.seconds = time.perf_counter() - t0
        return out
    problems = compare(sc, d, ans, sol)
    if problems:
        out.status = problems[0][0]
        out.detail = "; ".join(p[1] for p in problems[:4])
    out.seconds = time.perf_counter() - t0
    return out


def compare(sc: Scene, d: Dense, ans: dict, sol) -> list[tuple[str, str]]:
    """(kind, what) for every disagreement with the dense solve and every law broken."""
    probs = []
    vscale = 1.0 + max(abs(v) for v in d.v2.values())
    jscale = 1e-300 + max([abs(v) for v in d.impulses.values()] + [1e-12])
    for (b, q), v in d.v2.items():
        got = ans.get(f"{b}.{q}@2")
        if got is None or abs(got - v) > REL_TOL * vscale:
            probs.append(("mismatch", f"{b}.{q}@2 = {got}, dense solve {v!r}"))
    for nm, v in d.impulses.items():
        got = ans.get(nm)
        if got is None or abs(got - v) > REL_TOL * (jscale + abs(v)):
            probs.append(("mismatch", f"{nm} = {got}, dense solve {v!r}"))
    for c in sc.contacts:
        if c.e_unknown:
            got = ans.get(f"e[{c.label}]")
            if got is None or abs(got - c.e) > 1e-7:
                probs.append(("mismatch", f"e[{c.label}] = {got}, generated {c.e!r}"))
    # stated principles are true: the program must find them to hold
    for ch in sol.checks:
        if "(stated)" in ch.name and ch.status not in ("ok", "info"):
            probs.append(("law", f"stated principle refused: {ch.name}: {ch.detail}"))
    # a contact that would pull is answered with a warning naming it (documented)
    warned = {ch.name for ch in sol.checks if ch.status == "warning" and "pull" in ch.detail}
    for lab in d.pull:
        if f"contact J_n[{lab}]@1->2" not in warned:
            probs.append(("law", f"contact {lab} pulls (J_n < 0) without the warning"))
    # laws on the program's own answers
    v2 = {}
    for b in sc.bodies:
        for q in ("vx", "vy", "omega")[:b.ndof]:
            v2[(b.name, q)] = ans.get(f"{b.name}.{q}@2", math.nan)
    probs += laws(sc, v2, d)
    probs += coulomb(sc, ans, v2, sol.regimes)
    return probs


def coulomb(sc: Scene, ans: dict, v2: dict, regimes: dict) -> list[tuple[str, str]]:
    """The program's friction regimes obey Coulomb: stick inside the cone; a sliding
    contact pushes (J_n >= 0) and its friction opposes the slip before and after."""
    probs = []
    for c in sc.contacts:
        if c.mode != "friction":
            continue
        jn, jt = ans.get(f"J_n[{c.label}]@1->2"), ans.get(f"J_t[{c.label}]@1->2")
        if jn is None or jt is None:
            continue
        t = (-c.normal[1], c.normal[0])
        vt1, vt2 = _rel(sc, c, None, t), _rel(sc, c, v2, t)
        tol = 1e-9 * (abs(jn) + abs(jt) + 1e-300)
        regime = regimes.get(f"1->2:{c.label}", "stick")
        if regime == "stick" and abs(jt) > c.mu * jn + tol:
            probs.append(("law", f"{c.label} sticks outside the friction cone: "
                          f"|J_t| = {abs(jt)!r} > mu J_n = {c.mu * jn!r}"))
        elif regime != "stick":
            if jn < -tol:
                probs.append(("law", f"{c.label} slides while pulling: J_n = {jn!r}"))
            elif jt * vt1 > tol * abs(vt1) and jt * vt2 > -tol * abs(vt2):
                probs.append(("law", f"{c.label}: friction J_t = {jt!r} acts along the slip "
                              f"(before {vt1!r}, after {vt2!r})"))
            elif vt1 * vt2 < 0 and abs(vt2) > 1e-9 * (abs(vt1) + 1.0):
                probs.append(("law", f"{c.label}: sliding reversed the slip (before {vt1!r}, "
                              f"after {vt2!r}): friction opposing it would have stopped it"))
    return probs


def laws(sc: Scene, v2: dict, d: Dense) -> list[tuple[str, str]]:
    """Momentum in impulse-free directions, angular momentum about a lone ground pin,
    no energy gained by frictionless contacts with e <= 1 that push."""
    probs = []
    allb = {b.name for b in sc.bodies}
    p1 = [sum(b.mass * b.v1[k] for b in sc.bodies) for k in (0, 1)]
    p2 = [sum(b.mass * v2[(b.name, q)] for b in sc.bodies) for q in ("vx", "vy")]
    pscale = sum(b.mass * math.hypot(b.v1[0], b.v1[1]) for b in sc.bodies) + 1e-300
    dirs, pins = external(sc, allb)
    f = free_direction(dirs)
    for u in ([(1.0, 0.0), (0.0, 1.0)] if f == "xy" else [f] if f else []):
        a = p1[0] * u[0] + p1[1] * u[1]
        b = p2[0] * u[0] + p2[1] * u[1]
        if not abs(a - b) <= LAW_TOL * pscale * 10:
            probs.append(("law", f"momentum along {u} not conserved: {a!r} -> {b!r}"))
    if len(pins) == 1 and pins[0] is not None and len(dirs) == 1 and _colocated(sc, allb):
        O = pins[0].ground_at

        def H(vel):
            h = 0.0
            for b in sc.bodies:
                vx, vy, w = vel(b)
                h += b.mass * cross((b.pos[0] - O[0], b.pos[1] - O[1]), (vx, vy)) + b.inertia * w
            return h
        h1 = H(lambda b: b.v1)
        h2 = H(lambda b: (v2[(b.name, "vx")], v2[(b.name, "vy")],
                          v2.get((b.name, "omega"), 0.0)))
        # momentum times the scene's length scale (1 m) as a floor: bodies at the pin
        hscale = sum(b.mass * (math.hypot(b.pos[0] - O[0], b.pos[1] - O[1]) + 1.0) *
                     math.hypot(b.v1[0], b.v1[1]) + b.inertia * abs(b.v1[2])
                     for b in sc.bodies) + 1e-300
        if not abs(h1 - h2) <= LAW_TOL * hscale * 10:
            probs.append(("law", f"angular momentum about the pin {O} not conserved: "
                          f"{h1!r} -> {h2!r}"))
    # Newton's law at one contact dissipates; with a joint that forms (plastic) in the
    # same impact, the simultaneous Newton system can gain energy (as with several
    # contacts of different e), so the law is checked without forming joints
    if all(c.mode == "smooth" and c.e <= 1 for c in sc.contacts) and not d.pull and \
            not any(j.forming for j in sc.joints):
        T1 = sum(b.mass * (b.v1[0] ** 2 + b.v1[1] ** 2) + b.inertia * b.v1[2] ** 2
                 for b in sc.bodies) / 2
        T2 = sum(b.mass * (v2[(b.name, "vx")] ** 2 + v2[(b.name, "vy")] ** 2) +
                 b.inertia * v2.get((b.name, "omega"), 0.0) ** 2 for b in sc.bodies) / 2
        if not T2 <= T1 * (1 + LAW_TOL) + 1e-300:
            probs.append(("law", f"energy gained by frictionless contacts: T1 = {T1!r}, "
                          f"T2 = {T2!r}"))
    return probs


# ---- shrinking -----------------------------------------------------------------------------------

def shrink(sc: Scene, status: str) -> Scene:
    """Remove statements, contacts, joints and bodies while the failure stays the same."""
    def still(s: Scene) -> bool:
        try:
            if not _valid(s):
                return False
            return run_one(s.seed, scene=s).status == status
        except Exception:  # noqa: BLE001
            return False

    changed = True
    while changed:
        changed = False
        for attr in ("statements", "contacts", "joints"):
            for k in range(len(getattr(sc, attr))):
                lst = list(getattr(sc, attr))
                del lst[k]
                cand = _copy(sc, **{attr: lst})
                if still(cand):
                    sc, changed = cand, True
                    break
        for k, b in enumerate(sc.bodies):
            if len(sc.bodies) == 1:
                break
            cand = _copy(sc, bodies=[x for x in sc.bodies if x is not b],
                         contacts=[c for c in sc.contacts
                                   if b.name not in (c.a.body, c.b.body if c.b else None)],
                         joints=[j for j in sc.joints
                                 if b.name not in (j.a.body, j.b.body if j.b else None)],
                         statements=[_without(s, b.name) for s in sc.statements
                                     if _without(s, b.name) is not None])
            if still(cand):
                sc, changed = cand, True
                break
    return sc


def _without(st, body: str):
    """A statement with a body taken out (None when nothing is left of it)."""
    if st[0] == "equation":
        return None if st[1][0] == body else st
    group = set(st[1]) - {body}
    if not group or (st[0] == "angular" and st[2].a.body == body):
        return None
    return (st[0], group, st[2])


def _copy(sc: Scene, **kw) -> Scene:
    import copy
    new = copy.deepcopy(replace(sc, **kw))
    new.e_given = {k: v for k, v in new.e_given.items()
                   if any(c.label == k for c in new.contacts) and v[0] in
                   {b.name for b in new.bodies}}
    return new


def _valid(sc: Scene) -> bool:
    """The scene (after a removal) is still well-posed by the generator's criteria."""
    if not sc.contacts:
        return False
    idx, nv = _velocity_columns(sc)
    rows = joint_rows(sc, [j for j in sc.joints if not j.forming], idx, nv)
    if rows:
        q = np.array([sum(([b.v1[c] for c in range(b.ndof)] for b in sc.bodies), [])]).ravel()
        if np.abs(np.array(rows) @ q).max() > 1e-9:
            return False
    for c in sc.contacts:
        if _rel(sc, c, None, c.normal) >= 0:
            return False
        if c.e_unknown and c.label not in sc.e_given:
            return False
    d = dense_solve(sc)
    if not d.rank_ok:
        return False
    for st in sc.statements:
        if st[0] == "equation" and st[1] not in d.v2:
            return False
        if st[0] in ("momentum", "angular") and not set(st[1]) <= {b.name for b in sc.bodies}:
            return False
        if st[0] == "momentum":
            dirs, _ = external(sc, set(st[1]))
            f = free_direction(dirs)
            if f is None or (f != "xy" and isinstance(st[2], str)) or \
                    (f == "xy" and not isinstance(st[2], str)):
                return False
        if st[0] == "angular":
            dirs, pins = external(sc, set(st[1]))
            if not (len(pins) == 1 and pins[0] is st[2] and len(dirs) == 1):
                return False
    return True


# ---- the large run -------------------------------------------------------------------------------

def run_many(count: int, start: int = 0, only=None, progress=None, gated=False):
    """Outcomes of `count` scenes (seeds start..start+count-1), with the figures."""
    cats = only or categories(gated)
    outs = []
    t0 = time.perf_counter()
    for k in range(count):
        seed = start + k
        cat = cats[seed % len(cats)]
        try:
            outs.append(run_one(seed, cat, gated=gated))
        except Exception as exc:  # noqa: BLE001 - the generator itself failing is a finding
            outs.append(Outcome(seed, cat, "crash", f"generator: {type(exc).__name__}: {exc}"))
        if progress and (k + 1) % progress == 0:
            print(f"  {k + 1} scenes, {time.perf_counter() - t0:.1f} s", file=sys.stderr)
    return outs, time.perf_counter() - t0


def figures(outs, seconds: float) -> dict:
    fig = {"scenes": len(outs), "seconds": round(seconds, 1)}
    for s in ("ok", "refused", "pull-refused", "crash", "mismatch", "law"):
        fig[s] = sum(o.status == s for o in outs)
    fig["pull (warned, answered)"] = sum(o.pull and o.status == "ok" for o in outs)
    bycat = {}
    for o in outs:
        bycat.setdefault(o.category, {}).setdefault(o.status, 0)
        bycat[o.category][o.status] += 1
    fig["by category"] = bycat
    return fig


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--count", type=int, default=1000)
    ap.add_argument("--start", type=int, default=0)
    ap.add_argument("--category", action="append", help="draw only these (gated ones too)")
    ap.add_argument("--gated", action="append", choices=sorted(GATES),
                    help="open a gate: also draw the feature it keeps out")
    ap.add_argument("--shrink", type=int, default=0, help="shrink up to N failures per kind")
    ap.add_argument("--out", type=Path, help="write the shrunk reproductions here")
    args = ap.parse_args(argv)
    outs, secs = run_many(args.count, args.start, args.category, progress=1000,
                           gated=args.gated)
    fig = figures(outs, secs)
    for k, v in fig.items():
        print(f"{k}: {v}")
    bad = [o for o in outs if o.status not in ("ok", "pull-refused")]
    kinds: dict[str, list] = {}
    for o in bad:
        kinds.setdefault(f"{o.category}/{o.status}", []).append(o)
    for kind, lst in sorted(kinds.items()):
        print(f"\n== {kind}: {len(lst)}  (seeds {[o.seed for o in lst[:10]]})")
        for o in lst[:args.shrink]:
            sc = shrink(generate(o.seed, o.category, args.gated), o.status)
            r = run_one(o.seed, scene=sc)
            print(f"-- seed {o.seed}: {r.detail}\n{r.text}")
            if args.out:
                args.out.mkdir(parents=True, exist_ok=True)
                (args.out / f"{kind.replace('/', '_')}_{o.seed}.mom").write_text(
                    f"# {r.status}: {r.detail}\n" + r.text)
    return 0


if __name__ == "__main__":
    sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
    raise SystemExit(main())
