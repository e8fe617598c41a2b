"""Compile helper: the principles a textbook states for a system during an impact.

In: one impact (its impulse sources, the impulses each body received with their arms).
Out: `SystemLaw`s for the report: the linear momentum of the bodies together along each
direction free of external impulse (sum of momenta; `(m_A + m_B) v'` when they move
together), and angular impulse-momentum about a fixed pin with I_O = I_G + m d^2. They
follow from the body-by-body rows the solve uses, so they are shown, not solved.
"""
from __future__ import annotations

import math

from .elements.keys import state_key
from .elements.kinds import JointKind
from .expr import V2, ZERO, Add, Const, E, Known, Mul, Var, add, add_all, mul, neg
from .records import field, record
from .tree_template import plain_leaves, template


@record
class SystemLaw:
    kind: str  # "linear" | "pin"
    principle: str
    why: str
    lhs: E
    rhs: E
    bodies: tuple = ()
    # linear: the form when the bodies move together afterwards, `(m_A + m_B)*vx'@2`,
    # and the velocity each stand-in name is (the first body's), for the numbers
    locked: E | None = None
    alias: dict = field(default_factory=dict)
    # pin: the parallel-axis step, I_O = I_G + m d^2 (numbers in SI)
    parallel: dict | None = None
    # pin-system: per side (before, after) the pinned body's w and the other bodies'
    # (m, r x v about O, I w)
    parts: tuple = ()


def _external(sources, members: set) -> list:
    return [s for s in sources if (s.bodies[0] in members or s.bodies[1] in members)
            and not (s.bodies[0] in members and s.bodies[1] in members)]


_AXES = {(1.0, 0.0): "x", (0.0, 1.0): "y"}


def _words(d) -> str:
    w = _AXES.get((abs(d[0]), abs(d[1])))
    return w if w is not None else f"({d[0]:.4g}, {d[1]:.4g})"


def system_laws(c, t, sources, moved: list[str], hits: dict) -> list[SystemLaw]:
    """The system statements of impact `t` (compiler `c`); `hits[body]` lists the
    (point, arm from G, impulse, torque) of every impulse the body received."""
    out: list[SystemLaw] = []
    i, j = t.before, t.after
    if len(moved) >= 2:
        out += _linear(c, sources, moved, i, j)
    out += _pins(c, t, moved, hits, i, j)
    out += _pinned_system(c, t, sources, moved, i, j)
    return out


def _pin_to_ground(c, t):
    """(joint, the body's point) of each fixed pin acting in t on a rigid body."""
    for jt in c.joints:
        if jt.kind != JointKind.PIN or not jt.acts_in(c, t):
            continue
        ends = [p for p in (jt.a, jt.b) if p.body is not None]
        if len(ends) != 1:
            continue
        p = ends[0]
        body = c.scene.bodies[p.body]
        if body.is_particle or p.located_by is not None or p.round_contact:
            continue
        yield jt, p


def _known_here(c, body: str, qty: str, sid: str) -> bool:
    """Whether a state quantity is given or already an unknown of the system."""
    key = c._find((body, qty, sid))
    return c._given(key) is not None or state_key(*key) in c.unknowns


def _pinned_system(c, t, sources, moved, i, j) -> list[SystemLaw]:
    """Bodies together with a body pinned to the ground at O, every external impulse at
    O: their angular momentum about O is conserved, the pinned body's as I_O w."""
    if len(moved) < 2 or any(s.before == t.before and s.after == t.after and
                             hasattr(s, "about") for s in c.scene.stated):
        return []
    ext = _external(sources, set(moved))
    out = []
    for jt, p in _pin_to_ground(c, t):
        b = p.body
        if b not in moved or not ext or any(s.torque_only or s.point != p.name for s in ext):
            continue
        body = c.scene.bodies[b]
        d = math.hypot(*p.offset)
        I_O = body.inertia + body.mass * d * d
        others = [o for o in moved if o != b]
        parts, sides = [], []
        fixed = jt.b if jt.b.body is None else jt.a  # the pin's ground point: O itself
        # positions do not change during an impact: the state before gives every arm
        # (asking for the state after would make new unknowns of its positions)
        if not all(_known_here(c, o, q, i) for o in others for q in ("x", "y")):
            continue  # a position no row asks for: stating this would make it an unknown
        rp = c.point_position(fixed, i)
        arms = {o: c.pos(o, i) - rp for o in others}
        for sid in (i, j):
            side = []
            for o in others:
                ob = c.scene.bodies[o]
                r = arms[o]
                spin = None if ob.is_particle else mul(Known(f"I_{o}", ob.inertia),
                                                       c.sv(o, "omega", sid))
                side.append((c.mass(o, i), r.cross(c.vel(o, sid)), spin))
            parts.append((c.sv(b, "omega", sid), side))
            H = mul(Known(f"I_{p.name}", I_O), c.sv(b, "omega", sid))
            for m, rxv, spin in side:
                H = add(H, mul(m, rxv))
                if spin is not None:
                    H = add(H, spin)
            sides.append(H)
        names = ", ".join(moved)
        out.append(SystemLaw("pin-system", f"angular momentum of {{{names}}} about the pin "
                             f"{p.name}: H_{p.name}{i} = H_{p.name}{j}",
                             f"every external impulse on the system acts at {p.name}",
                             sides[0], sides[1], tuple(moved),
                             parallel=dict(body=b, point=p.name, I_G=body.inertia,
                                           m=body.mass, d=d, I_O=I_O), parts=tuple(parts)))
    return out


