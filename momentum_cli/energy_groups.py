"""Compile helper: which bodies each work-energy balance of an energy phase covers.

In: the scene, its joint elements and the phase. Out: groups of body names, one balance
each. `of {rod}, {ball}` names them; otherwise bodies fall into groups that nothing ties
together during the phase (a joint, a spring, a user equation between their states, a
contact of an impact between the same two states), and
`free ball` puts a body in a group of its own.
"""
from __future__ import annotations

from . import syntax as S


def energy_groups(scene, joints, holds_at, t) -> list[tuple[str, ...]]:
    """The groups of bodies whose energies are balanced separately in energy phase t."""
    if t.groups:
        return list(t.groups)
    names = [b for b in scene.bodies if b not in t.free]
    parent = {b: b for b in names}

    def root(b: str) -> str:
        while parent[b] != b:
            parent[b] = parent[parent[b]]
            b = parent[b]
        return b

    def tie(bodies) -> None:
        inside = [b for b in bodies if b in parent]
        for b in inside[1:]:
            parent[root(b)] = root(inside[0])

    for jt in joints:
        if holds_at(jt.from_state, t.before) or holds_at(jt.from_state, t.after):
            tie(jt.bodies())
    for ue in scene.equations:
        tie(_bodies_at(scene, (ue.left, ue.right), {t.before, t.after}))
    for tr in scene.transitions:  # an impact (or interval) between the same two states:
        if (tr.before, tr.after) == (t.before, t.after) and tr is not t:  # its contacts tie
            for c in tr.contacts:
                tie([c.a.body] + ([c.b.body] if c.b is not None else []))
    groups: dict[str, list[str]] = {}
    for b in names:
        groups.setdefault(root(b), []).append(b)
    return [tuple(g) for g in groups.values()] + [(b,) for b in t.free]


def split_joints(groups, joints, holds_at, t) -> list[str]:
    """Warnings for joints that `of {...}` groups cut (its work is left out of both)."""
    where = {b: k for k, g in enumerate(groups) for b in g}
    out = []
    for jt in joints:
        if not (holds_at(jt.from_state, t.before) or holds_at(jt.from_state, t.after)):
            continue
        a, b = jt.bodies()
        if a is not None and b is not None and (a in where or b in where) and \
                where.get(a) != where.get(b):
            what = f"{jt.kind} {jt.label}" if jt.label else f"the {jt.kind}"
            out.append(f"{what} joins {a} and {b}, which this energy phase "
                       "balances apart: the work it does on each is left out")
    return out


def _bodies_at(scene, nodes, states: set[str]) -> list[str]:
    """The bodies whose quantities at these states the expressions mention."""
    out: list[str] = []
    todo = list(nodes)
    while todo:
        n = todo.pop()
        if isinstance(n, S.Ref):
            if n.at and n.at[-1] in states or n.at and n.at[0] in states:
                body = n.name if n.name in scene.bodies else getattr(
                    scene.points.get(n.name), "body", None)
                if body is not None and body not in out:
                    out.append(body)
        elif isinstance(n, S.BinOp):
            todo += [n.left, n.right]
        elif isinstance(n, (S.Neg, S.Mag)):
            todo.append(n.arg)
        elif isinstance(n, S.Call):
            todo += list(n.args)
        elif isinstance(n, S.VecLit):
            todo += [n.x, n.y]
    return out
