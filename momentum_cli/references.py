"""References in `find` lines and user equations (part of `compile`).

Resolves names such as `rod.omega@3`, `t@1->2`, `J_n[A]@2->3`, `e[A]`, `T_lost@2->3`,
`BODY.dtheta@1->2` and `POINT.v@S` to expressions over the system's unknowns, with
their dimensions, so that finds and equations are checked for units like any other
quantity.
"""
from __future__ import annotations

import math

from . import syntax as S
from .diagnostics import ProblemError, did_you_mean
from .elements.keys import duration_key
from .elements.kinds import EquationKind, KeyKind, TransitionKind
from .expr import V2, Const, E, Known, Var, add, add_all, mul, neg, power
from .quantity import Evaluator, Q, unit_readings
from .records import record
from .scene import STATE_QTYS, PointOn, TransitionSpec
from .source import Span
from .units import (
    ACCELERATION,
    ANGULAR_IMPULSE,
    IMPULSE,
    LENGTH,
    MASS,
    MOMENT,
    NONE,
    TIME,
    VELOCITY,
    Dim,
    describe,
    si_label,
    suggest_unit,
)


@record
class FindSpec:
    name: str
    expr: E
    dim: Dim
    unit: str  # display unit label
    factor: float  # SI value / factor = display value
    span: Span
    alt: E | None = None  # the same quantity in another form (solve keeps the better bound)
    explicit: bool = False  # `find ... in UNIT`: the reader's units (--units) do not apply


