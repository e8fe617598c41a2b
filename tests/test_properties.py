"""Property tests (hypothesis): random frictionless impacts, written as problem TEXT.

Every scene is a plain description (bodies, contact points, normals, e) that is
rendered to the problem language, solved through tests.helpers, and checked against

* conservation laws: linear momentum of the system (no ground contact), linear
  momentum of each body along its contact tangent, angular momentum of each body
  about its single contact point;
* the energy inequality T2 <= T1 (one e for all contacts of a scene, 0 <= e <= 1)
  and T2 = T1 for e = 1;
* an independent solution derived here: the contact (Delassus) equations
  W lambda = -(1 + e) u-, with W = G M^-1 G^T, solved in exact rational arithmetic
  from the same floats the file gives (for one contact this is the textbook closed
  form J = -(1 + e) u- / (1/m_a + 1/m_b + (r_a x n)^2/I_a + (r_b x n)^2/I_b));
* invariance under a rotation of the frame, a translation (where positions are
  given), the order of the bodies (and the sides of each contact) in the file, and
  a change to US customary units;
* symmetry: symmetric scenes give symmetric answers, and the closed form of the
  three-billiard-ball problem.

No expected value comes from the program's own output, except in the invariance
tests, which compare two renderings of the same scene with each other (and both with
the independent solution).

Note on the energy property. With simultaneous contacts, T2 - T1 =
sum_k lambda_k (1 - e_k) u-_k / 2, and lambda = -W^-1 (1 + E) u-. For one e at every
contact this is -(1 - e^2) u-^T W^-1 u- / 2 <= 0. With *different* e_k it is <= 0 when
every contact is closing (u-_k < 0) and pushes (lambda_k >= 0), but Newton's law at
each contact can make one contact pull (lambda_k < 0, which the program flags as a
warning) and then gain energy with every e_k in [0, 1]: a property of the model, not a
bug. So the energy inequality is asserted for one e per scene, or when every J_n >= 0.
"""
from __future__ import annotations

import math
import os
from dataclasses import dataclass, field
from fractions import Fraction

import pytest
from helpers import answers as answers_of
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

