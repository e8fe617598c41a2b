"""The simulated scene: bodies and their coordinates, effects, constraints and contacts.

A body pinned to the ground at one point (and nothing else to the ground) moves with
one coordinate, its angle, so a pendulum is integrated as one equation rather than
three with two constraint forces; every other body is free (x, y, angle; particles
x, y) and the remaining joints and persistent contacts enter as constraint forces.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

from ..diagnostics import ProblemError
from ..elements.contacts import ContactElement
from ..elements.geometry import centre, rot  # noqa: F401  (the simulation's names for them)
from ..elements.joints import JointElement, joint_element
from ..elements.kinds import JointKind
from ..scene import Contact, PointOn, Scene


@dataclass
class SimBody:
    name: str
    index: int  # first coordinate in q (and u)
    size: int  # 1 (pinned), 2 (particle), 3 (free rigid body)
    mass: float
    inertia: float
    particle: bool
    radius: float | None
    pivot: tuple[float, float] | None = None  # world point of a ground pin
    pin_offset: tuple[float, float] = (0.0, 0.0)  # the pin's point from G, body frame


@dataclass
class Watch:
    """A contact the simulation watches: it may impact, rest, roll or slide."""

    label: str
    a: PointOn
    b: PointOn | None  # another body's point, or None: a fixed plane
    normal: tuple[float, float] | None  # fixed normal (planes, given); None: from shapes
    ra: float  # radius at a's point (a round body's centre), else 0
    rb: float
    spec: Contact  # restitution, mode, mu, source line
    plane: tuple[float, float] = (0.0, 0.0)  # a point of the plane
    gap0: float = 0.0  # subtracted from the raw gap (surfaces placed by a transition)
    element: ContactElement | None = None  # its laws (restitution, tangential)


@dataclass
class Model:
    scene: Scene
    bodies: list[SimBody]
    by_name: dict[str, SimBody]
    n: int
    gravity: tuple[float, float] | None
    joints: list[JointElement]  # pins, welds, links not reduced into coordinates
    springs: list[JointElement]
    dampers: list[JointElement]
    forces: list  # (F, PointOn, Span)
    moments: list  # (M, body, Span)
    bearings: dict[str, float]  # pin label -> friction torque
    watches: list[Watch]
    length_scale: float = 1.0
    scene_joints: list[JointElement] = field(default_factory=list)  # every joint of the file


def build_model(scene: Scene, spec) -> Model:
    """Coordinates for each body, and the effects the file declares (nothing else)."""
    elements = [joint_element(j, scene) for j in scene.joints]
    ground_pins: dict[str, list[JointElement]] = {}
    for j in elements:
        if j.kind is JointKind.PIN and j.b.body is None and j.from_state is None:
            ground_pins.setdefault(j.a.body, []).append(j)
    bodies: list[SimBody] = []
    joints: list[JointElement] = []
    reduced: set[str] = set()
    k = 0
    for name, b in scene.bodies.items():
        pins = ground_pins.get(name, [])
        if len(pins) == 1 and not b.is_particle:
            j = pins[0]
            sb = SimBody(name, k, 1, b.mass, b.inertia, False, b.radius, j.b.offset, j.a.offset)
            reduced.add(j.label)
        else:
            size = 2 if b.is_particle else 3
            sb = SimBody(name, k, size, b.mass, b.inertia, b.is_particle, b.radius)
        bodies.append(sb)
        k += sb.size
    for j in elements:
        if j.constrains and j.label not in reduced:
            if j.from_state is not None:
                raise ProblemError(f"'{j.label}' holds from state {j.from_state}: a simulation "
                                   "takes joints that hold throughout", j.span, code="name")
            joints.append(j)
    by_name = {b.name: b for b in bodies}
    bearings = {label: torque for label, torque, _ in spec.bearings}
    model = Model(scene, bodies, by_name, k, scene.gravity, joints,
                  [j for j in elements if j.kind is JointKind.SPRING],
                  [joint_element(d, scene) for d in spec.dampers],
                  list(spec.forces), list(spec.moments), bearings, [])
    model.length_scale = _length_scale(scene)
    model.scene_joints = elements
    return model


def _length_scale(scene: Scene) -> float:
    sizes = [x for b in scene.bodies.values() for x in (b.radius, b.length) if x]
    sizes += [math.hypot(*p.offset) for p in scene.points.values() if p.body]
    sizes = [s for s in sizes if s > 0]
    return max(sizes) if sizes else 1.0


def watch_for(model: Model, c: Contact, placed_at: dict | None) -> Watch:
    """A watched contact. `placed_at` (a transition's start-state poses) places a ground or
    an unlocated surface where the contact is in that state: the file says it touches there."""
    scene = model.scene
    element = ContactElement(c)
    element.restitution.sim_restitution()  # a law a simulation cannot apply is refused here
    ra = _radius(scene, c.a)
    if c.b is not None:
        w = Watch(c.label, c.a, c.b, c.normal, ra, _radius(scene, c.b), c, element=element)
        if c.normal is not None and placed_at is not None:
            w.ra = w.rb = 0.0  # the gap along the normal is measured from where it touches
    else:
        sf = scene.surfaces.get(c.surface) if c.surface else None
        w = Watch(c.label, c.a, None, c.normal, ra, 0.0, c,
                  sf.at if sf is not None else (0.0, 0.0), element=element)
        located = sf is not None and sf.located
        if located or placed_at is None:
            return w
    if placed_at is not None:
        w.gap0 = raw_gap(model, w, placed_at)
    return w


def _radius(scene: Scene, p: PointOn) -> float:
    if p.body is None or not p.round_contact:
        return 0.0
    return scene.bodies[p.body].radius or 0.0


def raw_gap(model: Model, w: Watch, pose: dict) -> float:
    """The gap before subtracting `gap0`, from poses {body: (x, y, angle)}."""
    pa = centre(pose, w.a)
    if w.b is None:
        n = w.normal
        return (pa[0] - w.plane[0]) * n[0] + (pa[1] - w.plane[1]) * n[1] - w.ra
    pb = centre(pose, w.b)
    if w.normal is not None:
        n = w.normal
        return (pa[0] - pb[0]) * n[0] + (pa[1] - pb[1]) * n[1] - w.ra - w.rb
    return math.hypot(pa[0] - pb[0], pa[1] - pb[1]) - w.ra - w.rb
