"""Joint elements: pin, weld, link, spring, the simulation's damper, and bearing friction.

Compile asks a joint for its reaction impulses in an impact or interval (it acts in
every transition from its `from` state on, and in the one into that state: the plastic
joining) and for its constraint rows at each state where it holds; a spring adds its
potential energy instead. Simulate asks the same objects for their velocity rows, their
position residuals (drift) and their forces along the line (springs, dampers).
"""
from __future__ import annotations

import math

from ..expr import ZERO, Const, E, V2, add, mul, neg, omega_cross, power, rotate
from ..units import ANGULAR_IMPULSE, IMPULSE
from .base import Element, ImpulseSource, Phase, SimRow, registrar
from .keys import Key, impulse_key
from .kinds import Component, JointKind, KeyKind, PhaseKind

JOINTS: dict[JointKind, type["JointElement"]] = {}




joint_kind = registrar(JOINTS)  # @joint_kind(KIND) on a JointElement subclass


def joint_element(jt, scene) -> "JointElement":
    """The element for a scene Joint record (its class may choose a variant)."""
    return JOINTS[JointKind(jt.kind)].element_for(jt, scene)


class JointElement(Element):
    kind: JointKind
    impulsive = True  # exerts reaction impulses (a spring's finite force does not)
    constrains = True  # adds constraint rows at each state where it holds

    def __init__(self, jt, scene):
        self.record = jt
        self.label, self.span, self.a, self.b = jt.label, jt.span, jt.a, jt.b
        self.along, self.stiffness, self.length = jt.along, jt.stiffness, jt.length
        self.from_state = jt.from_state
        bodies = scene.bodies
        self.has_particle = any(p.body is not None and bodies[p.body].is_particle
                                for p in (jt.a, jt.b))

    @classmethod
    def element_for(cls, jt, scene) -> "JointElement":
        return cls(jt, scene)

    def bodies(self) -> tuple[str | None, ...]:
        return (self.a.body, self.b.body)

    def quantity(self, member: str, sid: str, compiler):
        """A quantity the joint defines (`pole.omega@2`), or None."""
        return None

    def describe(self) -> str:
        return f"{self.kind} {self.label}"

    # ---- compile
    def acts_in(self, compiler, t) -> bool:
        """Whether it exerts an impulse in transition t: from its `from` state on, and in
        the transition into that state (the joining). Where a contact of t joins the same
        bodies, how the impulse splits between them is undetermined; the solve's numeric
        rank test answers the motion and names the split only if a `find` asks for it."""
        if not self.impulsive:
            return False
        return compiler.holds_at(self.from_state, t.before) or \
            compiler.holds_at(self.from_state, t.after)

    def stamp(self, phase: Phase, compiler) -> None:
        if phase.kind is PhaseKind.STATE:
            if self.constrains and compiler.holds_at(self.from_state, phase.before):
                self.state_rows(phase, compiler)
        elif self.impulsive:
            self.impulse(phase, compiler)

    def impulse(self, phase: Phase, compiler) -> None:
        pass

    def state_rows(self, phase: Phase, compiler) -> None:
        pass

    def _pair(self, J: V2, M: E | None, phase: Phase) -> None:
        phase.apply(self.a, J, M)
        if self.b.body is not None:
            phase.apply(self.b, -J, neg(M) if M is not None else None)

    # ---- simulate
    def sim_reference(self, frame) -> float | None:
        """What a drift residual is measured from (a weld's angle, a link's length)."""
        return None

    def sim_residuals(self, frame, ref: dict, L: float) -> list[float]:
        return []

    def sim_force(self, frame, Q) -> float:
        """Add its force to the generalized forces; returns its power if dissipative."""
        return 0.0

    def sim_energy(self, frame) -> float:
        return 0.0

    def _pair_rows(self, frame):
        """(2 x n Jacobian, 2 acceleration terms) of a's point relative to b's."""
        ra = frame.offset(self.a.body, self.a.offset)
        Ja, ba = frame.point_jac(self.a.body, ra)
        if self.b.body is None:
            return Ja, (ba[0], ba[1])
        rb = frame.offset(self.b.body, self.b.offset)
        Jb, bb = frame.point_jac(self.b.body, rb)
        return Ja - Jb, (ba[0] - bb[0], ba[1] - bb[1])

    def _gap(self, frame) -> tuple[float, float]:
        pa = frame.point(self.a.body, self.a.offset)
        pb = frame.point(self.b.body, self.b.offset)
        return pa[0] - pb[0], pa[1] - pb[1]

    def _angle(self, frame) -> float:
        return frame.pose[self.a.body][2] - (frame.pose[self.b.body][2] if self.b.body
                                             else 0.0)


