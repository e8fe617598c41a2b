"""A state's full pose and velocity, solved from what the file gives for it.

The state's own constraints (pins, welds, links, rolling) fill in what is not given,
with the same compiler and solver that `solve` uses. A position that nothing fixes is
taken as 0 (angles first, then x and y), since only relative geometry matters; a
velocity that nothing fixes is an error, because the motion would be a guess.
"""
from __future__ import annotations

from ..diagnostics import Collector, ProblemError
from ..elements.kinds import JointKind
from ..scene import Scene, StateSpec

POSITIONS = ("angle", "x", "y")
VELOCITIES = ("vx", "vy", "omega")


def _reduced(scene: Scene, spec: StateSpec) -> Scene:
    joints = [j for j in scene.joints if j.kind != JointKind.SPRING and j.from_state is None]
    return Scene(title=scene.title, gravity=scene.gravity, g=scene.g, constants=scene.constants,
                 user_unknowns=scene.user_unknowns, bodies=scene.bodies, points=scene.points,
                 surfaces=scene.surfaces, joints=joints, states={spec.id: spec}, transitions=[],
                 stated=[], equations=[], finds=[], notes=Collector(),
                 gravity_span=scene.gravity_span)


def _given_directly(scene: Scene, spec: StateSpec, need_velocities: bool) -> dict | None:
    """The values without solving, when the state gives them all, or gives the angle (and
    omega) of a body whose only joint is a pin to the ground (the pin places it)."""
    from .model import rot

    joints = [j for j in scene.joints if j.kind != JointKind.SPRING and j.from_state is None]
    if spec.rolls:
        return None
    out = {}
    for name, b in scene.bodies.items():
        g = {q: v for (body, q), (v, _) in spec.givens.items() if body == name}
        mine = [j for j in joints if name in (j.a.body, j.b.body)]
        if len(mine) == 1 and mine[0].kind == JointKind.PIN and mine[0].b.body is None and \
                not b.is_particle and "angle" in g and \
                (not need_velocities or "omega" in g) and not ({"x", "y", "vx", "vy"} & set(g)):
            j, th = mine[0], g["angle"]
            rx, ry = rot(th, (-j.a.offset[0], -j.a.offset[1]))  # G - O
            w = g.get("omega", 0.0)
            out[name] = {"angle": th, "x": j.b.offset[0] + rx, "y": j.b.offset[1] + ry,
                         "vx": -w * ry, "vy": w * rx, "omega": w}
            continue
        if mine:
            return None
        need = ("x", "y") + (() if b.is_particle else ("angle",))
        if need_velocities:
            need += ("vx", "vy") + (() if b.is_particle else ("omega",))
        if not all(q in g for q in need):
            return None
        out[name] = {q: g.get(q, 0.0) for q in POSITIONS + VELOCITIES}
    return out


def state_values(scene: Scene, sid: str, need_velocities: bool, where=None) -> dict:
    """{body: {qty: value}} for state `sid`: x, y, angle (and vx, vy, omega)."""
    from ..solve import solve_scene

    base = scene.states[sid]
    direct = _given_directly(scene, base, need_velocities)
    if direct is not None:
        return direct
    spec = StateSpec(id=base.id, label=base.label, span=base.span, givens=dict(base.givens),
                     hints={}, rolls=list(base.rolls))
    for _ in range(4):
        sol = solve_scene(_reduced(scene, spec))
        values = dict(sol.values)
        missing = []
        for name, b in scene.bodies.items():
            for q in POSITIONS + (VELOCITIES if need_velocities else ()):
                if b.is_particle and q in ("angle", "omega"):
                    continue
                if (name, q) not in spec.givens and f"{name}.{q}@{sid}" not in values:
                    missing.append((name, q))
        if not missing:
            break
        angles = [m for m in missing if m[1] == "angle"]
        places = angles or [m for m in missing if m[1] in POSITIONS]
        if not places:
            names = ", ".join(f"{b}.{q}@{sid}" for b, q in missing)
            raise ProblemError(f"the simulation starts from state {sid} but {names} "
                               f"{'is' if len(missing) == 1 else 'are'} not known there",
                               where or base.span, code="under-determined",
                               notes=[f"give {'it' if len(missing) == 1 else 'them'} in state "
                                      f"{sid} (or `BODY at rest`)"])
        for b, q in places:
            spec.givens[(b, q)] = (0.0, base.span)
    out: dict[str, dict[str, float]] = {}
    for name, b in scene.bodies.items():
        d = {}
        for q in POSITIONS + VELOCITIES:
            if (name, q) in spec.givens:
                d[q] = spec.givens[(name, q)][0]
            elif f"{name}.{q}@{sid}" in values:
                d[q] = values[f"{name}.{q}@{sid}"]
            else:
                d[q] = 0.0
        out[name] = d
    return out
