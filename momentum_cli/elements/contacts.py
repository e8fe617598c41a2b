"""Contact elements: a normal (restitution) law and a tangential law at one contact.

Compile (`stamp`) writes, per transition, the contact's impulses and rows: in an impact
the restitution law's rows (Newton's v_n+ = -e v_n-, or a given separation speed) and
the tangential law's (smooth: none; rough: no slip; Coulomb friction: stick or slide
with |J_t| <= mu J_n); in an interval, persistence (no normal velocity at either end)
and kinetic friction. Simulate asks the same tangential law for its regime and its
friction column. A new restitution law is one `RestitutionLaw` subclass registered
with `@restitution_law`; it may take over the tangential rows (`owns_tangential`).
"""
from __future__ import annotations

from ..diagnostics import ProblemError
from ..expr import ZERO, Const, E, Known, Mul, V2, add, evaluate, mul, neg, power, variables
from ..records import record
from ..units import IMPULSE, NONE
from .base import Check, Element, FrictionSite, ImpulseSource, Phase, SimRow, registrar
from .keys import Key, impulse_key, named_key, parameter_key
from .kinds import Component, KeyKind, PhaseKind, Regime, Restitution, Tangential

STICK_SLACK = 1e-12  # relative: |J_t| above mu J_n by more than this is a slide


class ContactRows:
    """What a contact's laws write rows over in one transition: the impulses jn (on body
    a, along n) and jt (along t = (-n_y, n_x); ZERO when smooth), the relative normal
    velocity of a's point to b's before and after (vn1, vn2) and the tangential (slip)
    one (vt1, vt2: formed when a law asks, a smooth contact never does)."""

    __slots__ = ("contact", "phase", "jn", "jt", "vn1", "vn2", "_r1", "_r2", "_tv", "_vt")

    def __init__(self, contact, phase: Phase, jn: E, jt: E, r1: V2, r2: V2, nv: V2, tv: V2):
        self.contact, self.phase, self.jn, self.jt = contact, phase, jn, jt
        self.vn1, self.vn2 = r1.dot(nv), r2.dot(nv)
        self._r1, self._r2, self._tv, self._vt = r1, r2, tv, None

    def _slip(self) -> tuple[E, E]:
        if self._vt is None:
            self._vt = (self._r1.dot(self._tv), self._r2.dot(self._tv))
        return self._vt

    @property
    def vt1(self) -> E:
        return self._slip()[0]

    @property
    def vt2(self) -> E:
        return self._slip()[1]

    @property
    def site(self) -> str:
        return f"{self.phase.key}:{self.contact.label}"


# ---- restitution laws (impacts) -------------------------------------------------------------
RESTITUTION_LAWS: dict[str, type["RestitutionLaw"]] = {}
restitution_law = registrar(RESTITUTION_LAWS)  # @restitution_law(KIND) on a subclass


class RestitutionLaw:
    """How the normal impulse of an impact ends. Subclasses stamp their own rows."""

    kind: Restitution
    owns_tangential = False  # True: the law writes the tangential rows itself

    def __init__(self, c):
        self.c = c

    def stamp_impact(self, rows: ContactRows, compiler) -> None:
        raise NotImplementedError

    def normal_loss(self, rows: ContactRows, compiler) -> E:
        """J_n (v_n- + v_n+): twice the work the normal impulse takes."""
        return mul(rows.jn, add(rows.vn1, rows.vn2))

    def sim_restitution(self) -> float:
        """The coefficient a simulation applies at each impact of this contact."""
        c = self.c
        raise ProblemError(f"simulate cannot apply {self.describe()} at contact {c.label}: "
                           "it needs a coefficient of restitution", c.law_span or c.span,
                           code="simulate", notes=["write `restitution 0.5` (a number) for "
                                                   "the simulation"])

    def describe(self) -> str:
        return str(self.kind)