class ReferencesMixin:
    """`_Compiler` methods that resolve references and build finds and equations."""

    def _resolver(self):
        sc = self.scene

        def resolve(ref: S.Ref, expect) -> Q:
            name, idx, member, at = ref.name, ref.index, ref.member, ref.at
            if idx is None and member is None and not at:
                if name in sc.constants:
                    return sc.constants[name]
                if name == "pi":
                    return Q(Const(math.pi), NONE)
                if name == "g" and sc.g is not None:
                    return Q(Known("g", sc.g), ACCELERATION)
                if name in sc.user_unknowns:
                    dim, unit, span = sc.user_unknowns[name]
                    return Q(self.unknown(name, dim, KeyKind.USER, unit or si_label(dim)), dim)
                if name in self.unknowns:
                    return Q(Var(name), self.unknowns[name].dim)
            if ref.about is not None and (name != "H" or idx is None):
                raise ProblemError("'about' belongs to an angular momentum: write "
                                   "`H[{BODY, ...}]@S about POINT`", ref.span, code="name")
            if name in _OF_BODIES and idx is not None and member is None and len(at) == 1:
                return self._of_bodies(ref)
            if member and len(at) == 1 and name in self._by_label:  # a joint's `pole.omega@2`
                self._state_exists(at[0], ref)
                q = self._by_label[name].quantity(member, at[0], self)
                if q is not None:
                    return Q(q, STATE_QTYS[member][0])
            if member and len(at) == 1 and name in sc.bodies:
                return self._body_ref(ref)
            if member in ("v", "vx", "vy", "speed") and len(at) == 1 and name in sc.points:
                self._state_exists(at[0], ref)
                v = self.point_velocity(sc.points[name], at[0])
                if member == "v":
                    return Q(v, VELOCITY)
                if member == "speed":
                    return Q(power(v.dot(v), 0.5), VELOCITY)
                return Q(v.x if member == "vx" else v.y, VELOCITY)
            if member is None and idx is None and len(at) == 1 and name == "T":
                self._state_exists(at[0], ref)
                return Q(self._kinetic(at[0]), MOMENT)
            if member is None and idx is None and len(at) == 2 and name == "T_lost":
                self._transition_exists(at, ref)
                moved = self._moved("->".join(at))  # only what this transition changes
                return Q(add(self._kinetic(at[0], moved), neg(self._kinetic(at[1], moved))),
                         MOMENT)
            if member is None and idx is None and len(at) == 2 and name == "t":
                if self.flows and "->".join(at) in self.flows.durations:
                    return Q(self.flows.durations["->".join(at)], TIME)
                tr = self._transition_exists(at, ref)
                if tr.kind != TransitionKind.INTERVAL:
                    raise ProblemError(f"{ref.text}: only an interval has a duration (an impact "
                                       "takes no time)", ref.span, code="name")
                if tr.duration is not None:
                    return Q(Known(duration_key(tr.key), tr.duration), TIME)
                return Q(self.unknown(duration_key(tr.key), TIME, KeyKind.DURATION, "s"), TIME)
            text = ref.text
            if text in self.unknowns:
                return Q(Var(text), self.unknowns[text].dim)
            if idx is not None and name == "e" and not at:
                for t in sc.transitions:
                    for c in t.contacts:
                        if c.label == idx and not c.restitution_unknown:
                            return Q(Known(text, c.restitution), NONE)
            candidates = list(self.unknowns) + list(sc.constants) + ["g", "pi"]
            hint = did_you_mean(text, candidates)
            known = _FAMILIES + list(sc.bodies) + list(sc.points)
            if not hint and name not in known:
                # a misspelt family, body or point with a good rest: `T_lots@1->2`
                import difflib  # (here: an error's hint; its import costs every run)

                close = difflib.get_close_matches(name, sorted(set(known)), n=1, cutoff=0.6)
                hint = f"; did you mean '{close[0]}{text[len(name):]}'?" if close else ""
            raise ProblemError(f"unknown quantity '{text}'" + hint,
                               ref.span, code="name", notes=_ref_help(ref))

        return resolve

    def _moved(self, key: str) -> list[str] | None:
        """The bodies transition `key` changes (None: all, as for an energy phase)."""
        for info in self.transitions:
            if info.key == key and info.kind != "energy":
                return list(info.bodies)
        return None

    def _of_bodies(self, ref: S.Ref) -> Q:
        """T, p, px, py or H (about a point) of a body or a set: `p[{A, B}]@2`."""
        sc = self.scene
        sid = ref.at[0]
        bodies = ref.bodies
        for b in bodies:
            if b not in sc.bodies:
                raise ProblemError(f"unknown body '{b}' in {ref.text}" +
                                   did_you_mean(b, sc.bodies), ref.span, code="name")
        self._state_exists(sid, ref)
        if ref.name == "T":
            return Q(self._kinetic(sid, bodies), MOMENT)
        if ref.name == "H":
            if ref.about is None:
                raise ProblemError(f"an angular momentum is about a point: write `{ref.text} "
                                   "about POINT`", ref.span, code="name")
            return Q(self._angular_momentum(bodies, self._point_of(ref.about), sid),
                     ANGULAR_IMPULSE)
        terms = [(self.mass(b, sid), self.vel(b, sid)) for b in bodies]
        p = V2(add_all([mul(m, v.x) for m, v in terms]), add_all([mul(m, v.y) for m, v in terms]))
        if ref.name == "p":
            return Q(p, IMPULSE)
        return Q(p.x if ref.name == "px" else p.y, IMPULSE)

    def _point_of(self, ref: S.PointRef) -> PointOn:
        """A point named after `about`: a named point, a body's centre, `rod.end(+)`."""
        sc = self.scene
        if ref.end and ref.name in sc.bodies and sc.bodies[ref.name].length is not None:
            half = sc.bodies[ref.name].length / 2 * (1 if ref.end == "+" else -1)
            return PointOn(ref.name, (half, 0.0), ref.text, ref.span)
        if ref.member in ("center", "centre", "G") and ref.name in sc.bodies:
            return PointOn(ref.name, (0.0, 0.0), ref.text, ref.span)
        name = ref.member if ref.member else ref.name
        if name in sc.points and not ref.end:
            p = sc.points[name]
            return PointOn(p.body, p.offset, p.name, ref.span)
        if name in sc.bodies and not ref.end:
            return PointOn(name, (0.0, 0.0), name, ref.span)
        raise ProblemError(f"unknown point '{ref.text}'" +
                           did_you_mean(name, list(sc.points) + list(sc.bodies)), ref.span,
                           code="name")

    def _impact_loss(self, tr: TransitionSpec) -> E | None:
        """T_lost of an impact from its contact impulses (cancellation-free), when the
        contacts are its only impulses that work: joints that hold on both sides of the
        impact do none; one that forms in it, or a bearing's friction torque, does."""
        losses = self.losses.get(tr.key)
        if tr.kind != "impact" or not losses or tr.bearing_friction:
            return None
        for jt in self.joints:
            if jt.impulsive and self.holds_at(jt.from_state, tr.after) != \
                    self.holds_at(jt.from_state, tr.before):
                return None
        return add_all(losses)

    def _state_exists(self, sid: str, ref: S.Ref) -> None:
        if sid not in self.scene.states:
            raise ProblemError(f"state {sid} is not declared" +
                               did_you_mean(sid, self.scene.states), ref.span, code="name")

    def _transition_exists(self, at, ref: S.Ref) -> TransitionSpec:
        key = "->".join(at)
        if key not in self.tspecs:
            raise ProblemError(f"no transition {at[0]} -> {at[1]} is declared" +
                               did_you_mean(key, self.tspecs), ref.span, code="name")
        return self.tspecs[key]

    def _body_ref(self, ref: S.Ref) -> Q:
        sc = self.scene
        b, q, sid = ref.name, ref.member, ref.at[0]
        body = sc.bodies[b]
        if q in ("dx", "dy", "dtheta", "alpha"):
            raise ProblemError(f"'{ref.text}' belongs to a transition: write "
                               f"{b}.{q}@{sid}->STATE", ref.span, code="name")
        self._state_exists(sid, ref)
        if q == "mass":
            return Q(self.mass(b, sid), MASS)
        if q in STATE_QTYS:
            if body.is_particle and q in ("angle", "omega"):
                raise ProblemError(f"'{b}' is a particle: it has no {q}", ref.span, code="name")
            return Q(self.sv(b, q, sid), STATE_QTYS[q][0])
        if q == "v":
            return Q(self.vel(b, sid), VELOCITY)
        if q == "pos":
            return Q(self.pos(b, sid), LENGTH)
        if q == "speed":
            v = self.vel(b, sid)
            return Q(power(v.dot(v), 0.5), VELOCITY)
        if q == "T":
            return Q(self._kinetic(sid, {b}), MOMENT)
        raise ProblemError(f"'{q}' is not a quantity of a body" +
                           did_you_mean(q, list(STATE_QTYS) + ["v", "pos", "speed", "T"]),
                           ref.span, code="name")

    def _displacement(self, ref: S.Ref) -> Q | None:
        sc = self.scene
        if not (ref.member and len(ref.at) == 2 and ref.name in sc.bodies):
            return None
        q = ref.member
        if q not in ("dx", "dy", "dtheta", "alpha"):
            return None
        tr = self._transition_exists(ref.at, ref)
        if tr.kind != TransitionKind.INTERVAL:
            raise ProblemError(f"'{ref.text}': displacements belong to an interval", ref.span,
                               code="name")
        b = ref.name
        i, j = ref.at
        if tr.duration is not None:
            t: E = Known(duration_key(tr.key), tr.duration)
        else:
            t = self.unknown(duration_key(tr.key), TIME, KeyKind.DURATION, "s")
        if q == "alpha":
            w1, w2 = self.sv(b, "omega", i), self.sv(b, "omega", j)
            return Q(mul(add(w2, neg(w1)), power(t, -1.0)), (0, 0, -2))
        comp = {"dx": "vx", "dy": "vy", "dtheta": "omega"}[q]
        dim = LENGTH if q != "dtheta" else NONE
        d = self.unknown(ref.text, dim, KeyKind.DERIVED, "m" if q != "dtheta" else "rad")
        a1, a2 = self.sv(b, comp, i), self.sv(b, comp, j)
        self.eq(d, mul(mul(Const(0.5), add(a1, a2)), t),
                "constant acceleration: displacement = (start + end velocity)/2 * t",
                f"interval {i} -> {j}", ref.span)
        return Q(d, dim)

    def _evaluator(self) -> Evaluator:
        base = self._resolver()

        def resolve(ref: S.Ref, expect) -> Q:
            d = self._displacement(ref)
            if d is not None:
                return d
            return base(ref, expect)

        return Evaluator(resolve)

    def _user_equation(self, ue: S.UserEquation) -> None:
        ev = self._evaluator()
        a, b = ev(ue.left), ev(ue.right, None)
        if a.dim != b.dim and not (_bare_zero(ue.left) or _bare_zero(ue.right)):
            raise ProblemError(f"the two sides differ: {describe(a.dim)} = {describe(b.dim)}",
                               ue.span, code="units")
        if a.is_vector != b.is_vector:
            raise ProblemError("one side is a vector and the other a scalar", ue.span,
                               code="type")
        user = EquationKind.USER
        if a.is_vector:
            self.eq(a.value.x, b.value.x, "equation (x)", "user equations", ue.span, user)
            self.eq(a.value.y, b.value.y, "equation (y)", "user equations", ue.span, user)
        else:
            self.eq(a.value, b.value, "equation", "user equations", ue.span, user)

    def _finds(self) -> list[FindSpec]:
        ev = self._evaluator()
        out = []
        for item in self.scene.finds:
            q = ev(item.expr)
            base = item.name or _expr_text(item.expr)
            unit, factor = _display_unit(self.unknowns, item, q)
            if item.unit:
                readings = unit_readings(item.unit, item.unit_span, q.dim)
                match = [r for r in readings if r[1] == q.dim]
                if not match:
                    raise ProblemError(f"cannot show {describe(q.dim)} in {item.unit} "
                                       f"({describe(readings[0][1])})" +
                                       suggest_unit(item.unit, q.dim), item.unit_span,
                                       code="units")
                unit, factor = item.unit, match[0][0]
            if q.is_vector:
                v = q.value
                if isinstance(item.expr, S.Ref) and item.expr.member in ("v", "pos"):
                    comps = {"v": ("vx", "vy"), "pos": ("x", "y")}[item.expr.member]
                    names = [base.replace(f".{item.expr.member}@", f".{c}@") for c in comps]
                elif isinstance(item.expr, S.Ref) and item.expr.name == "p" and not item.name:
                    names = ["px" + base[1:], "py" + base[1:]]
                else:
                    names = [f"{base}.x", f"{base}.y"]
                out.append(FindSpec(names[0], v.x, q.dim, unit, factor, item.span,
                                    explicit=bool(item.unit)))
                out.append(FindSpec(names[1], v.y, q.dim, unit, factor, item.span,
                                    explicit=bool(item.unit)))
            else:
                out.append(FindSpec(base, q.value, q.dim, unit, factor, item.span,
                                    self._loss_form(item.expr), explicit=bool(item.unit)))
        return out

    def _loss_form(self, node) -> E | None:
        """`T_lost@i->j` of an impact, from its contact impulses: T1 - T2 cancels every
        digit when little is lost; the impulse form cancels when large impulses oppose."""
        if not (isinstance(node, S.Ref) and node.name == "T_lost" and len(node.at) == 2
                and node.member is None and node.index is None):
            return None
        return self._impact_loss(self.tspecs["->".join(node.at)])