@joint_kind(JointKind.PIN)
class Pin(JointElement):
    """Points coincide: an unknown reaction impulse (Jx, Jy), two position and two velocity
    rows at each state."""

    transmits_moment = False

    def unknowns(self, phase: Phase) -> list[Key]:
        out = [impulse_key(Component.JX, self.label, phase.key),
               impulse_key(Component.JY, self.label, phase.key)]
        if self.transmits_moment and not self.has_particle:
            out.append(impulse_key(Component.M, self.label, phase.key))
        return out

    def impulse(self, phase: Phase, compiler) -> None:
        keys = self.unknowns(phase)
        J = V2(compiler.unknown(keys[0], IMPULSE, KeyKind.IMPULSE),
               compiler.unknown(keys[1], IMPULSE, KeyKind.IMPULSE))
        M = compiler.unknown(keys[2], ANGULAR_IMPULSE, KeyKind.ANGULAR_IMPULSE) \
            if len(keys) > 2 else None
        self._pair(J, M, phase)
        phase.sources.append(ImpulseSource(self.bodies(), self.a.name, None, False,
                                           self.describe()))
        if M is not None:
            phase.sources.append(ImpulseSource(self.bodies(), self.a.name, None, True,
                                               f"weld moment {self.label}"))

    def state_rows(self, phase: Phase, compiler) -> None:
        sid, a, b = phase.before, self.a, self.b
        pa, pb = compiler.point_position(a, sid), compiler.point_position(b, sid)
        va, vb = compiler.point_velocity(a, sid), compiler.point_velocity(b, sid)
        for comp, x1, x2 in (("x", pa.x, pb.x), ("y", pa.y, pb.y)):
            compiler.eq(x1, x2, f"{self.describe()}: points coincide ({comp})", phase.group,
                        self.span)
        for comp, x1, x2 in (("x", va.x, vb.x), ("y", va.y, vb.y)):
            compiler.eq(x1, x2, f"{self.describe()}: same velocity ({comp})", phase.group,
                        self.span)

    def constraint(self, frame) -> list:
        J, beta = self._pair_rows(frame)
        return [SimRow(f"F{axis}[{self.label}]", J[k], beta[k]) for k, axis in enumerate("xy")]

    def sim_residuals(self, frame, ref: dict, L: float) -> list[float]:
        return list(self._gap(frame))


@joint_kind(JointKind.WELD)
class Weld(Pin):
    """A pin that also transmits a moment (unless one side is a particle: then a pin)."""

    transmits_moment = True

    @classmethod
    def element_for(cls, jt, scene) -> "JointElement":
        """Two particles welded at a distance are one rigid body: a RigidPair. Welded at
        one point (coincident, or no state gives both positions: a bullet lodging in a
        block) they are a pin: one velocity, an impulse (Jx, Jy) -- a pole of zero length
        has no line for its impulse."""
        bodies = [scene.bodies[p.body] for p in (jt.a, jt.b) if p.body is not None]
        if len(bodies) == 2 and all(b.is_particle for b in bodies) \
                and _given_separation(jt, scene) > 0.0:
            return RigidPair(jt, scene)
        return cls(jt, scene)

    def state_rows(self, phase: Phase, compiler) -> None:
        super().state_rows(phase, compiler)
        if not self.has_particle:
            sid, b = phase.before, self.b
            wb = compiler.sv(b.body, "omega", sid) if b.body else ZERO
            compiler.eq(compiler.sv(self.a.body, "omega", sid), wb,
                        f"weld {self.label}: same angular velocity", phase.group, self.span)

    def constraint(self, frame) -> list:
        row = frame.jac[self.a.body][2].copy()
        if self.b.body is not None:
            row -= frame.jac[self.b.body][2]
        return super().constraint(frame) + [SimRow(f"M[{self.label}]", row, 0.0, True)]

    def sim_reference(self, frame) -> float | None:
        return self._angle(frame)

    def sim_residuals(self, frame, ref: dict, L: float) -> list[float]:
        return super().sim_residuals(frame, ref, L) + [(self._angle(frame) -
                                                        ref[self.label]) * L]