@restitution_law(Restitution.NEWTON)
class NewtonRestitution(RestitutionLaw):
    """Newton's kinematic law: the normal separation speed is e times the approach speed."""

    def coefficient(self, compiler) -> E:
        c = self.c
        if c.restitution_unknown:
            key = named_key(c.restitution_name, KeyKind.RESTITUTION) if c.restitution_name \
                else parameter_key(Component.E, c.label)
            return compiler.unknown(key, NONE, KeyKind.RESTITUTION, "")
        return Known(parameter_key(Component.E, c.label), c.restitution)

    def normal_loss(self, rows: ContactRows, compiler) -> E:
        """Newton's law makes v_n- + v_n+ = (1 - e) v_n-, and 1 - e is exact near e = 1."""
        c = self.c
        one_minus_e = add(Const(1.0), neg(self.coefficient(compiler))) if c.restitution_unknown \
            else Const(1.0 - c.restitution)
        return mul(rows.jn, mul(one_minus_e, rows.vn1))

    def stamp_impact(self, rows: ContactRows, compiler) -> None:
        e = self.coefficient(compiler)
        compiler.eq(rows.vn2, mul(neg(e), rows.vn1), f"restitution at {self.c.label} (Newton)",
                    rows.phase.group, self.c.span)

    def describe(self) -> str:
        c = self.c
        if c.restitution_unknown:
            return f"restitution {c.restitution_name or '?'}"
        return f"restitution {c.restitution:g}"

    def sim_restitution(self) -> float:
        if self.c.restitution_unknown:
            return super().sim_restitution()  # found by `solve`, not known to a simulation
        # a contact that only persists (an interval's) closes plastically
        return self.c.restitution if self.c.restitution is not None else 0.0


@restitution_law(Restitution.SEPARATION)
class GivenSeparation(RestitutionLaw):
    """A given separation speed instead of Newton's law (an explosive separation)."""

    def stamp_impact(self, rows: ContactRows, compiler) -> None:
        c = self.c
        compiler.eq(rows.vn2, Known(parameter_key(Component.V_SEP, c.label), c.separation),
                    f"separation speed at {c.label} (given)", rows.phase.group, c.span)

    def describe(self) -> str:
        return f"separation {self.c.separation:g} m/s"


class PathRestitution(RestitutionLaw):
    """Poisson's or Stronge's law: the normal impulse ends where the impulse path (Coulomb
    friction integrated along P_n, `laws.impulse_path`) says; the solve resolves it between
    two passes (`contact_laws`), so the law also writes the tangential rows."""

    owns_tangential = True

    def stamp_impact(self, rows: ContactRows, compiler) -> None:
        from ..contact_laws import stamp_path_law

        ph = rows.phase
        stamp_path_law(compiler, ph, self.c, rows.jn, rows.jt, (rows.vt1, rows.vn1),
                       (rows.vt2, rows.vn2), ph.group)

    def describe(self) -> str:
        return f"restitution {self.c.restitution:g} {self.kind}"

    def sim_restitution(self) -> float:
        c = self.c
        raise ProblemError(f"simulate applies Newton's law at impacts; contact {c.label} has "
                           f"{self.describe()}", c.law_span or c.span, code="simulate",
                           notes=["write `restitution E` (Newton's law) in the simulation"])


@restitution_law(Restitution.POISSON)
class PoissonRestitution(PathRestitution):
    """Poisson: the normal impulse of restitution is e times that of compression."""


@restitution_law(Restitution.ENERGETIC)
class EnergeticRestitution(PathRestitution):
    """Stronge: the normal work of restitution is -e^2 times that of compression."""


# ---- tangential laws -------------------------------------------------------------------------
TANGENTIAL_LAWS: dict[Tangential, type["TangentialLaw"]] = {}
tangential_law = registrar(TANGENTIAL_LAWS)


