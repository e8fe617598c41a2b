"""An impact during a simulation, resolved by the same impulse solver as `solve`.

The moment of contact becomes a two-state scene (`state 1` fully given, `state 2`
unknown) with an `impact 1 -> 2` whose contacts sit where the bodies touch; the
compiler writes impulse-momentum, restitution and friction for it exactly as for a
file (the same contact and joint elements), and the solver picks the friction regime.
"""
from __future__ import annotations

from ..diagnostics import Collector
from ..elements.keys import state_key
from ..elements.kinds import TransitionKind
from ..scene import Contact, PointOn, Scene, StateSpec, TransitionSpec
from .dynamics import Frame
from .model import Model, Watch, rot

IMPACT = "1->2"


def _givens(model: Model, frame: Frame, span) -> dict:
    givens = {}
    for b in model.bodies:
        x, y, th = frame.pose[b.name]
        vx, vy, w = frame.twist[b.name]
        if b.size == 1:  # the pin fixes the rest
            items = {"angle": th, "omega": w}
        elif b.particle:
            items = {"x": x, "y": y, "vx": vx, "vy": vy}
        else:
            items = {"x": x, "y": y, "angle": th, "vx": vx, "vy": vy, "omega": w}
        for q, v in items.items():
            givens[(b.name, q)] = (v, span)
    return givens


def _contact(frame: Frame, w: Watch, geometry) -> Contact:
    gap, n, c, ra, rb = geometry
    th = frame.pose[w.a.body][2]
    a = PointOn(w.a.body, rot(-th, ra), w.a.name, w.a.span)
    b = None
    if rb is not None:
        b = PointOn(w.b.body, rot(-frame.pose[w.b.body][2], rb), w.b.name, w.b.span)
    s = w.spec
    return Contact(label=w.label, span=s.span, a=a, b=b, normal=n,
                   restitution=w.element.restitution.sim_restitution(),
                   restitution_unknown=False, mode=s.mode, mu=s.mu, slip=None, surface=None)


def resolve(model: Model, frame: Frame, hits: list) -> tuple[dict, dict, dict]:
    """Velocities just after, impulses, and friction regimes, for contacts `hits`
    [(watch, geometry)] that close at once."""
    from ..solve import solve_scene

    scene = model.scene
    span = hits[0][0].spec.span
    before = StateSpec(id="1", label="before", span=span, givens=_givens(model, frame, span))
    after = StateSpec(id="2", label="after", span=span)
    impact = TransitionSpec(kind=TransitionKind.IMPACT, before="1", after="2", span=span,
                            contacts=[_contact(frame, w, g) for w, g in hits])
    sub = Scene(title=scene.title, gravity=scene.gravity, g=scene.g, constants=scene.constants,
                user_unknowns=scene.user_unknowns, bodies=scene.bodies, points=scene.points,
                surfaces=scene.surfaces,
                joints=[j.record for j in model.scene_joints if j.impulsive],
                states={"1": before, "2": after}, transitions=[impact], stated=[],
                equations=[], finds=[], notes=Collector(), gravity_span=scene.gravity_span)
    sol = solve_scene(sub, solve_all=True)
    v = sol.values
    out = {}
    for b in model.bodies:
        old = frame.twist[b.name]
        out[b.name] = tuple(v.get(state_key(b.name, q, "2"), old[k])
                            for k, q in enumerate(("vx", "vy", "omega")))
    impulses = {k.local: v[k] for k in sol.system.unknowns
                if getattr(k, "transition", None) == IMPACT and k in v}
    return out, impulses, dict(sol.regimes)
