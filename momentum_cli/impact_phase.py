"""Compile helper: a whole impact of particles at simple contacts, without the phase layers.

In: an impact whose only actors are contacts that impact_contacts.fits, every body it moves
a particle, no joint, flow or end condition. Out: what compile._impulse_phase makes for it
(unknowns, rows, sources, losses, TransitionInfo), in its order: a few bodies' impact
replayed whole from one plan per kind (trees, texts as format strings; why_texts.py),
many contacts (a chain) each from its kind's template.
"""
from __future__ import annotations

from collections import defaultdict
from itertools import islice
from math import copysign

from . import impact_contacts, system_laws, tree_template, why_texts
from .elements.base import ImpulseSource
from .elements.keys import impulse_key, parameter_key
from .elements.kinds import Component, KeyKind, TransitionKind
from .expr import NEG_ONE, V2, Add, Const, Known, Mul, Var, add, add_all, mul, neg
from .impact_contacts import ZERO_V2
from .system_laws import _momenta_builder, _plain_dirs, linear_head, linear_laws
from .tree_template import template
from .units import IMPULSE, si_label
from .why_texts import compiled, kind, linear_formats, linear_texts, values, why_formats, \
    why_lines

ENABLED = True  # tests switch it off to compare with compile._impulse_phase
FRESH = True  # off: every repeat of a row's principle printed and compared (compile.eq)
TEMPLATE = True  # the whole impact from one template per kind (off: contact by contact)
_FEW = system_laws._FEW  # bodies of an impact replayed whole (the momenta's template)
_NAMED = (Var, Known)
_JN = Component.JN
_E = Component.E
_IMPACT = TransitionKind.IMPACT
_IMPACT_WORD = str(_IMPACT)
_IMPULSE_UNIT = si_label(IMPULSE)
_PLANS: dict = {}  # whole-impact kind -> _plan's answer (a few kinds: bounded below)
_LIMIT = 512
_KINDS = 0  # plans made so far in this process (each plan's number)


def fits(comp, t) -> bool:
    """Whether impact t takes this path (see the module's docstring)."""
    if not ENABLED or t.kind is not _IMPACT or comp.joints or comp.flows is not None:
        return False
    if t.bearing_friction or t.stops or t.stops_relative or t.rolls or t.forces or \
            t.moments or t.duration_expr is not None:
        return False
    # with none of those (and no joint), the bodies it moves are its contacts' bodies,
    # each a particle if every contact fits
    bodies = comp.scene.bodies
    fit = impact_contacts.fits
    for c in t.contacts:
        if not fit(c, bodies):
            return False
    return True


def stamp(comp, t, key: str) -> None:
    """compile._impulse_phase for an impact that `fits`: replayed whole from its kind's
    template when it has few bodies, else contact by contact."""
    if TEMPLATE and t.contacts and t.before != t.after and len(comp._busy[key]) <= _FEW:
        return _replay(comp, t, key)
    i, j = t.before, t.after
    group = f"{t.kind} {i} -> {j}"
    lin: dict = defaultdict(list)
    applied: list = []
    sources: list = []
    contacts_info: list = []
    _contacts(comp, t, key, i, j, group, lin, applied, sources, contacts_info)
    moved = comp._moved(key)
    tracks, mass, eq, span = comp._tracks, comp.mass, comp.eq, t.span
    declared = comp.flows is None  # mass's memo holds the mass (no burn: as declared)
    bp, eqs, Equation = comp._by_principle, comp.equations, comp.Equation
    for b in moved:
        tr = tracks[b]
        v1, v2 = tr.vel[i], tr.vel[j]  # what vel remembered in _contacts
        m = tr.mass if declared else None
        if m is None:
            m = mass(b, i)
        Js = lin[b]
        named = type(m) in _NAMED
        for comp_, a1, a2, rhs in (("x", v1.x, v2.x, add_all([J.x for J in Js])),
                                   ("y", v1.y, v2.y, add_all([J.y for J in Js]))):
            if named and type(a1) in _NAMED and type(a2) in _NAMED:
                lhs = _m_diff(m, a2, a1)
            else:
                lhs = mul(m, add(a2, neg(a1)))
            p = f"linear impulse-momentum {comp_}: {b}"
            if bp is not None and "|" not in p and p not in bp:
                # what eq does with a principle seen for the first time, inline
                e = bp[p] = Equation(lhs, rhs, p, group, span)
                e.index = len(eqs)
                eqs.append(e)
            else:
                eq(lhs, rhs, p, group, span)
                bp = comp._by_principle  # None from a principle with a `|` on
    comp.sources[key] = sources
    why = why_lines(comp, sources, moved)
    energy = (comp._kinetic(i, moved), comp._kinetic(j, moved))
    texts = linear_texts(sources, moved) if len(moved) >= 2 else None
    laws = linear_laws(comp, moved, i, j, *texts) if texts is not None else []
    comp.transitions.append(comp.TransitionInfo(t.kind, key, i, j, span, why, contacts_info,
                                                energy, tuple(moved), laws, applied))