class TangentialLaw:
    kind: Tangential
    has_impulse = True  # a tangential impulse J_t exists

    def __init__(self, c):
        self.c = c

    def stamp_impact(self, rows: ContactRows, compiler) -> None:
        pass

    def stamp_interval(self, rows: ContactRows, compiler) -> None:
        pass

    def loss(self, rows: ContactRows) -> E | None:
        """J_t (v_t- + v_t+): twice the work the tangential impulse takes (None: none)."""
        return mul(rows.jt, add(rows.vt1, rows.vt2)) if self.has_impulse else None

    def regimes(self) -> tuple[Regime, ...]:
        return ()

    # simulate: the regime of a persistent contact (REST, STICK, or the slip sign +-1.0)
    def sim_regime(self, slip: float, tol: float):
        return Regime.STICK

    def stick_holds(self, jt: float, jn: float) -> bool:
        """Whether a sticking contact's tangential impulse (or force) jt is inside the
        cone of its normal one jn."""
        return True

    def sim_column(self, rn, rt, regime):
        """The column of B that carries the normal force of a persistent contact (a
        sliding one also carries its friction, -mu N along the slip)."""
        return rn

    def sim_power(self, normal: float, slip: float, regime) -> float:
        """The power of the tangential force of a persistent contact."""
        return 0.0

    def friction_detail(self, jt: float, jn: float) -> str:
        return f"|J_t| = {abs(jt):.6g} N*s"

    def _static_site(self, rows: ContactRows, compiler, jt_name: str | None = None,
                     then: str = "") -> None:
        """With `static MU`: the friction a no-slip (or a hold) needs is checked against it."""
        mu = getattr(self.c, "mu_static", None)
        if mu is not None:
            self.then = then
            compiler.friction.append(FrictionSite(rows.site, self.c.label, rows.phase.key, mu,
                                                  rows.jn.name, jt_name or rows.jt.name,
                                                  Regime.NO_SLIP, None, self.c.span, True, self))

    def static_check(self, jt: float, jn: float) -> tuple[str, str]:
        """(status, detail) of the friction needed against the static coefficient."""
        mu = self.c.mu_static
        ok = not abs(jt) > mu * jn * (1 + STICK_SLACK) + 1e-300
        need = f"{abs(jt) / jn:.6g}" if jn > 0 else "inf"
        detail = f"{self.holding} needs mu >= |J_t|/J_n = {need}; static {mu:g}"
        if ok:
            return "ok", detail + ": it holds"
        then = getattr(self, "then", "")
        return ("ok" if then else "warning"), detail + ": it slips" + (
            f" ({then})" if then else " (give `friction MU` for the sliding case)")

    holding = "no slip"

    def describe(self) -> str:
        return str(self.kind)


@tangential_law(Tangential.SMOOTH)
class Smooth(TangentialLaw):
    has_impulse = False

    def sim_regime(self, slip: float, tol: float):
        return Regime.REST


@tangential_law(Tangential.ROUGH)
class Rough(TangentialLaw):
    """No slip after the impact (enough friction to stop it)."""

    def loss(self, rows: ContactRows) -> E | None:
        return mul(rows.jt, rows.vt1) if rows.phase.kind is PhaseKind.IMPACT else \
            super().loss(rows)  # v_t+ = 0 in an impact: drop it

    def stamp_impact(self, rows: ContactRows, compiler) -> None:
        compiler.eq(rows.vt2, ZERO, f"no slip at {self.c.label} (rough)", rows.phase.group,
                    self.c.span)
        self._static_site(rows, compiler)

    def stamp_interval(self, rows: ContactRows, compiler) -> None:
        """No slip at either end: with constant forces the slip rate changes linearly, so
        none throughout (rolling). The friction impulse J_t is what that needs."""
        for sid, vt in ((rows.phase.before, rows.vt1), (rows.phase.after, rows.vt2)):
            compiler.eq(vt, ZERO, f"no slip at {self.c.label} (rough: throughout)",
                        f"state {sid}", self.c.span)
        self._static_site(rows, compiler)

    def stick_holds(self, jt: float, jn: float) -> bool:
        mu = getattr(self.c, "mu_static", None)
        return mu is None or not abs(jt) > mu * jn * (1 + STICK_SLACK) + 1e-300

    def friction_detail(self, jt: float, jn: float) -> str:
        mu = getattr(self.c, "mu_static", None)
        if mu is None or jn <= 0:
            return super().friction_detail(jt, jn)
        return f"no slip needs mu >= |J_t|/J_n = {abs(jt) / jn:.6g}; static {mu:g}"