@joint_kind(JointKind.LINK)
class Link(JointElement):
    """No stretching along a fixed line: one impulse along it, one velocity row."""

    def unknowns(self, phase: Phase) -> list[Key]:
        return [impulse_key(Component.J, self.label, phase.key)]

    def impulse(self, phase: Phase, compiler) -> None:
        d = self.along
        Jl = compiler.unknown(self.unknowns(phase)[0], IMPULSE, KeyKind.IMPULSE)
        self._pair(V2(Const(d[0]), Const(d[1])).scale(Jl), None, phase)
        phase.sources.append(ImpulseSource(self.bodies(), self.a.name, d, False,
                                           self.describe()))

    def state_rows(self, phase: Phase, compiler) -> None:
        sid = phase.before
        d = V2(Const(self.along[0]), Const(self.along[1]))
        va, vb = compiler.point_velocity(self.a, sid), compiler.point_velocity(self.b, sid)
        compiler.eq((va - vb).dot(d), ZERO, f"link {self.label}: no stretching along its line",
                    phase.group, self.span)

    def constraint(self, frame) -> list:
        J, beta = self._pair_rows(frame)
        d = self.along
        return [SimRow(f"F[{self.label}]", d[0] * J[0] + d[1] * J[1],
                       d[0] * beta[0] + d[1] * beta[1])]

    def sim_reference(self, frame) -> float | None:
        dx, dy = self._gap(frame)
        return dx * self.along[0] + dy * self.along[1]

    def sim_residuals(self, frame, ref: dict, L: float) -> list[float]:
        return [self.sim_reference(frame) - ref[self.label]]


def _given_separation(jt, scene) -> float:
    """The largest distance between a joint's two points over the states that give both
    positions (0.0 when none does)."""
    far = 0.0
    for spec in scene.states.values():
        pos = []
        for p in (jt.a, jt.b):
            xy = [spec.givens.get((p.body, q)) for q in ("x", "y")]
            if None in xy:
                break
            pos.append((xy[0][0] + p.offset[0], xy[1][0] + p.offset[1]))
        else:
            far = max(far, math.hypot(pos[0][0] - pos[1][0], pos[0][1] - pos[1][1]))
    return far


class RigidPair(JointElement):
    """Two particles welded at a distance (skaters holding a light pole): one rigid body.
    The pole is a two-force member: one impulse along the line between them, and their
    relative velocity has no part along it; the pair turns with
    omega = (r_a - r_b) x (v_a - v_b) / |r_a - r_b|^2 (`LABEL.omega@S`)."""

    kind = JointKind.WELD

    def unknowns(self, phase: Phase) -> list[Key]:
        return [impulse_key(Component.J, self.label, phase.key)]

    def _line(self, compiler, sid: str) -> V2:
        return compiler.point_position(self.a, sid) - compiler.point_position(self.b, sid)

    def impulse(self, phase: Phase, compiler) -> None:
        d = self._line(compiler, phase.before)
        Jl = compiler.unknown(self.unknowns(phase)[0], IMPULSE, KeyKind.IMPULSE)
        self._pair(d.scale(mul(Jl, power(d.dot(d), -0.5))), None, phase)
        phase.sources.append(ImpulseSource(self.bodies(), self.a.name, None, False,
                                           self.describe()))

    def state_rows(self, phase: Phase, compiler) -> None:
        sid = phase.before
        va, vb = compiler.point_velocity(self.a, sid), compiler.point_velocity(self.b, sid)
        compiler.eq((va - vb).dot(self._line(compiler, sid)), ZERO,
                    f"weld {self.label}: the particles keep their distance (one rigid body)",
                    phase.group, self.span)

    def quantity(self, member: str, sid: str, compiler):
        if member != "omega":
            return None
        d = self._line(compiler, sid)
        rel = compiler.point_velocity(self.a, sid) - compiler.point_velocity(self.b, sid)
        return mul(d.cross(rel), power(d.dot(d), -1.0))

    def constraint(self, frame) -> list:
        J, beta = self._pair_rows(frame)
        dx, dy = self._gap(frame)
        va = frame.point_velocity(self.a.body, (0.0, 0.0))
        vb = frame.point_velocity(self.b.body, (0.0, 0.0))
        rel2 = (va[0] - vb[0]) ** 2 + (va[1] - vb[1]) ** 2
        d = math.hypot(dx, dy)  # a unit row: its multiplier is the force along the pole
        return [SimRow(f"F[{self.label}]", (dx * J[0] + dy * J[1]) / d,
                       (dx * beta[0] + dy * beta[1] + rel2) / d)]

    def sim_reference(self, frame) -> float | None:
        return math.hypot(*self._gap(frame))

    def sim_residuals(self, frame, ref: dict, L: float) -> list[float]:
        return [self.sim_reference(frame) - ref[self.label]]