_new = object.__new__


def _m_diff(m, a2, a1) -> Mul:
    """`Mul((m, Add((a2, Mul((NEG_ONE, a1))))))`, its nodes made by object.__new__ and
    their slots, as their __init__ would (one a body and component of a big impact)."""
    d = _new(Mul)
    d.factors = (NEG_ONE, a1)
    s = _new(Add)
    s.terms = (a2, d)
    out = _new(Mul)
    out.factors = (m, s)
    return out


def _contacts(comp, t, key, i, j, group, lin, applied, sources, contacts_info) -> None:
    """impact_contacts.stamp for each contact of t, its calls inlined (an impact of
    10^4 contacts: a chain), each contact's trees replayed from its kind's template."""
    bodies = comp.scene.bodies
    vel, after, unknowns = comp.vel, comp.moved_vel, comp.unknowns
    Unknown, Applied, Equation = comp.Unknown, comp.Applied, comp.Equation
    bp = comp._by_principle
    eqs = comp.equations
    losses = comp.losses.setdefault(key, []) if t.contacts else None
    kinds: dict = {}  # contact kind -> its trees' function (this impact's few kinds)
    for c in t.contacts:
        label = c.label
        kn = impulse_key(_JN, label, key)
        u = unknowns.get(kn)
        if u is None:
            u = unknowns[kn] = Unknown(kn, IMPULSE, _IMPULSE_UNIT, KeyKind.IMPULSE)
        Jn = Var(kn)
        u.hints.append((">", 0.0, c.span))
        e = c.restitution
        pa, pb = c.a, c.b
        a = pa.body
        E_ = Known(parameter_key(_E, label), e)
        n = c.normal
        n0, n1 = n
        # the unknowns in the order the element makes them: J_n, then v_a, v_b before, after
        # (in this order: the columns')
        if pb is not None:
            b = pb.body
            va1, vb1, va2, vb2 = vel(a, i), vel(b, i), after(a, j), after(b, j)
            leaves = (Jn, va1.x, va1.y, vb1.x, vb1.y, va2.x, va2.y, vb2.x, vb2.y, E_)
        else:
            b = None
            va1, va2 = vel(a, i), after(a, j)
            leaves = (Jn, va1.x, va1.y, va2.x, va2.y, E_)
        ck = (n0, copysign(1.0, n0), n1, copysign(1.0, n1), e, copysign(1.0, e), b is not None)
        f = kinds.get(ck)
        if f is None:
            f = kinds[ck] = template(("contact",) + ck, impact_contacts._builder, len(leaves),
                                     n0, n1, e, pb) or impact_contacts._builder(n0, n1, e, pb)
        for x in leaves:
            if type(x) not in _NAMED:
                f = impact_contacts._builder(n0, n1, e, pb)  # leaves that fold
                break
        J, Jb, vn1, vn2, loss, rhs = f(*leaves)
        what = f"contact {label}"
        body_a = bodies[a]
        r = body_a.radius
        arm = V2(Const(-1.0 * r * n0), Const(-1.0 * r * n1)) if pa.round_contact and r \
            else ZERO_V2
        applied.append(Applied(a, pa, J, None, arm, what))
        lin[a].append(J)
        if b is not None:
            r = bodies[b].radius
            arm = V2(Const(1.0 * r * n0), Const(1.0 * r * n1)) if pb.round_contact and r \
                else ZERO_V2
            applied.append(Applied(b, pb, Jb, None, arm, what))
            lin[b].append(Jb)
        where = f"{label}'s contact point" if pa.round_contact and body_a.radius else pa.name
        sources.append(ImpulseSource((a, b), where, n, False, what))
        losses.append(loss)
        p = f"restitution at {label} (Newton)"
        if bp is not None and p not in bp and "|" not in p:
            row = bp[p] = Equation(vn2, rhs, p, group, c.span)
            row.index = len(eqs)
            eqs.append(row)
        else:
            comp.eq(vn2, rhs, p, group, c.span)
            bp = comp._by_principle
        contacts_info.append((label, vn1, vn2))


