"""The `simulate from S:` block, resolved against the scene (names, units, SI values).

Built through the scene builder's public resolving interface (`value`, `vector`,
`point`, `body_named`, `contact`, `state_qty_dim`, `damper`), so a misspelt point or a
force in the wrong unit is reported exactly as it is everywhere else in the language.
This module does not import `scene` (scene calls it; no import cycle).
"""
from __future__ import annotations

from .. import syntax as S
from ..diagnostics import ProblemError, did_you_mean
from ..elements.kinds import Clause, JointKind
from ..records import field, record
from ..source import Span
from ..units import FORCE, MOMENT, TIME

DAMPING = (1, 0, -1)  # N*s/m = kg/s


@record(frozen=True)
class Until:
    kind: str  # time | qty | apex | impacts
    span: Span
    value: float = 0.0
    body: str | None = None
    qty: str | None = None


@record
class SimSpec:
    start: str
    span: Span
    untils: list = field(default_factory=list)  # Until
    contacts: list = field(default_factory=list)  # scene.Contact (normal None: from geometry)
    forces: list = field(default_factory=list)  # (F, PointOn, Span)
    moments: list = field(default_factory=list)  # (M, body, Span)
    dampers: list = field(default_factory=list)  # scene.Joint with `stiffness` = damping
    bearings: list = field(default_factory=list)  # (pin label, torque, Span)


def build_simulation(b, s: S.SimulateDecl, states) -> SimSpec:
    """Resolve one `simulate` block with the scene builder `b` (its public interface)."""
    if s.start not in states:
        raise ProblemError(f"state {s.start} is not declared" + did_you_mean(s.start, states),
                           s.start_span, code="name", notes=[f"add a line `state {s.start}`"])
    spec = SimSpec(s.start, s.span)
    pins = {j.label for j in b.joints if j.kind == JointKind.PIN}
    for c in s.clauses:
        if isinstance(c, S.Until):
            spec.untils.append(_until(b, c))
        elif isinstance(c, S.Contact):
            spec.contacts.append(b.contact(c, "simulate"))
        elif isinstance(c, S.Joint):
            a, p = b.fixed_point(c.a), b.fixed_point(c.b)
            if a.body is None and p.body is not None:
                a, p = p, a
            if a.body is None or a.body == p.body:
                raise ProblemError("a damper joins two different bodies (or a body and the "
                                   "ground)", c.span, code="name")
            damping = b.value(c.stiffness, DAMPING, "a damping coefficient")
            if damping < 0:
                raise ProblemError("a damping coefficient cannot be negative", c.stiffness.span,
                                   code="number")
            label = c.label or (a.name if p.body is None else f"{a.name}-{p.name}")
            spec.dampers.append(b.damper(label, a, p, c.span, damping))
        elif c.kind == Clause.FORCE:
            spec.forces.append((b.vector(c.value, FORCE, "a force"), b.fixed_point(c.point),
                                c.span))
        elif c.kind == Clause.MOMENT:
            body = b.body_named(c.names[0], c.span)
            spec.moments.append((b.value(c.value, MOMENT, "a moment"), body.name, c.span))
        elif c.kind == Clause.BEARING_TORQUE:
            if c.names[0] not in pins:
                raise ProblemError(f"no pin called '{c.names[0]}'" + did_you_mean(c.names[0], pins),
                                   c.span, code="name",
                                   notes=["name a pin: `pin bearing: disk to rod.A`"])
            torque = b.value(c.value, MOMENT, "a friction torque")
            if torque < 0:
                raise ProblemError("a friction torque cannot be negative", c.value.span,
                                   code="number")
            spec.bearings.append((c.names[0], torque, c.span))
    if not spec.untils:
        raise ProblemError("a simulation needs a stop condition: `until t = 5 s`, "
                           "`until BODY.omega = 0`, `until apex` or `until 3 impacts`", s.span,
                           code="name")
    return spec


def _until(b, c: S.Until) -> Until:
    left = c.left
    if c.right is None:
        if isinstance(left, S.Ref) and left.name == "apex" and not (left.member or left.at or
                                                                      left.index):
            return Until("apex", c.span)
        if isinstance(left, S.Num) and left.unit in ("impact", "impacts"):
            n = left.value
            if not n < 2**53 or n < 1 or n != int(n):  # inf and nan too
                raise ProblemError("the number of impacts must be a whole number, at least 1",
                                   left.span, code="number")
            return Until("impacts", c.span, float(n))
    elif isinstance(left, S.Ref) and not (left.index or left.at):
        if left.name == "t" and left.member is None:
            t = b.value(c.right, TIME, "a stop time")
            if t <= 0:
                raise ProblemError("a stop time must be positive", c.right.span, code="number")
            return Until("time", c.span, t)
        if left.member is not None:
            body = b.body_named(left.name, left.span)
            dim = b.state_qty_dim(body, left.member, left.span)
            v = b.value(c.right, dim, f"{left.name}.{left.member}")
            return Until("qty", c.span, v, body.name, left.member)
    raise ProblemError("`until` takes `t = 5 s`, `BODY.QTY = value` (x, y, angle, vx, vy, "
                       "omega), `apex` or `N impacts`", c.span, code="name")