# Deterministic and bounded so that the file runs in a few seconds; set
# MOMENTUM_PROPERTY_EXAMPLES=1000 for a thorough (slower, still deterministic) run.
N_EXAMPLES = int(os.environ.get("MOMENTUM_PROPERTY_EXAMPLES", "150"))
SETTINGS = settings(derandomize=True, max_examples=N_EXAMPLES, deadline=None, database=None,
                    suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
FEW = settings(SETTINGS, max_examples=max(1, N_EXAMPLES // 2))

MOMENTUM_TOL = 1e-12  # relative to the momentum scale of the scene
ENERGY_TOL = 1e-12    # relative to T1
INVARIANCE_TOL = 1e-10
REFERENCE_TOL = 1e-9  # the program (floats) against the exact solution of the same data

# US customary factors, written out here (independent of momentum_cli.units)
FT = 0.3048
INCH = 0.0254
LBM = 0.45359237
LBF = 4.4482216152605
SLUG = LBF / FT
MPH = 1609.344 / 3600
RPM = 2 * math.pi / 60
G_US = 32.2 * FT  # the file's g when weights are given with `gravity 32.2 ft/s^2`


# ---- the scene model -------------------------------------------------------------------------

ROUND = ("disk", "ring", "sphere")
KINDS = ("particle", "disk", "ring", "sphere", "rod", "plate")


@dataclass
class Body:
    name: str
    kind: str
    mass: float
    dims: tuple[float, ...]  # (radius,) | (length,) | (width, height) | ()
    angle: float = 0.0
    v: tuple[float, float] = (0.0, 0.0)
    omega: float = 0.0

    @property
    def inertia(self) -> float:
        """I_G from the shape's formula (derived here, not read from the program)."""
        m = self.mass
        if self.kind == "particle":
            return 0.0
        if self.kind == "disk":
            return m * self.dims[0] ** 2 / 2
        if self.kind == "ring":
            return m * self.dims[0] ** 2
        if self.kind == "sphere":
            return 2 * m * self.dims[0] ** 2 / 5
        if self.kind == "rod":
            return m * self.dims[0] ** 2 / 12
        if self.kind == "plate":
            return m * (self.dims[0] ** 2 + self.dims[1] ** 2) / 12
        raise AssertionError(self.kind)

    @property
    def size(self) -> float:
        """A length to turn omega into a velocity when comparing."""
        if self.kind == "particle":
            return 0.0
        if self.kind == "plate":
            return math.hypot(*self.dims) / 2
        if self.kind == "rod":
            return self.dims[0] / 2
        return self.dims[0]


@dataclass
class Pt:
    """A contact point: the body's name (`round`: G - r n on a round body, G otherwise),
    a rod end (`end+`, `end-`) or a named point at a body-frame offset (`offset`)."""

    body: str
    mode: str
    offset: tuple[float, float] = (0.0, 0.0)


@dataclass
class Contact:
    label: str
    a: Pt
    b: Pt | None  # None: the ground
    theta: float  # the normal's angle (rad): the direction of the impulse on a
    e: float


@dataclass
class Scene:
    bodies: list[Body]
    contacts: list[Contact]
    extra: list[str] = field(default_factory=list)

    def body(self, name: str) -> Body:
        return next(b for b in self.bodies if b.name == name)


def rot(v, a):
    c, s = math.cos(a), math.sin(a)
    return (c * v[0] - s * v[1], s * v[0] + c * v[1])


def cross(a, b):
    return a[0] * b[1] - a[1] * b[0]


def normal_of(c: Contact):
    return (math.cos(c.theta), math.sin(c.theta))


def arm(scene: Scene, p: Pt, n, sign: float):
    """World vector from G to the contact point (as the language defines it)."""
    b = scene.body(p.body)
    if b.kind == "particle":
        return (0.0, 0.0)
    if p.mode == "round":
        if b.kind in ROUND:
            r = b.dims[0]
            return (-sign * r * n[0], -sign * r * n[1])
        return (0.0, 0.0)
    if p.mode in ("end+", "end-"):
        off = (b.dims[0] / 2 * (1 if p.mode == "end+" else -1), 0.0)
    else:
        off = p.offset
    return rot(off, b.angle)


# ---- the independent solution: Delassus equations in exact arithmetic ------------------------

def _F(x: float) -> Fraction:
    return Fraction(x)


def reference(scene: Scene):
    """(post-impact {name: (vx, vy, omega)}, [lambda_k], [u-_k]) in exact arithmetic.

    Rows of G: u_k = sum over the contact's bodies of s (n . v + omega (r x n)), s = +1
    for the first body and -1 for the second. Newton at every contact:
    G q+ = -e G q-, with q+ = q- + M^-1 G^T lambda.
    """
    rows = []  # per contact: list of (body, s, n, rxn)
    for c in scene.contacts:
        n = normal_of(c)
        terms = [(c.a.body, 1.0, n, cross(arm(scene, c.a, n, 1.0), n))]
        if c.b is not None:
            terms.append((c.b.body, -1.0, n, cross(arm(scene, c.b, n, -1.0), n)))
        rows.append(terms)
    bodies = {b.name: b for b in scene.bodies}

    def u_of(terms):
        u = Fraction(0)
        for name, s, n, rxn in terms:
            b = bodies[name]
            u += _F(s) * (_F(n[0]) * _F(b.v[0]) + _F(n[1]) * _F(b.v[1]) +
                          (_F(b.omega) * _F(rxn) if b.kind != "particle" else 0))
        return u

    u = [u_of(t) for t in rows]
    k = len(rows)
    W = [[Fraction(0)] * k for _ in range(k)]
    for i in range(k):
        for j in range(k):
            for bi, si, ni, ri in rows[i]:
                for bj, sj, nj, rj in rows[j]:
                    if bi != bj:
                        continue
                    b = bodies[bi]
                    w = (_F(ni[0]) * _F(nj[0]) + _F(ni[1]) * _F(nj[1])) / _F(b.mass)
                    if b.kind != "particle":
                        w += _F(ri) * _F(rj) / _F(b.inertia)
                    W[i][j] += _F(si) * _F(sj) * w
    rhs = [-(1 + _F(c.e)) * u[i] for i, c in enumerate(scene.contacts)]
    lam = _solve_exact(W, rhs)
    post = {}
    for b in scene.bodies:
        vx, vy, w = _F(b.v[0]), _F(b.v[1]), _F(b.omega)
        for i, terms in enumerate(rows):
            for name, s, n, rxn in terms:
                if name != b.name:
                    continue
                vx += _F(s) * _F(n[0]) * lam[i] / _F(b.mass)
                vy += _F(s) * _F(n[1]) * lam[i] / _F(b.mass)
                if b.kind != "particle":
                    w += _F(s) * _F(rxn) * lam[i] / _F(b.inertia)
        post[b.name] = (float(vx), float(vy), float(w))
    return post, [float(x) for x in lam], [float(x) for x in u]


def _solve_exact(A, b):
    """Gauss-Jordan in fractions (k <= 3): the closed form, without round-off."""
    n = len(A)
    M = [list(A[i]) + [b[i]] for i in range(n)]
    for col in range(n):
        piv = next(i for i in range(col, n) if M[i][col] != 0)
        M[col], M[piv] = M[piv], M[col]
        p = M[col][col]
        M[col] = [x / p for x in M[col]]
        for i in range(n):
            if i != col and M[i][col] != 0:
                f = M[i][col]
                M[i] = [x - f * y for x, y in zip(M[i], M[col])]
    return [M[i][n] for i in range(n)]


# ---- rendering a scene as problem text -------------------------------------------------------

def num(x: float) -> str:
    """A float as the language reads it back exactly (a leading minus is unary)."""
    r = repr(float(x))
    assert "inf" not in r and "nan" not in r
    return r


@dataclass(frozen=True)
class Render:
    phi: float = 0.0                   # rotate the frame by phi
    order: tuple[int, ...] | None = None   # permutation of the bodies
    swap: frozenset = frozenset()      # contact labels written as `b with a`
    contact_order: tuple[int, ...] | None = None
    units: str = "si"                  # si | us-slug | us-lbm | us-weight


def _mass_text(m: float, units: str) -> str:
    if units == "us-slug":
        return f"mass = {num(m / SLUG)} slug"
    if units == "us-lbm":
        return f"mass = {num(m / LBM)} lbm"
    if units == "us-weight":
        return f"weight = {num(m * G_US / LBF)} lb"
    return f"mass = {num(m)} kg"


def _len(x: float, units: str, inch: bool = False) -> str:
    if units == "si":
        return f"{num(x)} m"
    if inch:
        return f"{num(x / INCH)} in"
    return f"{num(x / FT)} ft"


def _vel(x: float, units: str, mph: bool = False) -> str:
    if units == "si":
        return f"{num(x)} m/s"
    if mph:
        return f"{num(x / MPH)} mph"
    return f"{num(x / FT)} ft/s"


def _rate(w: float, units: str) -> str:
    if units == "si":
        return f"{num(w)} rad/s"
    return f"{num(w / RPM)} rpm"


def _angle(a: float, units: str) -> str:
    if units == "si":
        return f"{num(a)} rad"
    return f"{num(math.degrees(a))} deg"


def _pt_text(p: Pt, label: str, side: str) -> str:
    if p.mode == "round":
        return p.body
    if p.mode == "end+":
        return f"{p.body}.end(+)"
    if p.mode == "end-":
        return f"{p.body}.end(-)"
    return f"q{label}{side}"


def render(scene: Scene, how: Render = Render(), finds: list[str] | None = None) -> str:
    u = how.units
    lines = ['problem "generated"']
    if u == "us-weight":
        lines.append("gravity 32.2 ft/s^2 into plane")
    order = how.order or tuple(range(len(scene.bodies)))
    bodies = [scene.bodies[i] for i in order]
    for k, b in enumerate(bodies):
        m = _mass_text(b.mass, u)
        if b.kind == "particle":
            shape = f"particle({m})"
        elif b.kind in ROUND:
            shape = f"{b.kind}({m}, radius = {_len(b.dims[0], u, inch=k % 2 == 0)})"
        elif b.kind == "rod":
            shape = f"rod({m}, length = {_len(b.dims[0], u)})"
        else:
            shape = (f"plate({m}, width = {_len(b.dims[0], u, inch=True)}, "
                     f"height = {_len(b.dims[1], u)})")
        lines.append(f"body {b.name}: {shape}")
    corder = how.contact_order or tuple(range(len(scene.contacts)))
    contacts = [scene.contacts[i] for i in corder]
    for c in contacts:
        for side, p in (("a", c.a), ("b", c.b)):
            if p is not None and p.mode == "offset":
                ox, oy = p.offset
                lines.append(f"point q{c.label}{side} = {p.body} at "
                             f"({_len(ox, u, inch=True)}, {_len(oy, u, inch=True)})")
    items = []
    for k, b in enumerate(bodies):
        v = rot(b.v, how.phi)
        items.append(f"{b.name}.v = ({_vel(v[0], u, mph=k == 1)}, {_vel(v[1], u, mph=k == 1)})")
        if b.kind != "particle":
            items.append(f"{b.name}.omega = {_rate(b.omega, u)}")
            items.append(f"{b.name}.angle = {_angle(b.angle + how.phi, u)}")
    lines.append("state 1 \"before\": " + ", ".join(items))
    lines.append("state 2 \"after\"")
    lines.append("impact 1 -> 2:")
    for c in contacts:
        a, b, theta = c.a, c.b, c.theta + how.phi
        sa, sb = "a", "b"
        if c.label in how.swap:
            assert b is not None
            a, b, theta, sa, sb = b, a, theta + math.pi, "b", "a"
        if u == "si":
            n = f"({num(math.cos(theta))}, {num(math.sin(theta))})"
        else:
            d = num(math.degrees(theta))
            n = f"(cos({d} deg), sin({d} deg))"
        target = "ground" if b is None else _pt_text(b, c.label, sb)
        lines.append(f"    contact {c.label}: {_pt_text(a, c.label, sa)} with {target} "
                     f"normal {n}: restitution {num(c.e)}, smooth")
    lines.extend(scene.extra)
    if finds is None:
        finds = []
        for b in bodies:
            finds += [f"{b.name}.vx@2", f"{b.name}.vy@2"]
            if b.kind != "particle":
                finds.append(f"{b.name}.omega@2")
        finds += [f"J_n[{c.label}]@1->2" for c in contacts]
        finds.append("T_lost@1->2")
    lines.append("find " + ", ".join(finds))
    return "\n".join(lines) + "\n"


def solved(scene: Scene, how: Render = Render()):
    """{name: (vx, vy, omega)} after the impact in the scene's own frame, {label: J_n},
    T_lost, from the program."""
    text = render(scene, how)
    try:
        ans = answers_of(text)
    except Exception as exc:  # show the problem text that failed
        raise AssertionError(f"{type(exc).__name__}: {exc}\n--- problem ---\n{text}") from exc
    post = {}
    for b in scene.bodies:
        v = rot((ans[f"{b.name}.vx@2"], ans[f"{b.name}.vy@2"]), -how.phi)
        w = ans.get(f"{b.name}.omega@2", 0.0)
        post[b.name] = (v[0], v[1], w)
    J = {c.label: ans[f"J_n[{c.label}]@1->2"] for c in scene.contacts}
    return post, J, ans["T_lost@1->2"], text


# ---- quantities computed in the test ---------------------------------------------------------

def kinetic(scene: Scene, vel) -> float:
    T = 0.0
    for b in scene.bodies:
        vx, vy, w = vel[b.name]
        T += 0.5 * b.mass * (vx * vx + vy * vy) + 0.5 * b.inertia * w * w
    return T


def before(scene: Scene):
    return {b.name: (b.v[0], b.v[1], b.omega) for b in scene.bodies}


def vel_scale(scene: Scene, *vels) -> float:
    s = 0.0
    for vel in vels:
        for b in scene.bodies:
            vx, vy, w = vel[b.name]
            s = max(s, abs(vx), abs(vy), abs(w) * b.size)
    return s or 1.0


def assert_close_velocities(scene, got, want, tol, what):
    scale = vel_scale(scene, got, want, before(scene))
    for b in scene.bodies:
        gv, wv = got[b.name], want[b.name]
        for k, comp in enumerate(("vx", "vy")):
            assert abs(gv[k] - wv[k]) <= tol * scale, \
                f"{what}: {b.name}.{comp} {gv[k]!r} vs {wv[k]!r} (scale {scale:g})"
        if b.kind != "particle":
            assert abs(gv[2] - wv[2]) * b.size <= tol * scale, \
                f"{what}: {b.name}.omega {gv[2]!r} vs {wv[2]!r} (scale {scale:g})"


def momentum_scale(scene: Scene, *vels) -> float:
    """The scene's momentum scale: sum of m |v| and of (I/size) |omega| (the impulse a
    spinning body can deliver), over the given velocity sets. Isotropic (a rotation of
    the frame mixes x and y), and the scale against which a float solution's errors
    are measured (a normwise-accurate solve makes every velocity's error a fraction of
    the scene's velocity scale, not of its own size)."""
    s = 0.0
    for vel in vels:
        for b in scene.bodies:
            vx, vy, w = vel[b.name]
            s += b.mass * math.hypot(vx, vy)
            if b.kind != "particle":
                s += b.inertia / b.size * abs(w)
    return s or 1.0


def check_conservation(scene: Scene, post, J: dict[str, float] | None = None):
    """(a) momentum laws, (b) energy never gained, (c) e = 1 conserves energy."""
    pre = before(scene)
    P = momentum_scale(scene, pre, post)
    # (a) linear momentum of the system when every contact is between two bodies
    if all(c.b is not None for c in scene.contacts):
        for k, comp in enumerate("xy"):
            p1 = sum(b.mass * pre[b.name][k] for b in scene.bodies)
            p2 = sum(b.mass * post[b.name][k] for b in scene.bodies)
            assert abs(p2 - p1) <= MOMENTUM_TOL * P, \
                f"system momentum {comp}: {p1!r} -> {p2!r} (scale {P:g})"
    # (a) a body with one smooth contact keeps its momentum along the contact's tangent,
    # and its angular momentum about the contact point
    for b in scene.bodies:
        mine = [(c, side) for c in scene.contacts for side, p in (("a", c.a), ("b", c.b))
                if p is not None and p.body == b.name]
        if len(mine) != 1:
            continue
        c, side = mine[0]
        n = normal_of(c)
        t = (-n[1], n[0])
        m = b.mass
        pt1 = m * (pre[b.name][0] * t[0] + pre[b.name][1] * t[1])
        pt2 = m * (post[b.name][0] * t[0] + post[b.name][1] * t[1])
        assert abs(pt2 - pt1) <= MOMENTUM_TOL * P, \
            f"{b.name}: momentum along the tangent {pt1!r} -> {pt2!r} (scale {P:g})"
        if b.kind != "particle":
            p = c.a if side == "a" else c.b
            r = arm(scene, p, n, 1.0 if side == "a" else -1.0)
            rq = (-r[0], -r[1])  # from the contact point to G

            h1, h2 = (b.inertia * vel[b.name][2] + m * cross(rq, vel[b.name][:2])
                      for vel in (pre, post))
            hs = (math.hypot(*rq) + b.size) * P
            assert abs(h2 - h1) <= MOMENTUM_TOL * hs, \
                f"{b.name}: angular momentum about its contact point {h1!r} -> {h2!r} " \
                f"(scale {hs:g})"
    # (b), (c) energy
    T1, T2 = kinetic(scene, pre), kinetic(scene, post)
    one_e = len({c.e for c in scene.contacts}) == 1
    if one_e or (J is not None and all(x >= 0 for x in J.values())):
        assert T2 <= T1 * (1 + ENERGY_TOL), f"energy gained: T1 = {T1!r}, T2 = {T2!r}"
    if all(c.e == 1.0 for c in scene.contacts):
        assert abs(T2 - T1) <= ENERGY_TOL * T1, f"e = 1 but T1 = {T1!r}, T2 = {T2!r}"
    return T1, T2


# ---- strategies ------------------------------------------------------------------------------

def floats(lo, hi):
    return st.floats(lo, hi, allow_nan=False, allow_infinity=False, allow_subnormal=False)


def _no_tiny(lo, hi, tiny):
    """Floats in [lo, hi], with magnitudes below `tiny` replaced by 0: velocities of
    1e-300 m/s only test underflow in the test's own arithmetic."""
    return floats(lo, hi).map(lambda x: 0.0 if abs(x) < tiny else x)


masses = st.floats(-3, 3).map(lambda x: 10.0 ** x)
sizes = st.floats(-2, 1).map(lambda x: 10.0 ** x)   # 1 cm .. 10 m
speeds = _no_tiny(-50, 50, 1e-6)
rates = _no_tiny(-20, 20, 1e-6)
fractions = _no_tiny(-1, 1, 1e-9)  # positions of contact points within a body
angles = floats(-math.pi, math.pi)
restitutions = st.one_of(st.just(1.0), st.just(0.0), floats(0, 1))


@st.composite
def bodies(draw, name: str, kinds=KINDS) -> Body:
    kind = draw(st.sampled_from(kinds))
    m = draw(masses)
    if kind == "particle":
        dims: tuple[float, ...] = ()
    elif kind == "plate":
        dims = (draw(sizes), draw(sizes))
    else:
        dims = (draw(sizes),)
    b = Body(name, kind, m, dims, v=(draw(speeds), draw(speeds)))
    if kind != "particle":
        b.angle = draw(angles)
        b.omega = draw(rates)
    return b


@st.composite
def points(draw, b: Body) -> Pt:
    if b.kind == "particle":
        return Pt(b.name, "round")
    if b.kind in ROUND:
        if draw(st.booleans()):
            return Pt(b.name, "round")
        rho = b.dims[0] * abs(draw(fractions))
        psi = draw(angles)
        return Pt(b.name, "offset", (rho * math.cos(psi), rho * math.sin(psi)))
    if b.kind == "rod":
        mode = draw(st.sampled_from(("end+", "end-", "offset")))
        if mode != "offset":
            return Pt(b.name, mode)
        return Pt(b.name, "offset", (b.dims[0] / 2 * draw(fractions), 0.0))
    w, h = b.dims
    return Pt(b.name, "offset", (w / 2 * draw(fractions), h / 2 * draw(fractions)))


def approaching(scene: Scene) -> Scene:
    """Flip each normal so that its contact is closing (u- < 0); reject grazing ones."""
    _, _, u = reference(scene)
    scale = vel_scale(scene, before(scene))
    for c, uk in zip(scene.contacts, u):
        assume(abs(uk) > 1e-6 * scale)
        if uk > 0:
            c.theta = c.theta + math.pi if c.theta <= 0 else c.theta - math.pi
    return scene


@st.composite
def scenes(draw, topology: str | None = None, same_e: bool = False) -> Scene:
    """Two- and three-body frictionless impacts.

    pair: A-B. chain: A-B, B-C. star: A-C, B-C (C strikes both). pair+ground: A-B and
    C on the ground. ground: one body on the ground.
    """
    topo = topology or draw(st.sampled_from(("pair", "chain", "star", "pair+ground", "ground")))
    n = {"pair": 2, "ground": 1}.get(topo, 3)
    bs = [draw(bodies(name)) for name in ("A", "B", "C")[:n]]
    links = {"pair": [("A", "B")], "chain": [("A", "B"), ("B", "C")],
             "star": [("A", "C"), ("B", "C")], "pair+ground": [("A", "B"), ("C", None)],
             "ground": [("A", None)]}[topo]
    scene = Scene(bs, [])
    e0 = draw(restitutions)
    for k, (a, b) in enumerate(links):
        pa = draw(points(scene.body(a)))
        pb = draw(points(scene.body(b))) if b is not None else None
        e = e0 if same_e else draw(restitutions)
        scene.contacts.append(Contact(f"c{k}", pa, pb, draw(angles), e))
    return approaching(scene)


# ---- (a) (b) (c) conservation, energy, and the independent solution --------------------------

@SETTINGS
@given(scenes(topology="pair", same_e=False))
def test_two_bodies_one_contact(scene):
    post, J, T_lost, text = solved(scene)
    T1, T2 = check_conservation(scene, post, J)
    want, lam, u = reference(scene)
    assert_close_velocities(scene, post, want, REFERENCE_TOL, "closed form")
    # the textbook closed form for one contact, written out
    c = scene.contacts[0]
    n = normal_of(c)
    A, B = scene.body(c.a.body), scene.body(c.b.body)
    ra, rb = arm(scene, c.a, n, 1.0), arm(scene, c.b, n, -1.0)
    w = 1 / A.mass + 1 / B.mass
    w += cross(ra, n) ** 2 / A.inertia if A.kind != "particle" else 0.0
    w += cross(rb, n) ** 2 / B.inertia if B.kind != "particle" else 0.0
    J_closed = -(1 + c.e) * u[0] / w
    P = momentum_scale(scene, before(scene), post)
    assert abs(J["c0"] - J_closed) <= REFERENCE_TOL * max(abs(J_closed), P), (J["c0"], J_closed)
    assert J["c0"] >= 0
    assert math.isclose(T_lost, T1 - T2, rel_tol=1e-9, abs_tol=1e-12 * T1)
    # the energy lost by one contact: (1 - e^2) u-^2 / (2 w)
    assert math.isclose(T_lost, (1 - c.e ** 2) * u[0] ** 2 / (2 * w), rel_tol=1e-9,
                        abs_tol=1e-12 * T1)


@SETTINGS
@given(scenes(topology="ground", same_e=False))
def test_one_body_on_the_ground(scene):
    post, J, T_lost, text = solved(scene)
    check_conservation(scene, post, J)
    want, lam, u = reference(scene)
    assert_close_velocities(scene, post, want, REFERENCE_TOL, "closed form")
    P = momentum_scale(scene, before(scene), post)
    assert abs(J["c0"] - lam[0]) <= REFERENCE_TOL * max(abs(lam[0]), P), (J["c0"], lam[0])


@SETTINGS
@given(st.sampled_from(("chain", "star", "pair+ground")).flatmap(
    lambda topo: scenes(topology=topo)), st.booleans())
def test_three_bodies_two_contacts(scene, one_e):
    if one_e:
        for c in scene.contacts:
            c.e = scene.contacts[0].e
    post, J, T_lost, text = solved(scene)
    T1, T2 = check_conservation(scene, post, J)
    want, lam, u = reference(scene)
    assert_close_velocities(scene, post, want, REFERENCE_TOL, "Delassus solution")
    scale = max(max(abs(x) for x in lam), momentum_scale(scene, before(scene), post))
    for c, lk in zip(scene.contacts, lam):
        assert abs(J[c.label] - lk) <= REFERENCE_TOL * scale, (c.label, J[c.label], lk)
    # Newton's law at each contact, from the answers: u+ = -e u-
    for c, uk in zip(scene.contacts, u):
        n = normal_of(c)
        ups = 0.0
        for p, s in ((c.a, 1.0), (c.b, -1.0)):
            if p is None:
                continue
            vx, vy, w = post[p.body]
            r = arm(scene, p, n, s)
            ups += s * (n[0] * vx + n[1] * vy + w * cross(r, n))
        assert abs(ups + c.e * uk) <= REFERENCE_TOL * vel_scale(scene, post, before(scene))


@FEW
@given(scenes(topology="star"))
def test_elastic_scenes_conserve_energy(scene):
    for c in scene.contacts:
        c.e = 1.0
    post, J, T_lost, text = solved(scene)
    T1, T2 = check_conservation(scene, post, J)
    assert abs(T_lost) <= 1e-9 * T1


# ---- (d) invariance --------------------------------------------------------------------------

def compare_solutions(scene, s1, s2, what):
    """Two renderings of one scene agree (to INVARIANCE_TOL), and both agree with the
    independent solution (to REFERENCE_TOL) and the conservation laws."""
    (p1, J1, L1, _), (p2, J2, L2, t2) = s1, s2
    want, _, _ = reference(scene)
    for post, J in ((p1, J1), (p2, J2)):
        assert_close_velocities(scene, post, want, REFERENCE_TOL, what + " (vs the closed form)")
        check_conservation(scene, post, J)
    scale = vel_scale(scene, p1, p2, before(scene))
    for b in scene.bodies:
        v1, v2 = p1[b.name], p2[b.name]
        sp1, sp2 = math.hypot(v1[0], v1[1]), math.hypot(v2[0], v2[1])
        assert abs(sp1 - sp2) <= INVARIANCE_TOL * scale, \
            f"{what}: {b.name} speed {sp1!r} vs {sp2!r}\n{t2}"
        if b.kind != "particle":
            assert abs(v1[2] - v2[2]) * b.size <= INVARIANCE_TOL * scale, \
                f"{what}: {b.name}.omega {v1[2]!r} vs {v2[2]!r}\n{t2}"
    assert_close_velocities(scene, p1, p2, INVARIANCE_TOL, what)
    js = max(max(abs(x) for x in J1.values()), momentum_scale(scene, before(scene), p1, p2))
    for k in J1:
        assert abs(J1[k] - J2[k]) <= INVARIANCE_TOL * js, f"{what}: J_n[{k}] {J1[k]} vs {J2[k]}"
    T1 = kinetic(scene, before(scene))
    assert abs(L1 - L2) <= INVARIANCE_TOL * T1, f"{what}: T_lost {L1} vs {L2}"


@SETTINGS
@given(scenes(), angles)
def test_rotation_of_the_frame(scene, phi):
    base = solved(scene)
    turned = solved(scene, Render(phi=phi))
    compare_solutions(scene, base, turned, f"rotated by {phi!r} rad")


@SETTINGS
@given(scenes(), st.data())
def test_order_of_bodies_and_sides_of_contacts(scene, data):
    n = len(scene.bodies)
    order = tuple(data.draw(st.permutations(range(n))))
    corder = tuple(data.draw(st.permutations(range(len(scene.contacts)))))
    swappable = [c.label for c in scene.contacts if c.b is not None]
    swap = frozenset(data.draw(st.sets(st.sampled_from(swappable))) if swappable else ())
    base = solved(scene)
    other = solved(scene, Render(order=order, swap=swap, contact_order=corder))
    compare_solutions(scene, base, other, f"order {order}, swapped {sorted(swap)}")


@SETTINGS
@given(scenes(), st.sampled_from(("us-slug", "us-lbm", "us-weight")))
def test_us_customary_units(scene, units):
    base = solved(scene)
    us = solved(scene, Render(units=units))
    compare_solutions(scene, base, us, units)


@dataclass
class Pinned:
    """A rod pinned at its end O to the ground at (X, Y), struck at Q by a particle."""

    M: float
    L: float
    mp: float
    alpha: float
    omega: float
    q: float  # Q's offset from G along the rod
    v: tuple[float, float]
    theta: float
    e: float
    s: float  # the particle's centre is at Q - s n (on the line of impact)

    def geometry(self, X, Y):
        rho = rot((self.q + self.L / 2, 0.0), self.alpha)  # O -> Q
        rG = rot((self.L / 2, 0.0), self.alpha)  # O -> G
        n = (math.cos(self.theta), math.sin(self.theta))
        P = (X + rho[0] - self.s * n[0], Y + rho[1] - self.s * n[1])
        return rho, rG, n, P

    def text(self, X, Y, phi=0.0, stated=False):
        rho, rG, n, P = self.geometry(0.0, 0.0)
        # rotate the frame about the origin, then translate
        P = rot(P, phi)
        th = self.theta + phi
        v = rot(self.v, phi)
        return "\n".join([
            'problem "pinned rod struck by a particle"',
            f"body rod: rod(mass = {num(self.M)} kg, length = {num(self.L)} m)",
            f"body p: particle(mass = {num(self.mp)} kg)",
            "point O = rod.end(-)",
            f"point Q = rod at ({num(self.q)} m, 0)",
            f"pin O to ground at ({num(X)} m, {num(Y)} m)",
            f"state 1: rod.angle = {num(self.alpha + phi)} rad, rod.omega = "
            f"{num(self.omega)} rad/s, p.v = ({num(v[0])} m/s, {num(v[1])} m/s), "
            f"p.pos = ({num(P[0] + X)} m, {num(P[1] + Y)} m)",
            "state 2",
            "impact 1 -> 2:",
            f"    contact c0: Q with p normal ({num(math.cos(th))}, {num(math.sin(th))}): "
            f"restitution {num(self.e)}, smooth",
            *(["conserve angular momentum of {rod, p} about O over 1 -> 2"] if stated else []),
            "find rod.omega@2, p.vx@2, p.vy@2, J_n[c0]@1->2, Jx[O]@1->2, Jy[O]@1->2, "
            "rod.x@1, rod.y@1, rod.vx@2, rod.vy@2, T_lost@1->2",
            ""])

    def closed_form(self):
        """Rotation about the pin: I_O = M L^2/3; one contact."""
        rho, rG, n, _ = self.geometry(0.0, 0.0)
        I_O = self.M * self.L ** 2 / 3
        vQ = (-self.omega * rho[1], self.omega * rho[0])
        u = (vQ[0] - self.v[0]) * n[0] + (vQ[1] - self.v[1]) * n[1]
        k = cross(rho, n)
        lam = -(1 + self.e) * u / (k * k / I_O + 1 / self.mp)
        w2 = self.omega + k * lam / I_O
        vp = (self.v[0] - n[0] * lam / self.mp, self.v[1] - n[1] * lam / self.mp)
        vG1 = (-self.omega * rG[1], self.omega * rG[0])
        vG2 = (-w2 * rG[1], w2 * rG[0])
        Jpin = (self.M * (vG2[0] - vG1[0]) - n[0] * lam, self.M * (vG2[1] - vG1[1]) - n[1] * lam)
        T1 = 0.5 * I_O * self.omega ** 2 + 0.5 * self.mp * (self.v[0] ** 2 + self.v[1] ** 2)
        T2 = 0.5 * I_O * w2 ** 2 + 0.5 * self.mp * (vp[0] ** 2 + vp[1] ** 2)
        return dict(w2=w2, vp=vp, lam=lam, Jpin=Jpin, u=u, T1=T1, T2=T2, vG2=vG2, rG=rG)


@st.composite
def pinned(draw):
    p = Pinned(M=draw(masses), L=draw(sizes), mp=draw(masses), alpha=draw(angles),
               omega=draw(rates), q=0.0, v=(draw(speeds), draw(speeds)), theta=draw(angles),
               e=draw(restitutions), s=draw(floats(0, 1)))
    p.q = p.L / 2 * draw(floats(-0.9, 1))
    cf = p.closed_form()
    scale = max(abs(p.omega) * p.L, math.hypot(*p.v), 1e-300)
    assume(abs(cf["u"]) > 1e-6 * scale)
    if cf["u"] > 0:
        p.theta += math.pi
    return p


offsets = floats(-1e3, 1e3)


def check_pinned(p: Pinned, dx: float, dy: float, phi: float, stated: bool = False):
    cf = p.closed_form()
    a0 = answers_of(p.text(0.0, 0.0, stated=stated))
    a1 = answers_of(p.text(dx, dy, stated=stated))
    ar = answers_of(p.text(0.0, 0.0, phi, stated=stated))
    vs = max(abs(p.omega) * p.L, math.hypot(*p.v), abs(cf["w2"]) * p.L, math.hypot(*cf["vp"]))
    # impulses against the momentum scale (J_pin is a small difference of momenta)
    js = max(abs(cf["lam"]), math.hypot(*cf["Jpin"]), p.M * abs(p.omega) * p.L / 2,
             p.M * abs(cf["w2"]) * p.L / 2, p.mp * math.hypot(*p.v), p.mp * math.hypot(*cf["vp"]))
    # the closed form
    assert abs(a0["rod.omega@2"] - cf["w2"]) * p.L <= REFERENCE_TOL * vs
    assert abs(a0["p.vx@2"] - cf["vp"][0]) <= REFERENCE_TOL * vs
    assert abs(a0["p.vy@2"] - cf["vp"][1]) <= REFERENCE_TOL * vs
    assert abs(a0["J_n[c0]@1->2"] - cf["lam"]) <= REFERENCE_TOL * js
    assert abs(a0["Jx[O]@1->2"] - cf["Jpin"][0]) <= REFERENCE_TOL * js
    assert abs(a0["Jy[O]@1->2"] - cf["Jpin"][1]) <= REFERENCE_TOL * js
    assert abs(a0["rod.x@1"] - cf["rG"][0]) <= 1e-12 * p.L
    assert abs(a0["rod.y@1"] - cf["rG"][1]) <= 1e-12 * p.L
    # energy (the pin does no work)
    assert cf["T2"] <= cf["T1"] * (1 + ENERGY_TOL)
    assert math.isclose(a0["T_lost@1->2"], cf["T1"] - cf["T2"], rel_tol=1e-9,
                        abs_tol=1e-10 * cf["T1"])
    # translation: velocities, impulses and T_lost unchanged; positions shifted
    for k in ("rod.omega@2", "p.vx@2", "p.vy@2", "rod.vx@2", "rod.vy@2"):
        f = p.L if k.startswith("rod.omega") else 1.0
        assert abs(a1[k] - a0[k]) * f <= INVARIANCE_TOL * vs, (k, a0[k], a1[k])
    for k in ("J_n[c0]@1->2", "Jx[O]@1->2", "Jy[O]@1->2"):
        assert abs(a1[k] - a0[k]) <= INVARIANCE_TOL * js, (k, a0[k], a1[k])
    assert abs(a1["rod.x@1"] - (a0["rod.x@1"] + dx)) <= 1e-12 * (abs(dx) + p.L)
    assert abs(a1["rod.y@1"] - (a0["rod.y@1"] + dy)) <= 1e-12 * (abs(dy) + p.L)
    assert abs(a1["T_lost@1->2"] - a0["T_lost@1->2"]) <= INVARIANCE_TOL * cf["T1"]
    # rotation of the frame: omega, speeds, J_n, |J_pin| unchanged; vectors turned
    assert abs(ar["rod.omega@2"] - a0["rod.omega@2"]) * p.L <= INVARIANCE_TOL * vs
    vr = rot((ar["p.vx@2"], ar["p.vy@2"]), -phi)
    assert abs(vr[0] - a0["p.vx@2"]) <= INVARIANCE_TOL * vs
    assert abs(vr[1] - a0["p.vy@2"]) <= INVARIANCE_TOL * vs
    assert abs(ar["J_n[c0]@1->2"] - a0["J_n[c0]@1->2"]) <= INVARIANCE_TOL * js
    jr = rot((ar["Jx[O]@1->2"], ar["Jy[O]@1->2"]), -phi)
    assert abs(jr[0] - a0["Jx[O]@1->2"]) <= INVARIANCE_TOL * js
    assert abs(jr[1] - a0["Jy[O]@1->2"]) <= INVARIANCE_TOL * js


@SETTINGS
@given(pinned(), offsets, offsets, angles)
def test_pinned_rod_translation_and_rotation(p, dx, dy, phi):
    """Positions are given (the pin, the particle): translating them changes only the
    positions; rotating the frame turns the vectors. Both against the closed form."""
    check_pinned(p, dx, dy, phi)



def lever_y(p: Pinned, phi: float) -> float:
    """The y-component (in a frame turned by phi) of the particle's position from O."""
    rho, rG, n, P = p.geometry(0.0, 0.0)
    return rot(P, phi)[1]


@FEW
@given(pinned(), offsets, offsets, angles)
def test_pinned_rod_with_stated_angular_momentum(p, dx, dy, phi):
    """`conserve angular momentum of {rod, p} about O` is redundant and true (the pin's
    impulse acts at O; the particle is on the line of impact): it must check out and
    change nothing, wherever the scene is placed. Scenes where the particle's lever arm
    about O is (nearly) horizontal in the file's frame hit the bug of the next tests."""
    assume(min(abs(lever_y(p, 0.0)), abs(lever_y(p, phi))) > 0.05 * p.L)
    check_pinned(p, dx, dy, phi, stated=True)


DEGENERATE = Pinned(M=1.0, L=1.0, mp=10.0, alpha=0.0, omega=0.0, q=0.0, v=(0.0, 1.0),
                    theta=1.0, e=1.0, s=0.0)


def test_degenerate_pinned_rod_without_the_stated_principle():
    """The same scene as the next test solves exactly without the redundant line..."""
    check_pinned(DEGENERATE, 0.0, 0.0, 0.0)


def test_degenerate_pinned_rod_in_a_rotated_frame():
    """...and with it, in a rotated frame: nothing is degenerate physically."""
    check_pinned(DEGENERATE, 0.0, 0.0, 0.3, stated=False)
    answers_of(DEGENERATE.text(0.0, 0.0, 0.3, stated=True))


def test_redundant_stated_principle_with_degenerate_geometry():
    check_pinned(DEGENERATE, 0.0, 0.0, 0.0, stated=True)


# ---- (e) symmetric scenes --------------------------------------------------------------------

def billiards_text(m, M, V, beta, e, phi=0.0, order="ABC"):
    nA = rot((math.cos(beta), math.sin(beta)), phi)
    nB = rot((math.cos(beta), -math.sin(beta)), phi)
    vC = rot((V, 0.0), phi)
    decl = {"A": f"body A: particle(mass = {num(m)} kg)",
            "B": f"body B: particle(mass = {num(m)} kg)",
            "C": f"body C: particle(mass = {num(M)} kg)"}
    return "\n".join([
        'problem "three billiard balls"',
        *[decl[k] for k in order],
        f"state 1: C.v = ({num(vC[0])} m/s, {num(vC[1])} m/s), A at rest, B at rest",
        "state 2",
        "impact 1 -> 2:",
        f"    contact cA: A with C normal ({num(nA[0])}, {num(nA[1])}): "
        f"restitution {num(e)}, smooth",
        f"    contact cB: B with C normal ({num(nB[0])}, {num(nB[1])}): "
        f"restitution {num(e)}, smooth",
        "find A.vx@2, A.vy@2, B.vx@2, B.vy@2, C.vx@2, C.vy@2, A.speed@2, B.speed@2, "
        "J_n[cA]@1->2, J_n[cB]@1->2, T_lost@1->2",
        ""])


@SETTINGS
@given(masses, masses, floats(0.01, 50), floats(math.radians(1), math.radians(89)),
       restitutions, angles, st.permutations("ABC"))
def test_three_billiard_balls_symmetric(m, M, V, beta, e, phi, order):
    """C (mass M) strikes A and B (mass m, at rest) symmetrically at +-beta.

    By symmetry J_A = J_B = J; C: M (v_C' - V) = -2 J cos(beta); A: m v_A' = J;
    Newton along n_A: J/m - v_C' cos(beta) = e V cos(beta), so
    J = (1 + e) V cos(beta) / (1/m + 2 cos^2(beta)/M).
    """
    a = answers_of(billiards_text(m, M, V, beta, e, phi, "".join(order)))
    c = math.cos(beta)
    J = (1 + e) * V * c / (1 / m + 2 * c * c / M)
    vC = V - 2 * J * c / M
    vA = J / m
    vs = max(V, abs(vC), vA)
    # symmetric scene, symmetric answers
    assert abs(a["A.speed@2"] - a["B.speed@2"]) <= 1e-12 * vs
    assert abs(a["J_n[cA]@1->2"] - a["J_n[cB]@1->2"]) <= 1e-12 * max(J, 1e-300)
    A2 = rot((a["A.vx@2"], a["A.vy@2"]), -phi)
    B2 = rot((a["B.vx@2"], a["B.vy@2"]), -phi)
    C2 = rot((a["C.vx@2"], a["C.vy@2"]), -phi)
    assert abs(A2[0] - B2[0]) <= 1e-12 * vs and abs(A2[1] + B2[1]) <= 1e-12 * vs
    assert abs(C2[1]) <= 1e-12 * vs
    # the closed form
    assert math.isclose(a["J_n[cA]@1->2"], J, rel_tol=REFERENCE_TOL)
    assert abs(a["A.speed@2"] - vA) <= REFERENCE_TOL * vs
    assert abs(C2[0] - vC) <= REFERENCE_TOL * vs
    # momentum and energy
    P = M * V + M * math.hypot(*C2) + m * (math.hypot(*A2) + math.hypot(*B2))
    p1x, p2x = M * V, M * C2[0] + m * (A2[0] + B2[0])
    assert abs(p2x - p1x) <= MOMENTUM_TOL * P, (p1x, p2x)
    assert abs(M * C2[1] + m * (A2[1] + B2[1])) <= MOMENTUM_TOL * P
    T1 = 0.5 * M * V * V
    T2 = 0.5 * M * (C2[0] ** 2 + C2[1] ** 2) + m * vA * vA
    assert T2 <= T1 * (1 + ENERGY_TOL)
    assert math.isclose(a["T_lost@1->2"], T1 - T2, rel_tol=1e-9, abs_tol=1e-12 * T1)
    if e == 1.0:
        assert abs(a["T_lost@1->2"]) <= 1e-12 * T1


ACCURACY_BUG = ("BUG (reported): the float block solve is only normwise accurate: in this "
                "well-conditioned block (cond 6.5) the heavy balls' small velocities (1e-5 m/s) "
                "come out with relative errors ~2e-10, so momentum is conserved only to ~1e-10 "
                "(the report's own 'momentum residuals' check shows 1.5e-10 and still says ok, "
                "and the error estimate claims relative error <= 7e-9 for every unknown)")


# Passes since the matching follows the compiled order instead of the names: the block
# holding the heavy balls' velocities no longer mixes them with C's (ACCURACY_BUG above
# still describes what a float solve of a mixed block gives).
def test_heavy_slow_bodies_keep_momentum_to_1e12():
    """Heavy A, B (1000 kg) struck by a light C (1 g) at 10 m/s, in a rotated frame."""
    m, M, V, beta, e, phi = 1000.0, 0.001, 10.0, 0.3, 1.0, -2.75
    a = answers_of(billiards_text(m, M, V, beta, e, phi))
    c = math.cos(beta)
    J = (1 + e) * V * c / (1 / m + 2 * c * c / M)
    vA, vC = J / m, V - 2 * J * c / M
    P = M * V + M * abs(vC) + 2 * m * vA
    vel = {k: rot((a[f"{k}.vx@2"], a[f"{k}.vy@2"]), -phi) for k in "ABC"}
    p1 = (M * V, 0.0)
    p2 = tuple(M * vel["C"][i] + m * (vel["A"][i] + vel["B"][i]) for i in (0, 1))
    assert abs(p2[0] - p1[0]) <= MOMENTUM_TOL * P and abs(p2[1]) <= MOMENTUM_TOL * P, (p1, p2)
    assert math.isclose(vel["A"][0], vA * c, rel_tol=1e-12), (vel["A"][0], vA * c)


def test_billiards_seed_numbers():
    """The lecture notes' numbers: e = 1, equal masses, 30 deg: v_C' = -V/5,
    v_A' = v_B' = 2 sqrt(3)/5 V."""
    a = answers_of(billiards_text(0.17, 0.17, 5.0, math.radians(30), 1.0))
    assert math.isclose(a["C.vx@2"], -1.0, rel_tol=1e-12)
    assert math.isclose(a["A.speed@2"], 2 * math.sqrt(3) / 5 * 5.0, rel_tol=1e-12)
    # C stops when e = 2/3
    a = answers_of(billiards_text(0.17, 0.17, 2.0, math.radians(30), 2 / 3))
    assert abs(a["C.vx@2"]) <= 1e-12 * 2.0


@SETTINGS
@given(masses, masses, sizes, floats(0.05, 1), angles, speeds, speeds,
       speeds, floats(math.radians(5), math.radians(175)), restitutions)
def test_rod_struck_symmetrically_at_both_ends(M, m, L, frac, alpha, a_t, b_p, c_p, gamma, e):
    """A rod (angle alpha) struck at +-q by two equal particles whose motion is the
    mirror image of each other in the rod's perpendicular bisector: the rod cannot
    turn, it cannot move along itself, and the particles leave with equal speeds."""
    q = frac * L / 2
    t = (math.cos(alpha), math.sin(alpha))
    p = (-t[1], t[0])

    def world(x_t, y_p):
        return (x_t * t[0] + y_p * p[0], x_t * t[1] + y_p * p[1])

    # normals on the rod at +q and -q (mirror images); make the contacts closing
    u = -a_t * math.cos(gamma) + (c_p - b_p) * math.sin(gamma)
    assume(abs(u) > 1e-6 * max(abs(a_t), abs(b_p), abs(c_p), 1e-300))
    s = 1.0 if u < 0 else -1.0
    n1 = world(s * math.cos(gamma), s * math.sin(gamma))
    n2 = world(-s * math.cos(gamma), s * math.sin(gamma))
    v1, v2, vr = world(a_t, b_p), world(-a_t, b_p), world(0.0, c_p)
    text = "\n".join([
        'problem "rod struck symmetrically"',
        f"body rod: rod(mass = {num(M)} kg, length = {num(L)} m)",
        f"body p1: particle(mass = {num(m)} kg)",
        f"body p2: particle(mass = {num(m)} kg)",
        f"point Q1 = rod at ({num(q)} m, 0)",
        f"point Q2 = rod at ({num(-q)} m, 0)",
        f"state 1: rod.angle = {num(alpha)} rad, rod.omega = 0, rod.v = ({num(vr[0])} m/s, "
        f"{num(vr[1])} m/s), p1.v = ({num(v1[0])} m/s, {num(v1[1])} m/s), "
        f"p2.v = ({num(v2[0])} m/s, {num(v2[1])} m/s)",
        "state 2",
        "impact 1 -> 2:",
        f"    contact c1: Q1 with p1 normal ({num(n1[0])}, {num(n1[1])}): restitution {num(e)}, "
        "smooth",
        f"    contact c2: Q2 with p2 normal ({num(n2[0])}, {num(n2[1])}): restitution {num(e)}, "
        "smooth",
        "find rod.omega@2, rod.vx@2, rod.vy@2, p1.speed@2, p2.speed@2, J_n[c1]@1->2, "
        "J_n[c2]@1->2, p1.vx@2, p1.vy@2",
        ""])
    a = answers_of(text)
    vs = max(abs(a_t), abs(b_p), abs(c_p), a["p1.speed@2"], 1e-300)
    assert abs(a["rod.omega@2"]) * L <= 1e-12 * vs
    along = a["rod.vx@2"] * t[0] + a["rod.vy@2"] * t[1]
    assert abs(along) <= 1e-12 * vs
    assert abs(a["p1.speed@2"] - a["p2.speed@2"]) <= 1e-12 * vs
    # an impulse is measured against the one that changes u by the velocity scale
    npp = n1[0] * p[0] + n1[1] * p[1]
    w = 1 / m + 2 * npp * npp / M
    assert abs(a["J_n[c1]@1->2"] - a["J_n[c2]@1->2"]) <= 1e-12 * vs / w
    # closed form: the rod translates along p; each contact sees
    # w = 1/m + 2 (n.p)^2 / M ... by symmetry, J on the rod totals 2 J (n.p) along p.
    # Newton at c1: u+ = -e u-, with u = (v_rod - v_p1) . n1
    uq = (vr[0] - v1[0]) * n1[0] + (vr[1] - v1[1]) * n1[1]
    J = -(1 + e) * uq / w
    assert abs(a["J_n[c1]@1->2"] - J) <= REFERENCE_TOL * vs / w
    vp1 = (v1[0] - n1[0] * J / m, v1[1] - n1[1] * J / m)
    assert abs(a["p1.vx@2"] - vp1[0]) <= REFERENCE_TOL * vs
    assert abs(a["p1.vy@2"] - vp1[1]) <= REFERENCE_TOL * vs