def _replay(comp, t, key: str) -> None:
    """The impact from one generated function of its leaves per kind (tree_template): the
    contacts' trees, the impulse-momentum rows, the kinetic energies before and after and
    the sums of momenta of its laws; the unknowns made in the element's order."""
    i, j = t.before, t.after
    bodies = comp.scene.bodies
    moved = comp._moved(key)
    index = {b: k for k, b in enumerate(moved)}
    unknowns, Unknown = comp.unknowns, comp.Unknown
    vel, after = comp.vel, comp.moved_vel
    leaves: list = []
    shape: list = []
    sources: list = []
    contacts = t.contacts
    made = len(unknowns)
    for c in contacts:
        label = c.label
        kn = impulse_key(_JN, label, key)
        u = unknowns.get(kn)  # comp.unknown, inline
        if u is None:
            u = unknowns[kn] = Unknown(kn, IMPULSE, _IMPULSE_UNIT, KeyKind.IMPULSE)
        Jn = Var(kn)
        u.hints.append((">", 0.0, c.span))
        pa, pb = c.a, c.b
        a = pa.body
        body_a = bodies[a]
        if pb is not None:  # the state unknowns in the order the element makes them
            b = pb.body
            vel(a, i)  # made if new, in this order
            vel(b, i)
            after(a, j)
            after(b, j)
            rb = bodies[b].radius if pb.round_contact and bodies[b].radius else None
        else:
            vel(a, i)
            after(a, j)
            rb = None
        e = c.restitution
        leaves += (Jn, Known(parameter_key(_E, label), e))
        n0, n1 = c.normal
        ra = body_a.radius if pa.round_contact and body_a.radius else None
        shape.append((index[a], -1 if pb is None else index[pb.body], n0, copysign(1.0, n0),
                      n1, copysign(1.0, n1), e, copysign(1.0, e), ra, rb))
        where = f"{label}'s contact point" if ra is not None else pa.name
        sources.append(ImpulseSource((a, pb.body if pb is not None else None), where,
                                     c.normal, False, f"contact {label}"))
    mass = comp.mass
    declared = comp.flows is None  # mass's memo holds the mass (no burn: as declared)
    tracks = comp._tracks
    trs = [tracks[b] for b in moved]  # each body's record: what vel remembered just now
    for b, tr in zip(moved, trs):
        vels = tr.vel
        v1, v2 = vels[i], vels[j]
        m = tr.mass if declared else None
        leaves += (mass(b, i) if m is None else m, v1.x, v1.y, v2.x, v2.y)
    plain = True
    for x in leaves:
        if type(x) not in _NAMED:
            plain = False
            break
    named = plain  # the rows are m*(v2 - v1) of these leaves, unfolded
    # the kinetic energies: the sums and each body's term already made are leaves
    names = tuple(moved)
    Ts = comp._T
    memo = []
    for sid in (i, j):
        hit = Ts.get((sid, names))
        if hit is not None:
            memo.append(True)
            leaves.append(hit)
            continue
        memo.append(False)
        for tr in trs:
            hit = tr.T.get(sid)
            if hit is None:
                memo.append(False)
            else:
                memo.append(True)
                leaves.append(hit[0])
                plain = plain and type(hit[0]) is Mul
    if len(sources) == 1:
        classes = None
    else:  # which points and names are equal, and the names' sort order (why_texts)
        points: dict = {}
        whats: dict = {}
        classes = (tuple(points.setdefault(s.point, k) for k, s in enumerate(sources)),
                   tuple(whats.setdefault(s.what, k) for k, s in enumerate(sources)))
        classes += (tuple(whats[w] for w in sorted(whats)),)
    pkey = (tuple(shape), len(moved), tuple(memo), plain, classes, why_texts.ENABLED,
            tree_template.ENABLED)
    plan = _PLANS.get(pkey)
    if plan is None:
        plan = _plan(comp, sources, moved, pkey)
        if len(_PLANS) < _LIMIT:
            _PLANS[pkey] = plan
    trees, dirs, why_fn, law_fn, kind_id = plan
    out = trees(*leaves)
    # the outputs in the order _impulse_phase makes them
    group = f"{_IMPACT_WORD} {i} -> {j}"  # f"{t.kind} ...", without the enum's __str__
    eq = comp.eq
    applied = []
    losses = comp.losses.setdefault(key, [])
    contacts_info = []
    Applied = comp.Applied
    pos = 0
    for n, c in enumerate(contacts):
        J, Jb, vn1, vn2, loss, rhs, arm_a, arm_b = out[pos:pos + 8]
        pos += 8
        pa, pb = c.a, c.b
        what = sources[n].what
        applied.append(Applied(pa.body, pa, J, None, arm_a, what))
        if pb is not None:
            applied.append(Applied(pb.body, pb, Jb, None, arm_b, what))
        losses.append(loss)
        eq(vn2, rhs, f"restitution at {c.label} (Newton)", group, c.span)
        contacts_info.append((c.label, vn1, vn2))
    span = t.span
    bp = comp._by_principle
    eqs = comp.equations
    Equation = comp.Equation
    # the unknowns this impact made: a row naming one repeats no earlier row (its text
    # holds a name no earlier tree has), so its principle's repeats need no texts
    made = len(unknowns) - made if named and FRESH else 0
    fresh = None  # their names, when a principle repeats
    Fresh = comp.Fresh
    for b, tr in zip(moved, trs):
        lx, rx, ly, ry = out[pos:pos + 4]
        pos += 4
        v2 = tr.vel[j]
        for lhs, rhs, p, x in ((lx, rx, f"linear impulse-momentum x: {b}", v2.x),
                               (ly, ry, f"linear impulse-momentum y: {b}", v2.y)):
            if bp is not None and "|" not in p:
                same = bp.get(p)
                if same is None:
                    # what eq does with a principle seen for the first time, inline
                    e = bp[p] = Equation(lhs, rhs, p, group, span)
                else:
                    if made and fresh is None:
                        fresh = set(islice(reversed(unknowns), made))
                    if not made or type(x) is not Var or x.name not in fresh:
                        eq(lhs, rhs, p, group, span)
                        continue
                    e = Equation(lhs, rhs, p, group, span)
                    if type(same) is Fresh:
                        same.append(e)
                    else:
                        bp[p] = Fresh((same, e))
                e.index = len(eqs)
                eqs.append(e)
            else:
                eq(lhs, rhs, p, group, span)
                bp = comp._by_principle  # None from a principle with a `|` on
    comp.sources[key] = sources
    vals = None
    if why_fn is not None:
        vals = values(sources, moved)
        why = why_fn(vals)
    else:
        why = comp._why(sources, None, moved)
    energy = []
    flags = iter(memo)
    for sid in (i, j):
        if next(flags):
            energy.append(out[pos])
            pos += 1
            continue
        for tr in trs:
            if not next(flags):
                tr.T[sid] = (out[pos],)
            pos += 1
        energy.append(Ts.setdefault((sid, names), out[pos]))
        pos += 1
    if dirs is None:
        laws = []
    elif law_fn is not None:
        if vals is None:
            vals = values(sources, moved)
        texts = law_fn(vals)
        laws = linear_laws(comp, moved, i, j, dirs, texts[0], texts[1:], rows=out[pos])
    else:
        texts = linear_texts(sources, moved, None)
        laws = linear_laws(comp, moved, i, j, *texts, rows=out[pos])
    comp.transitions.append(comp.TransitionInfo(t.kind, key, i, j, span, why, contacts_info,
                                                tuple(energy), names, laws, applied, kind_id))


