"""Compile helper: the principles a textbook states for a system during an impact.

In: one impact (its impulse sources, the impulses each body received with their arms).
Out: `SystemLaw`s for the report: the linear momentum of the bodies together along each
direction free of external impulse (sum of momenta; `(m_A + m_B) v'` when they move
together), and angular impulse-momentum about a fixed pin with I_O = I_G + m d^2. They
follow from the body-by-body rows the solve uses, so they are shown, not solved.
"""
from __future__ import annotations

import math
from dataclasses import field

from .elements.kinds import JointKind
from .expr import V2, ZERO, Add, Const, E, Known, Mul, Var, add, add_all, mul, neg
from .records import record


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


def _external(sources, members: set) -> list:
    return [s for s in sources if (s.bodies[0] in members or s.bodies[1] in members)
            and not (s.bodies[0] in members and s.bodies[1] in members)]


def _words(d) -> str:
    return {(1.0, 0.0): "x", (0.0, 1.0): "y"}.get((abs(d[0]), abs(d[1])),
                                                   f"({d[0]:.4g}, {d[1]:.4g})")


def system_laws(c, t, sources, moved: list[str], hits: dict) -> list[SystemLaw]:
    """The system statements of impact `t` (compiler `c`); `hits[body]` lists the
    (point, arm from G, impulse, torque) of every impulse the body received."""
    out: list[SystemLaw] = []
    i, j = t.before, t.after
    if len(moved) >= 2:
        out += _linear(c, sources, moved, i, j)
    out += _pins(c, t, moved, hits, i, j)
    return out


def _linear(c, sources, moved, i, j) -> list[SystemLaw]:
    members = set(moved)
    ext = [s for s in _external(sources, members) if not s.torque_only]
    if not ext:
        dirs = [(1.0, 0.0), (0.0, 1.0)]
        why = "no external impulse acts on the system"
    else:
        ds = [s.direction for s in ext]
        if any(d is None for d in ds) or any(abs(ds[0][0] * d[1] - ds[0][1] * d[0]) > 1e-12
                                             for d in ds):
            return []
        dirs = [(-ds[0][1], ds[0][0])]
        if dirs[0][0] < 0 or (dirs[0][0] == 0 and dirs[0][1] < 0):
            dirs = [(-dirs[0][0], -dirs[0][1])]
        why = f"the external impulses ({', '.join(sorted({s.what for s in ext}))}) act only " \
              f"along ({ds[0][0]:.4g}, {ds[0][1]:.4g})"
    names = ", ".join(moved)
    out = []
    for d in dirs:
        dv = V2(Const(d[0]), Const(d[1]))
        lhs = add_all([mul(c.mass(b, i), c.vel(b, i).dot(dv)) for b in moved])
        rhs = add_all([mul(c.mass(b, j), c.vel(b, j).dot(dv)) for b in moved])
        comp = _words(d)
        tag = comp if comp in ("x", "y") else "n"
        stand_in = f"v{tag}'@{j}"
        total = Add(tuple(c.mass(b, j) for b in moved))
        first = c.vel(moved[0], j).dot(dv)
        alias = {stand_in: first.name} if isinstance(first, Var) else {}
        out.append(SystemLaw("linear", f"linear momentum of {{{names}}} along {comp}: "
                             "sum of m v before = sum of m v after", why, lhs, rhs,
                             tuple(moved), Mul((total, Var(stand_in))) if alias else None,
                             alias))
    return out


def _pins(c, t, moved, hits, i, j) -> list[SystemLaw]:
    """A body turning about a fixed pin O: I_O (w2 - w1) = the moments about O of the
    other impulses on it (the pin's own impulse has no moment about O)."""
    out = []
    for jt in c.joints:
        if jt.kind != JointKind.PIN or not jt.acts_in(c, t):
            continue
        ends = [p for p in (jt.a, jt.b) if p.body is not None]
        if len(ends) != 1:
            continue
        p = ends[0]
        b = p.body
        body = c.scene.bodies[b]
        if b not in moved or body.is_particle or p.located_by is not None or p.round_contact:
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