_FEW = 8  # bodies of an impact whose sums of momenta replay a template (tree_template)


def _momenta(c, moved, i, j, dirs) -> list[tuple]:
    """For each direction d: the sums of m v along d before and after, the total mass
    after and the first body's velocity along d (the stand-in's value), as the general
    loop folds them; replayed from a template per directions and number of bodies when
    the leaves allow. Each body's mass and velocities are asked for once."""
    leaves = []
    for sid in (i, j):
        for b in moved:
            v = c.vel(b, sid)
            leaves += (c.mass(b, sid), v.x, v.y)
    k = len(moved)
    f = None
    if _plain_dirs(dirs) and plain_leaves(*leaves):
        f = template(("momenta", k) + tuple((d[0], math.copysign(1.0, d[0]), d[1],
                                              math.copysign(1.0, d[1])) for d in dirs),
                     _momenta_builder, len(leaves), k, dirs)
    return (f or _momenta_builder(k, dirs))(*leaves)


def _plain_dirs(dirs) -> bool:
    """Directions of plain floats (a template keys on them and keeps their numbers)."""
    return all(type(d[0]) is float and type(d[1]) is float for d in dirs)


def _many(c, moved, i, j, dirs) -> list[tuple] | None:
    """`_momenta` for many bodies: each term m (v . d) replayed from a template per
    direction (None: a leaf that folds, or no template; the general loop then)."""
    sides = []
    for sid in (i, j):
        side = []
        for b in moved:
            v = c.vel(b, sid)
            side.append((c.mass(b, sid), v.x, v.y))
        sides.append(side)
    if not _plain_dirs(dirs):
        return None  # a sweep's traced direction: its numbers are no template's
    for side in sides:
        for leaves in side:
            if not plain_leaves(*leaves):
                return None
    # each body's terms along every direction, before and after, from one replay
    f = template(("terms",) + tuple((d[0], math.copysign(1.0, d[0]), d[1],
                                     math.copysign(1.0, d[1])) for d in dirs),
                 _terms_builder, 6, dirs)
    if f is None:
        return None
    per = [f(*a, *b) for a, b in zip(*sides)]
    out = []
    for n, d in enumerate(dirs):
        lhs = add_all([p[2 * n] for p in per])
        rhs = add_all([p[2 * n + 1] for p in per])
        after = sides[1]
        total = Add(tuple(m for m, _, _ in after))
        _, vx, vy = after[0]
        out.append((lhs, rhs, total, V2(vx, vy).dot(V2(Const(d[0]), Const(d[1])))))
    return out


def _terms_builder(dirs):
    def terms(m1, x1, y1, m2, x2, y2):
        out = []
        for d in dirs:
            dv = V2(Const(d[0]), Const(d[1]))
            out += (mul(m1, V2(x1, y1).dot(dv)), mul(m2, V2(x2, y2).dot(dv)))
        return tuple(out)
    return terms


def _momenta_builder(k: int, dirs):
    def sums(*leaves):
        out = []
        before, after = leaves[:3 * k], leaves[3 * k:]
        for d in dirs:
            dv = V2(Const(d[0]), Const(d[1]))
            lhs, rhs = [add_all([mul(side[3 * n], V2(side[3 * n + 1], side[3 * n + 2]).dot(dv))
                                 for n in range(k)]) for side in (before, after)]
            total = Add(tuple(after[3 * n] for n in range(k)))
            out.append((lhs, rhs, total, V2(after[1], after[2]).dot(dv)))
        return tuple(out)
    return sums