def _plan(comp, sources, moved, pkey) -> tuple:
    """What every impact of this kind shares: the function of its leaves making its
    trees, the directions of its laws, and its texts as format strings (None: made
    directly each time)."""
    shape, nb, memo, plain = pkey[:4]
    head = linear_head(sources, moved) if nb >= 2 else None
    dirs = None if head is None else head[0]
    args = (shape, nb, memo, dirs)
    f = None
    if plain and (dirs is None or _plain_dirs(dirs)):
        f = template(("impact", shape, nb, memo, None if dirs is None else tuple(
            (d[0], copysign(1.0, d[0]), d[1], copysign(1.0, d[1])) for d in dirs)),
            _builder, sum(2 for _ in shape) + 5 * nb + _memo_leaves(memo, nb), *args)
    got = kind(sources, moved)
    why_fmts = None if got is None else why_formats(comp, sources, moved, got)
    law_fmts = None
    if dirs is not None and got is not None:
        law_fmts = linear_formats(sources, moved, got)
    # the texts as functions of the values (law_fmts: its why, then each principle)
    why_fn = None if why_fmts is None else compiled(why_fmts)
    law_fn = None if not law_fmts else compiled([law_fmts[1]] + law_fmts[2])
    if why_fmts is not None and why_fn is None:
        why_fn = lambda vals: [f.format(*vals) for f in why_fmts]  # noqa: E731
    if law_fmts and law_fn is None:
        law_fn = lambda vals: [f.format(*vals) for f in [law_fmts[1]] + law_fmts[2]]  # noqa: E731
    global _KINDS
    _KINDS += 1  # a new number per plan made: equal numbers, one pkey (see TransitionInfo)
    return (f or _builder(*args), dirs, why_fn, law_fn, _KINDS)