@tangential_law(Tangential.FRICTION)
class Coulomb(TangentialLaw):
    """Coulomb friction: stick (|J_t| <= mu J_n, checked) or slide (J_t = -mu J_n sgn slip)."""

    @property
    def mu(self) -> float:
        return self.c.mu

    def regimes(self) -> tuple[Regime, ...]:
        return (Regime.STICK, Regime.SLIDE_POS, Regime.SLIDE_NEG)

    def stick_holds(self, jt: float, jn: float) -> bool:
        return not abs(jt) > self.mu * jn * (1 + STICK_SLACK) + 1e-300

    def slide_row(self, rows: ContactRows, regime: Regime, principle: str, compiler) -> None:
        compiler.eq(rows.jt, mul(Const(-regime.sign * self.mu), rows.jn), principle,
                    rows.phase.group, self.c.span)

    def stamp_impact(self, rows: ContactRows, compiler) -> None:
        c = self.c
        regime = Regime(compiler.regimes.get(rows.site, Regime.STICK))
        if regime is Regime.STICK:
            compiler.eq(rows.vt2, ZERO, f"stick at {c.label} (assumed; |J_t| <= mu J_n checked)",
                        rows.phase.group, c.span)
        else:
            self.slide_row(rows, regime, f"sliding friction at {c.label}: J_t = -mu J_n "
                           "against the slip", compiler)
        compiler.friction.append(FrictionSite(rows.site, c.label, rows.phase.key, c.mu,
                                              rows.jn.name, rows.jt.name, regime, rows.vt1,
                                              c.span, law=self, slip_after=rows.vt2))

    def stamp_interval(self, rows: ContactRows, compiler) -> None:
        c = self.c
        s = self.slip_sign(rows.vt1, rows.phase)
        decided = s is not None
        if s is None:
            regime = Regime(compiler.regimes.get(rows.site, Regime.SLIDE_POS))
        else:
            regime = Regime.sliding(s)
        self.slide_row(rows, regime, f"kinetic friction at {c.label}: J_t = -mu J_n against "
                       "the slip", compiler)
        compiler.friction.append(FrictionSite(rows.site, c.label, rows.phase.key, c.mu,
                                              rows.jn.name, rows.jt.name, regime, rows.vt1,
                                              c.span, decided, self))
        self._hold_at_stop(rows, compiler)

    holding = "at the stop, holding it"

    def _hold_at_stop(self, rows: ContactRows, compiler) -> None:
        """`friction MU static MUS` on a particle that stops at the interval's end: would
        static friction hold it? With the interval's other forces still acting, holding
        needs the tangential impulse J_hold = m (v2 - v1).t - J_t over the same time,
        against mu_s J_n."""
        c, phase = self.c, rows.phase
        t = compiler.tspecs.get(phase.key)
        body = c.a.body
        if getattr(c, "mu_static", None) is None or t is None or \
                body not in {b for b, _ in t.stops} or \
                not compiler.scene.bodies[body].is_particle:
            return
        tg = V2(Const(-c.normal[1]), Const(c.normal[0]))
        dv = compiler.vel(body, phase.after) - compiler.vel(body, phase.before)
        key = impulse_key(Component.J_HOLD, c.label, phase.key)
        hold = compiler.unknown(key, IMPULSE, KeyKind.DERIVED)
        compiler.eq(hold, add(mul(compiler.mass(body, phase.before), dv.dot(tg)), neg(rows.jt)),
                    f"friction that would hold {body} at the stop", phase.group, c.span)
        later = [x for x in compiler.scene.transitions if x.before == phase.after]
        self._static_site(rows, compiler, hold.name,
                          f"transition {later[0].key} follows" if later else "")

    def next_regime(self, site: FrictionSite, values: dict) -> Regime | None:
        """The regime to try next after solving with `site.regime`, or None if it held:
        a stick whose |J_t| exceeds mu J_n slides against J_t; an interval's slide whose
        slip direction was not known beforehand follows the solved slip."""
        if site.jn not in values:
            return None
        jn = values[site.jn]
        jt = values.get(site.jt, 0.0) if site.jt else 0.0
        if site.regime == Regime.STICK:
            return None if self.stick_holds(jt, jn) else Regime.sliding(-jt)
        if site.slip_expr is None or site.decided:
            return None
        try:
            slip = evaluate(site.slip_expr, values)
        except KeyError:
            return None
        want = Regime.sliding(slip)
        return want if slip != 0 and want != site.regime else None

    def violation(self, site: FrictionSite, values: dict) -> str | None:
        """Why an impact's solved impulses break Coulomb's law in `site.regime` (None: they
        keep it): a stick outside the friction cone; a slide that pulls (J_n < 0), whose
        slip before the impact runs the other way, or whose slip the friction reversed."""
        jn = values[site.jn]
        jt = values.get(site.jt, 0.0) if site.jt else 0.0
        if site.regime == Regime.STICK:
            if self.stick_holds(jt, jn):
                return None
            return (f"sticking needs |J_t| = {abs(jt):.6g} <= mu J_n = {self.mu * jn:.6g} N*s")
        vt1, vt2 = evaluate(site.slip_expr, values), evaluate(site.slip_after, values)
        s = site.regime.sign
        if jn < -1e-9 * abs(jt):
            return f"sliding with J_n = {jn:.6g} N*s < 0 (the contact would pull)"
        tol = 1e-9 * max(abs(vt1), abs(vt2)) + 1e-15
        if s * vt1 < -tol:
            return (f"sliding along {'+' if s > 0 else '-'}t, but the slip before the impact "
                    f"is {vt1:.6g} m/s")
        if s * vt2 < -tol:
            return f"friction reversed the slip (after the impact it is {vt2:.6g} m/s)"
        return None

    def slip_sign(self, vt1: E, phase: Phase) -> float | None:
        """The slip direction over an interval: given, or known from the start state."""
        c = self.c
        if c.slip is not None:
            tg = (-c.normal[1], c.normal[0])
            d = c.slip[0] * tg[0] + c.slip[1] * tg[1]
            if abs(d) < 1e-12:
                raise ProblemError("the slip direction is along the normal; give a direction "
                                   "along the surface", c.span, code="name")
            return 1.0 if d > 0 else -1.0
        if not variables(vt1):
            v = evaluate(vt1, {})
            if v == 0:
                raise ProblemError(f"contact {c.label} does not slip at state {phase.before}: "
                                   "kinetic friction needs a slip direction", c.span,
                                   code="name",
                                   notes=["give `slip (dx, dy)`, or make the body roll"])
            return 1.0 if v > 0 else -1.0
        return None

    def sim_column(self, rn, rt, regime):
        if regime in (1.0, -1.0):
            return rn - self.mu * regime * rt
        return rn

    def sim_power(self, normal: float, slip: float, regime) -> float:
        if regime in (1.0, -1.0):
            return -self.mu * max(normal, 0.0) * abs(slip)
        return 0.0

    def sim_regime(self, slip: float, tol: float):
        if not self.mu:
            return Regime.REST  # mu = 0: smooth
        if abs(slip) <= tol:
            return Regime.STICK
        return 1.0 if slip > 0 else -1.0

    def describe(self) -> str:
        return f"friction {self.mu:g}"