def _linear(c, sources, moved, i, j) -> list[SystemLaw]:
    head = linear_head(sources, moved)
    if head is None:
        return []
    dirs, why = head
    names = ", ".join(moved)
    principles = [f"linear momentum of {{{names}}} along {_words(d)}: "
                  "sum of m v before = sum of m v after" for d in dirs]
    return linear_laws(c, moved, i, j, dirs, why, principles)


def linear_head(sources, moved) -> tuple | None:
    """The directions free of external impulse for the bodies `moved` together, and why
    (None: no direction is free); texts only, no tree (why_texts plans them per kind)."""
    members = set(moved)
    ext = [s for s in _external(sources, members) if not s.torque_only]
    if not ext:
        return [(1.0, 0.0), (0.0, 1.0)], "no external impulse acts on the system"
    ds = [s.direction for s in ext]
    if any(d is None for d in ds) or any(abs(ds[0][0] * d[1] - ds[0][1] * d[0]) > 1e-12
                                         for d in ds):
        return None
    dirs = [(-ds[0][1], ds[0][0])]
    if dirs[0][0] < 0 or (dirs[0][0] == 0 and dirs[0][1] < 0):
        dirs = [(-dirs[0][0], -dirs[0][1])]
    why = f"the external impulses ({', '.join(sorted({s.what for s in ext}))}) act only " \
          f"along ({ds[0][0]:.4g}, {ds[0][1]:.4g})"
    return dirs, why


def linear_laws(c, moved, i, j, dirs, why, principles, rows=None) -> list[SystemLaw]:
    """The linear-momentum laws along `dirs` (linear_head's), with their texts (and the
    sums of momenta, when the caller replayed `_momenta_builder` itself)."""
    out = []
    if rows is None:
        rows = _momenta(c, moved, i, j, dirs) if len(moved) <= _FEW else \
            _many(c, moved, i, j, dirs)
    for n, d in enumerate(dirs):
        if rows is not None:
            lhs, rhs, total, first = rows[n]
        else:
            dv = V2(Const(d[0]), Const(d[1]))
            lhs = add_all([mul(c.mass(b, i), c.vel(b, i).dot(dv)) for b in moved])
            rhs = add_all([mul(c.mass(b, j), c.vel(b, j).dot(dv)) for b in moved])
            total = Add(tuple(c.mass(b, j) for b in moved))
            first = c.vel(moved[0], j).dot(dv)
        comp = _words(d)
        tag = comp if comp in ("x", "y") else "n"
        stand_in = f"v{tag}'@{j}"
        alias = {stand_in: first.name} if isinstance(first, Var) else {}
        out.append(SystemLaw("linear", principles[n], why, lhs, rhs,
                             tuple(moved), Mul((total, Var(stand_in))) if alias else None,
                             alias))
    return out


def _pins(c, t, moved, hits, i, j) -> list[SystemLaw]:
    """A body turning about a fixed pin O: I_O (w2 - w1) = the moments about O of the
    other impulses on it (the pin's own impulse has no moment about O)."""
    out = []
    for jt, p in _pin_to_ground(c, t):
        b = p.body
        body = c.scene.bodies[b]
        if b not in moved:
            continue
        d = math.hypot(*p.offset)
        m = body.mass
        I_O = body.inertia + m * d * d
        rO = c.arm(p, i)
        moments: list[E] = []
        for q, r, J, torque in hits.get(b, ()):
            if q is p:
                continue  # the pin's impulse acts at O
            rel = V2(add(r.x, neg(rO.x)), add(r.y, neg(rO.y)))
            mo = rel.cross(J)
            if torque is not None:
                mo = add(mo, torque)
            moments.append(mo)
        w1, w2 = c.sv(b, "omega", i), c.sv(b, "omega", j)
        lhs = mul(Known(f"I_{p.name}", I_O), add(w2, neg(w1)))
        rhs = add_all(moments) if moments else ZERO
        out.append(SystemLaw("pin", f"angular impulse-momentum of {b} about the pin "
                             f"{p.name}: I_{p.name}*(w{j} - w{i}) = sum of the moments about "
                             f"{p.name}", f"{b} turns about the fixed pin {p.name}, whose "
                             "impulse has no moment about it", lhs, rhs, (b,),
                             parallel=dict(body=b, point=p.name, I_G=body.inertia, m=m, d=d,
                                           I_O=I_O)))
    return out