def _memo_leaves(memo, nb: int) -> int:
    """How many made-before terms of T are leaves (see _replay)."""
    n = 0
    flags = iter(memo)
    for _ in (0, 1):
        if next(flags):
            n += 1
            continue
        for _ in range(nb):
            n += bool(next(flags))
    return n


def _builder(shape, nb: int, memo, dirs):
    """The impact's trees from its leaves (see _replay), as the element, the rows,
    _body_kinetic and _momenta_builder fold them."""
    contact = [impact_contacts._builder(n0, n1, e, None if ib < 0 else True)
               for _ia, ib, n0, _s0, n1, _s1, e, _se, _ra, _rb in shape]
    nc = len(shape)

    def trees(*leaves):
        bl = leaves[2 * nc:2 * nc + 5 * nb]  # m, v1x, v1y, v2x, v2y of each body
        extra = list(leaves[2 * nc + 5 * nb:])
        out = []
        lin: list = [[] for _ in range(nb)]
        for n, (ia, ib, n0, _s0, n1, _s1, e, _se, ra, rb) in enumerate(shape):
            Jn, E_ = leaves[2 * n], leaves[2 * n + 1]
            a = bl[5 * ia:5 * ia + 5]
            if ib >= 0:
                b = bl[5 * ib:5 * ib + 5]
                J, Jb, vn1, vn2, loss, rhs = contact[n](Jn, a[1], a[2], b[1], b[2], a[3], a[4],
                                                        b[3], b[4], E_)
            else:
                J, Jb, vn1, vn2, loss, rhs = contact[n](Jn, a[1], a[2], a[3], a[4], E_)
            arm_a = ZERO_V2 if ra is None else V2(Const(-1.0 * ra * n0), Const(-1.0 * ra * n1))
            arm_b = None
            lin[ia].append(J)
            if ib >= 0:
                arm_b = ZERO_V2 if rb is None else V2(Const(1.0 * rb * n0), Const(1.0 * rb * n1))
                lin[ib].append(Jb)
            out += (J, Jb, vn1, vn2, loss, rhs, arm_a, arm_b)
        for k in range(nb):
            m, a1x, a1y, a2x, a2y = bl[5 * k:5 * k + 5]
            Js = lin[k]
            for a1, a2, rhs in ((a1x, a2x, add_all([J.x for J in Js])),
                                (a1y, a2y, add_all([J.y for J in Js]))):
                if type(m) in _NAMED and type(a1) in _NAMED and type(a2) in _NAMED:
                    lhs = Mul((m, Add((a2, Mul((NEG_ONE, a1))))))
                else:
                    lhs = mul(m, add(a2, neg(a1)))
                out += (lhs, rhs)
        flags = iter(memo)
        for s in (0, 1):
            if next(flags):
                out.append(extra.pop(0))  # the sum, made before
                continue
            terms = []
            for k in range(nb):
                if next(flags):
                    term = extra.pop(0)  # the body's term, made before
                else:
                    m, vx, vy = bl[5 * k], bl[5 * k + 1 + 2 * s], bl[5 * k + 2 + 2 * s]
                    if type(vx) in _NAMED and type(vy) in _NAMED and type(m) in _NAMED:
                        term = Mul((Const(0.5), m, Add((Mul((vx, vx)), Mul((vy, vy))))))
                    else:
                        term = mul(Const(0.5), mul(m, V2(vx, vy).dot(V2(vx, vy))))
                terms.append(term)
                out.append(term)
            out.append(add_all(terms))
        if dirs is not None:
            side = [[], []]
            for k in range(nb):
                m = bl[5 * k]
                side[0] += (m, bl[5 * k + 1], bl[5 * k + 2])
                side[1] += (m, bl[5 * k + 3], bl[5 * k + 4])
            out.append(_momenta_builder(nb, dirs)(*side[0], *side[1]))
        return tuple(out)
    return trees