def _display_unit(unknowns, item, q: Q) -> tuple[str, float]:
    node = item.expr
    if isinstance(node, S.Ref) and (node.name in ("T", "T_lost") or node.member == "T"):
        return "J", 1.0
    if isinstance(q.value, Var) and q.value.name in unknowns:
        return unknowns[q.value.name].unit, 1.0
    if isinstance(item.expr, S.Ref) and item.expr.member in ("omega",):
        return "rad/s", 1.0
    if isinstance(item.expr, S.Ref) and item.expr.member in ("angle", "dtheta"):
        return "rad", 1.0
    if isinstance(item.expr, S.Ref) and item.expr.member == "alpha":
        return "rad/s^2", 1.0
    return si_label(q.dim), 1.0


def _expr_text(node) -> str:
    if isinstance(node, S.Ref):
        return node.text
    return "value"


# quantities of a body or a set of bodies: `T[rod]@2`, `p[{A, B}]@2`, `H[{A}]@2 about O`
_OF_BODIES = ("T", "p", "px", "py", "H")

# names of quantities that are not a body's (`T@S`, `J_n[A]@S->S`, ...)
_FAMILIES = ["T", "T_lost", "t", "J_n", "J_t", "Jx", "Jy", "J", "e", "H", "p"]


def _ref_help(ref: S.Ref) -> list[str]:
    return ["quantities: BODY.omega@S, BODY.v@S, POINT.v@S, BODY.vx@S, BODY.angle@S, BODY.speed@S, "
            "t@S->S, J_n[CONTACT]@S->S, e[CONTACT], T@S, T_lost@S->S, BODY.dtheta@S->S"]


def _bare_zero(node) -> bool:
    """A `0` (or `(0, 0)`) written without a unit: zero of any dimension."""
    if isinstance(node, S.Num):
        return node.value == 0 and node.unit is None
    if isinstance(node, S.VecLit):
        return _bare_zero(node.x) and _bare_zero(node.y)
    return False