# ---- the element --------------------------------------------------------------------------------
class ContactElement(Element):
    """One contact clause of a transition: its restitution law and its tangential law."""

    def __init__(self, c):
        self.c = c
        self.label = c.label
        self.span = c.span
        law = getattr(c, "law", None) or (Restitution.SEPARATION if c.separation is not None
                                          else Restitution.NEWTON)
        self.restitution = RESTITUTION_LAWS[law](c)
        self.tangential = TANGENTIAL_LAWS[Tangential(c.mode)](c)

    def bodies(self) -> tuple[str | None, ...]:
        return (self.c.a.body, self.c.b.body if self.c.b is not None else None)

    def unknowns(self, phase: Phase) -> list[Key]:
        out = [impulse_key(Component.JN, self.label, phase.key)]
        if self.tangential.has_impulse:
            out.append(impulse_key(Component.JT, self.label, phase.key))
        return out

    def regimes(self) -> tuple[Regime, ...]:
        return self.tangential.regimes()

    def check(self, values: dict) -> list[Check]:
        """A compressive normal impulse; friction inside its cone."""
        out = []
        for k, x in values.items():
            if not isinstance(k, Key) or k.label != self.label:
                continue
            if k.comp is Component.JN:
                out.append(Check(f"contact {k}", x >= 0, f"J_n = {x:.6g} N*s"))
                jt = values.get(impulse_key(Component.JT, self.label, k.transition), 0.0)
                out.append(Check(f"friction at {self.label} ({k.transition})",
                                 self.tangential.stick_holds(jt, x),
                                 self.tangential.friction_detail(jt, x)))
        return out

    def describe(self) -> str:
        return f"contact {self.label}: {self.restitution.describe()}, " \
               f"{self.tangential.describe()}"

    def stamp(self, phase: Phase, compiler) -> None:
        c = self.c
        n = c.normal
        if phase.kind is PhaseKind.IMPACT and type(self.tangential) is Smooth and \
                type(self.restitution) is NewtonRestitution and not c.restitution_unknown \
                and type(c.restitution) is float and type(n[0]) is float and \
                type(n[1]) is float:
            return self._stamp_smooth_newton(phase, compiler)
        tg = (-n[1], n[0])
        nv, tv = V2(Const(n[0]), Const(n[1])), V2(Const(tg[0]), Const(tg[1]))
        keys = self.unknowns(phase)
        Jn = compiler.unknown(keys[0], IMPULSE, KeyKind.IMPULSE)
        compiler.unknowns[keys[0]].hints.append((">", 0.0, c.span))
        Jt: E = ZERO
        if len(keys) > 1:
            Jt = compiler.unknown(keys[1], IMPULSE, KeyKind.IMPULSE)
        J = V2(add(mul(Jn, nv.x), mul(Jt, tv.x)), add(mul(Jn, nv.y), mul(Jt, tv.y)))
        phase.apply(c.a, J, None, n, 1.0)
        if c.b is not None:
            phase.apply(c.b, -J, None, n, -1.0)
        # a round body touches at its rim (G - r n), not at its centre
        body_a = compiler.scene.bodies[c.a.body]
        where = f"{c.label}'s contact point" if c.a.round_contact and body_a.radius else c.a.name
        phase.sources.append(ImpulseSource(self.bodies(), where,
                                           None if self.tangential.has_impulse else n, False,
                                           f"contact {c.label}"))
        r1, r2 = self.relative_velocity(phase.before, compiler), \
            self.relative_velocity(phase.after, compiler)
        rows = ContactRows(self, phase, Jn, Jt, r1, r2, nv, tv)
        if phase.kind is PhaseKind.IMPACT:
            compiler.losses.setdefault(phase.key, []).append(self.energy_loss(rows, compiler))
            self.restitution.stamp_impact(rows, compiler)
            phase.contacts.append((c.label, rows.vn1, rows.vn2))
            if not self.restitution.owns_tangential:
                self.tangential.stamp_impact(rows, compiler)
        else:
            # an interval contact persists: no normal relative velocity at either end
            for sid, vn in ((phase.before, rows.vn1), (phase.after, rows.vn2)):
                compiler.eq(vn, ZERO, f"contact {c.label} persists (no normal velocity)",
                            f"state {sid}", c.span)
            self.tangential.stamp_interval(rows, compiler)

    def _stamp_smooth_newton(self, phase: Phase, compiler) -> None:
        """`stamp` for the commonest contact, in an impact: smooth, Newton's law with a
        given e (one unknown J_n, one row). The same nodes in the same order as the
        general path (tests/test_compile_equal.py), without its rows object and laws'
        dispatch: a chain of N balls stamps N of these."""
        c = self.c
        n = c.normal
        n0, n1 = n
        key = f"{phase.before}->{phase.after}"
        kn = impulse_key(Component.JN, self.label, key)
        Jn = compiler.unknown(kn, IMPULSE, KeyKind.IMPULSE)
        compiler.unknowns[kn].hints.append((">", 0.0, c.span))
        J = V2(_along(Jn, n0, -n1), _along(Jn, n1, n0))
        phase.apply(c.a, J, None, n, 1.0)
        if c.b is not None:
            phase.apply(c.b, -J, None, n, -1.0)
        body_a = compiler.scene.bodies[c.a.body]
        where = f"{c.label}'s contact point" if c.a.round_contact and body_a.radius else c.a.name
        phase.sources.append(ImpulseSource(self.bodies(), where, n, False, f"contact {c.label}"))
        r1, r2 = self.relative_velocity(phase.before, compiler), \
            self.relative_velocity(phase.after, compiler)
        nv = V2(Const(n0), Const(n1))
        vn1, vn2 = r1.dot(nv), r2.dot(nv)
        e = c.restitution
        # energy_loss: -1/2 J_n (1 - e) v_n- (Newton's normal_loss; smooth: no tangent)
        compiler.losses.setdefault(key, []).append(
            mul(Const(-0.5), mul(Jn, mul(Const(1.0 - e), vn1))))
        E_ = Known(parameter_key(Component.E, c.label), e)
        compiler.eq(vn2, mul(neg(E_), vn1), f"restitution at {c.label} (Newton)", phase.group,
                    c.span)
        phase.contacts.append((c.label, vn1, vn2))

    def energy_loss(self, rows: ContactRows, compiler) -> E:
        """The kinetic energy the contact takes in an impact, -J.(v- + v+)/2 along its
        impulse, in the form each law makes free of cancellation (T1 - T2 loses every
        digit when little is lost)."""
        normal = self.restitution.normal_loss(rows, compiler)
        tangent = self.tangential.loss(rows)
        if self.restitution.owns_tangential and tangent is not None:  # its own tangential rows
            tangent = mul(rows.jt, add(rows.vt1, rows.vt2))
        return mul(Const(-0.5), normal if tangent is None else add(normal, tangent))

    def constraint(self, frame, watch, geometry, regime) -> list[SimRow]:
        """Simulate: a persistent contact's normal row (its column carries a sliding
        friction too) and, sticking, its tangential row."""
        rn, bn = frame.normal_row(watch, geometry)
        col = rn
        if regime in (1.0, -1.0):
            rt, _, _ = frame.tangent_row(watch, geometry)
            col = self.tangential.sim_column(rn, rt, regime)
        out = [SimRow(f"N[{watch.label}]", rn, bn, col=col)]
        if regime == Regime.STICK:
            rt, bt, _ = frame.tangent_row(watch, geometry)
            out.append(SimRow(f"F_t[{watch.label}]", rt, bt))
        return out

    def relative_velocity(self, sid: str, compiler) -> V2:
        c = self.c
        va = compiler.point_velocity(c.a, sid, c.normal, 1.0)
        vb = compiler.point_velocity(c.b, sid, c.normal, -1.0) if c.b is not None \
            else V2(ZERO, ZERO)
        return va - vb