@joint_kind(JointKind.SLIDER)
class Slider(JointElement):
    """A collar on a body's line (a prismatic joint): free along it, held across it by one
    impulse J across the line, applied on the body where the collar is (so it turns the
    body); a rigid collar also turns with the body (a moment M). One velocity row across
    the line at each state: the collar's velocity less the body's material point under it."""

    def unknowns(self, phase: Phase) -> list[Key]:
        out = [impulse_key(Component.J, self.label, phase.key)]
        if not self.has_particle and self.b.body is not None:
            out.append(impulse_key(Component.M, self.label, phase.key))
        return out

    def _across(self, compiler, sid: str) -> V2:
        n = (-self.along[1], self.along[0])
        if self.b.body is None or compiler.scene.bodies[self.b.body].is_particle:
            return V2(Const(n[0]), Const(n[1]))
        return rotate(n, compiler.sv(self.b.body, "angle", sid))

    def _arm(self, compiler, sid: str) -> V2:
        """From the body's centre to the collar: where the reaction acts on the body."""
        return compiler.point_position(self.a, sid) - compiler.point_position(self.b, sid)

    def impulse(self, phase: Phase, compiler) -> None:
        sid, keys = phase.before, self.unknowns(phase)
        J = self._across(compiler, sid).scale(compiler.unknown(keys[0], IMPULSE,
                                                               KeyKind.IMPULSE))
        M = compiler.unknown(keys[1], ANGULAR_IMPULSE, KeyKind.ANGULAR_IMPULSE) \
            if len(keys) > 1 else None
        phase.apply(self.a, J, M)
        if self.b.body is not None:
            torque = self._arm(compiler, sid).cross(-J)
            phase.apply(self.b, -J, add(torque, neg(M)) if M is not None else torque)
        phase.sources.append(ImpulseSource(self.bodies(), self.a.name, None, False,
                                           self.describe()))

    def state_rows(self, phase: Phase, compiler) -> None:
        sid = phase.before
        va = compiler.point_velocity(self.a, sid)
        vb = V2(ZERO, ZERO)
        if self.b.body is not None:
            w = compiler.sv(self.b.body, "omega", sid)
            vb = compiler.vel(self.b.body, sid) + omega_cross(w, self._arm(compiler, sid))
        compiler.eq((va - vb).dot(self._across(compiler, sid)), ZERO,
                    f"slider {self.label}: no relative velocity across the line", phase.group,
                    self.span)
        if len(self.unknowns(phase)) > 1:
            compiler.eq(compiler.sv(self.a.body, "omega", sid),
                        compiler.sv(self.b.body, "omega", sid),
                        f"slider {self.label}: turns with {self.b.body}", phase.group,
                        self.span)

    # ---- simulate: g = n . (v_collar - v_m) = 0, m the body's material point under the
    # collar; its rate adds w x n to n and w x (v_collar - v_G) to v_m (the point slides)
    def _sim_across(self, frame) -> tuple[float, float]:
        n = (-self.along[1], self.along[0])
        if self.b.body is None:
            return n
        th = frame.pose[self.b.body][2]
        c, s_ = math.cos(th), math.sin(th)
        return (c * n[0] - s_ * n[1], s_ * n[0] + c * n[1])

    def constraint(self, frame) -> list:
        n = self._sim_across(frame)
        Ja, ba = frame.point_jac(self.a.body, frame.offset(self.a.body, self.a.offset))
        vc = frame.point_velocity(self.a.body, frame.offset(self.a.body, self.a.offset))
        row, beta = n[0] * Ja[0] + n[1] * Ja[1], n[0] * ba[0] + n[1] * ba[1]
        rows = []
        if self.b.body is not None:
            pc = frame.point(self.a.body, self.a.offset)
            gx, gy, _ = frame.pose[self.b.body]
            r = (pc[0] - gx, pc[1] - gy)
            Jm, bm = frame.point_jac(self.b.body, r, centripetal=False)
            vm = frame.point_velocity(self.b.body, r)
            vgx, vgy, w = frame.twist[self.b.body]
            rel = (vc[0] - vm[0], vc[1] - vm[1])
            slide = (vc[0] - vgx, vc[1] - vgy)
            ndot = (-w * n[1], w * n[0])
            row = row - (n[0] * Jm[0] + n[1] * Jm[1])
            beta += ndot[0] * rel[0] + ndot[1] * rel[1] - (n[0] * bm[0] + n[1] * bm[1]) \
                - (n[0] * -w * slide[1] + n[1] * w * slide[0])
            if not self.has_particle:
                rows.append(SimRow(f"M[{self.label}]", frame.jac[self.a.body][2] -
                                   frame.jac[self.b.body][2], 0.0, True))
        return [SimRow(f"F[{self.label}]", row, beta)] + rows

    def sim_reference(self, frame) -> float | None:
        n = self._sim_across(frame)
        pc = frame.point(self.a.body, self.a.offset)
        pg = frame.point(self.b.body, (0.0, 0.0))
        return (pc[0] - pg[0]) * n[0] + (pc[1] - pg[1]) * n[1]

    def sim_residuals(self, frame, ref: dict, L: float) -> list[float]:
        return [self.sim_reference(frame) - ref[self.label]]


