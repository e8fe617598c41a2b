"""Principles a student states (part of `compile`): conservation of linear momentum
along a direction, of angular momentum about a point, restitution along a line.

Each is checked against the declared scene first: if an external impulse acts along
the direction (or has a moment about the point) during that transition, the report
says so and the statement is not used. A statement that holds is added as a stated
equation, which the analysis matches last, so a redundant one becomes a check.
"""
from __future__ import annotations

from .elements.kinds import EquationKind
from .expr import V2, ZERO, Const, E, add, mul
from .scene import PointOn, StatedAngular, StatedMomentum, StatedRestitution
from .source import Span


def external(s, members: set) -> bool:
    """An impulse source external to a group of bodies: one side in it, the other not."""
    return (s.bodies[0] in members) is not (s.bodies[1] in members)


class PrinciplesMixin:
    """`_Compiler` methods for stated principles."""

    def _stated(self, s) -> None:
        key = f"{s.before}->{s.after}"
        group = "stated principles"
        sources = self.sources.get(key)
        if isinstance(s, StatedMomentum):
            d = V2(Const(s.direction[0]), Const(s.direction[1]))
            lhs = rhs = ZERO
            for b in s.bodies:
                lhs = add(lhs, mul(self.mass(b, s.before), self.vel(b, s.before).dot(d)))
                rhs = add(rhs, mul(self.mass(b, s.after), self.vel(b, s.after).dot(d)))
            principle = f"conservation of linear momentum along {s.axis_text} of " \
                        f"{{{', '.join(s.bodies)}}} (stated)"
            if sources is not None:
                members = set(s.bodies)
                bad = [x for x in sources if external(x, members) and not x.torque_only and
                       (x.direction is None or
                        abs(x.direction[0] * s.direction[0] + x.direction[1] * s.direction[1])
                        > 1e-12)]
                if bad:
                    self._invalid(s.span, f"linear momentum of {{{', '.join(s.bodies)}}} along "
                                  f"{s.axis_text} is not conserved over {key}: "
                                  f"{bad[0].what} gives an external impulse along it")
                    return
            self.eq(lhs, rhs, principle, group, s.span, EquationKind.STATED)
        elif isinstance(s, StatedAngular):
            lhs = self._angular_momentum(s.bodies, s.about, s.before)
            rhs = self._angular_momentum(s.bodies, s.about, s.after)
            if sources is not None:
                members = set(s.bodies)
                bad = [x for x in sources if external(x, members)
                       and (x.torque_only or x.point != s.about.name)]
                if bad:
                    self._invalid(s.span, f"angular momentum of {{{', '.join(s.bodies)}}} about "
                                  f"{s.about.name} is not conserved over {key}: "
                                  f"{bad[0].what} has a moment about it")
                    return
            self.eq(lhs, rhs, f"conservation of angular momentum of {{{', '.join(s.bodies)}}} "
                    f"about {s.about.name} (stated)", group, s.span, EquationKind.STATED)
        elif isinstance(s, StatedRestitution):
            n = V2(Const(s.along[0]), Const(s.along[1]))

            def rel(sid):
                va = self.point_velocity(s.a, sid)
                vb = self.point_velocity(s.b, sid) if s.b is not None else V2(ZERO, ZERO)
                return (va - vb).dot(n)

            self.eq(rel(s.after), mul(Const(-s.value), rel(s.before)),
                    f"restitution along the line of impact (stated, e = {s.value:g})", group,
                    s.span, EquationKind.STATED)

    def _invalid(self, span: Span, message: str) -> None:
        self.invalid.append((span, message))
        self.notes.warn(message + "; the stated principle is not used", span,
                        code="principle-does-not-hold")

    def _angular_momentum(self, bodies, about: PointOn, sid: str) -> E:
        H: E = ZERO
        rp = None
        for b in bodies:
            body = self.scene.bodies[b]
            m = self.mass(b, sid)
            if about.body == b:
                r = -self.arm(about, sid)
            else:
                if rp is None:
                    rp = self.point_position(about, sid)
                r = self.pos(b, sid) - rp
            H = add(H, mul(m, r.cross(self.vel(b, sid))))
            if not body.is_particle:
                H = add(H, mul(Const(body.inertia), self.sv(b, "omega", sid)))
        return H