def _along(Jn: E, a: float, b: float) -> E:
    """J_n a + 0 b as `add(mul(Jn, Const(a)), mul(ZERO, Const(b)))` folds it (a smooth
    contact's impulse component, J_t = 0), without the calls and their spare leaves."""
    if type(a) is not float or type(b) is not float:
        pass
    elif a == 0.0:
        if b - b == 0.0:  # finite: 0 * b is a zero, and 0 + it is it
            return Const(0.0 * b)
    elif a == 1.0:
        if b - b == 0.0:
            return Jn
    elif a - a == 0.0 and b - b == 0.0:
        return Mul((Const(a), Jn))
    return add(mul(Jn, Const(a)), mul(ZERO, Const(b)))


class PlanFriction(Element):
    """Kinetic friction with the ground in plan view (`gravity ... into plane`): over an
    interval the ground pushes against the body's velocity at the start with mu m g, at
    its centre (no moment; the skid runs straight, so the direction holds throughout):
    J = -mu m g t v1/|v1|, an impulse of its own, `J[LABEL]@1->2` in magnitude."""

    def __init__(self, c):
        self.c = c
        self.label = c.label
        self.span = c.span

    def bodies(self) -> tuple[str | None, ...]:
        return (self.c.a.body, None)

    def unknowns(self, phase: Phase) -> list[Key]:
        return [impulse_key(Component.JX, self.label, phase.key),
                impulse_key(Component.JY, self.label, phase.key)]

    def stamp(self, phase: Phase, compiler) -> None:
        c, sc = self.c, compiler.scene
        if phase.kind is not PhaseKind.INTERVAL:
            raise ProblemError("friction with the ground in plan view acts over an interval; "
                               "an impact needs a normal", c.span, code="name")
        body = c.a.body
        v = compiler.vel(body, phase.before)
        speed = power(add(mul(v.x, v.x), mul(v.y, v.y)), 0.5)
        if not variables(speed) and evaluate(speed, {}) == 0:
            raise ProblemError(f"{body} is at rest in state {phase.before}: kinetic friction "
                               "needs it to slide", c.span, code="name")
        kx, ky = self.unknowns(phase)
        J = V2(compiler.unknown(kx, IMPULSE, KeyKind.IMPULSE),
               compiler.unknown(ky, IMPULSE, KeyKind.IMPULSE))
        # along the velocity (J x v1 = 0) and against it with mu m g t: J . v1 = -mu m g t |v1|
        m_g = mul(compiler.mass(body, phase.before), Known("g", sc.g))
        compiler.eq(J.cross(v), ZERO, f"plan-view friction on {body}: along its velocity",
                    phase.group, c.span)
        compiler.eq(J.dot(v), neg(mul(mul(mul(Const(c.mu), m_g), phase.dur()), speed)),
                    f"plan-view friction on {body}: mu m g t against its velocity (normal "
                    "force: the weight)", phase.group, c.span)
        phase.apply(c.a, J, None)  # at G: c.a is the body itself
        phase.sources.append(ImpulseSource((body, None), body, None, False,
                                           f"friction on {body}"))

    def describe(self) -> str:
        return f"contact {self.label}: plan-view friction {self.c.mu:g}"


def contact_element(c) -> Element:
    """The element for a contact record: plan-view friction when it has no normal."""
    return PlanFriction(c) if c.normal is None else ContactElement(c)