class _LineForce(JointElement):
    """A force along the line between its two points: no impulse, no constraint."""

    impulsive = False
    constrains = False

    def line(self, frame):
        """(offsets ra, rb, unit direction a->b, length, rate of extension); None when
        the ends meet (no direction)."""
        ra = frame.offset(self.a.body, self.a.offset)
        rb = frame.offset(self.b.body, self.b.offset) if self.b.body is not None else None
        pa, pb = frame.point(self.a.body, self.a.offset), frame.point(self.b.body, self.b.offset)
        dx, dy = pb[0] - pa[0], pb[1] - pa[1]
        L = math.hypot(dx, dy)
        if L == 0:
            return None
        ex, ey = dx / L, dy / L
        va = frame.point_velocity(self.a.body, ra)
        vb = frame.point_velocity(self.b.body, rb) if rb is not None else (0.0, 0.0)
        return ra, rb, ex, ey, L, (vb[0] - va[0]) * ex + (vb[1] - va[1]) * ey

    def tension(self, length: float, rate: float) -> float:
        """The pull along the line (> 0 pulls the ends together)."""
        raise NotImplementedError

    def sim_force(self, frame, Q) -> float:
        line = self.line(frame)
        if line is None:
            return 0.0
        ra, rb, ex, ey, L, rate = line
        T = self.tension(L, rate)
        frame.add_force(Q, self.a.body, ra, (T * ex, T * ey))
        frame.add_force(Q, self.b.body, rb, (-T * ex, -T * ey))
        return self.power(T, rate)

    def power(self, tension: float, rate: float) -> float:
        return 0.0


@joint_kind(JointKind.SPRING)
class Spring(_LineForce):
    """A linear spring: potential (k/2)(L - L0)^2; a finite force has no impulse in an
    impact, and an interval's constant forces leave it out (see README)."""

    def potential(self, compiler, sid: str) -> E:
        d = compiler.point_position(self.a, sid) - compiler.point_position(self.b, sid)
        stretch = add(power(d.dot(d), 0.5), Const(-self.length))
        return mul(Const(0.5 * self.stiffness), mul(stretch, stretch))

    def tension(self, length: float, rate: float) -> float:
        return self.stiffness * (length - self.length)

    def sim_energy(self, frame) -> float:
        pa, pb = frame.point(self.a.body, self.a.offset), frame.point(self.b.body, self.b.offset)
        L = math.hypot(pb[0] - pa[0], pb[1] - pa[1])
        return 0.5 * self.stiffness * (L - self.length) ** 2


@joint_kind(JointKind.DAMPER)
class Damper(_LineForce):
    """A linear dashpot (simulate only): a pull c times the rate of extension."""

    def tension(self, length: float, rate: float) -> float:
        return self.stiffness * rate

    def power(self, tension: float, rate: float) -> float:
        return -tension * rate


class BearingFriction(Element):
    """A pin's bearing friction in one transition: an unknown torque impulse between its
    two sides."""

    def __init__(self, joint: JointElement, span):
        self.joint = joint
        self.label = joint.label
        self.span = span

    def bodies(self) -> tuple[str | None, ...]:
        return self.joint.bodies()

    def unknowns(self, phase: Phase) -> list[Key]:
        return [impulse_key(Component.M, self.label, phase.key)]

    def stamp(self, phase: Phase, compiler) -> None:
        if phase.kind is PhaseKind.STATE:
            return
        M = compiler.unknown(self.unknowns(phase)[0], ANGULAR_IMPULSE, KeyKind.ANGULAR_IMPULSE)
        jt = self.joint
        phase.apply(jt.a, V2(ZERO, ZERO), M)
        if jt.b.body is not None:
            phase.apply(jt.b, V2(ZERO, ZERO), neg(M))
        phase.sources.append(ImpulseSource(self.bodies(), self.label, None, True,
                                           f"friction torque at {self.label}"))

    def describe(self) -> str:
        return f"friction torque at {self.label}"
