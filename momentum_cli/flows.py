"""Open systems: steady flow through control volumes, and bodies that burn mass.

Part of `compile`. A control volume in steady flow (constant velocity u, steady in
its own frame) balances forces with momentum fluxes:
    sum F + sum_in mdot v - sum_out mdot v = 0
    sum M_O + sum_in r x mdot v - sum_out r x mdot v = 0     (about its origin O)
with absolute velocities v (a `relative` velocity is u + v_rel), and its mass
balance sum_in mdot = sum_out mdot. A support is an unknown force and moment.

A burning particle (constant exhaust speed c relative to it, along e, constant
rate mdot, gravity g) has the closed form of the rocket equation:
    m1 = m0 - mdot t,   v1 = v0 - e c ln(m0/m1) + g t,
    r1 = r0 + v0 t + g t^2/2 - e c (t - (m1/mdot) ln(m0/m1)),
evaluated without cancellation (massratio.py) when the rate, time and mass are known
numbers. A burn whose rate or exhaust speed varies is an integration block
(integration.py) that solve runs.
"""
from __future__ import annotations

import math

from . import syntax as S
from .diagnostics import ProblemError
from .expr import (
    V2,
    Const,
    E,
    Known,
    Var,
    add_all,
    evaluate,
    fn,
    mul,
    neg,
    power,
    variables,
)
from .integration import Integration, emit
from .massratio import burn_drift
from .records import record
from .scene import unit_direction
from .units import FORCE, LENGTH, MASS, MOMENT, NONE, TIME, VELOCITY, describe

MASS_RATE = (1, 0, -1)
BURN_TIME = "t~burn"  # a burn's own time, in `rate` and `exhaust` expressions
RTOL = 1e-10  # relative tolerance of the numerical integration of a varying burn
WEIGHT_RATE = (1, 1, -3)


@record
class FlowRow:
    """One row of a control volume's flux table (expressions, evaluated in the report)."""

    volume: str
    what: str  # inflow | outflow | force | support
    line: int
    rate: E | None
    velocity: V2 | None  # absolute
    at: V2
    sign: float  # +1 for an inflow's flux into the balance, -1 for an outflow


class FlowCompiler:
    """Adds the balances of `steady` and `burn` statements to a compiler's system."""

    def __init__(self, compiler):
        self.c = compiler
        self.rows: list[FlowRow] = []
        self.masses: dict[tuple[str, str], E] = {}  # (body, state) -> mass after a burn
        self.durations: dict[str, E] = {}  # "1->2" -> burn time
        self.integrations: list[Integration] = []  # phases solve integrates numerically

    # ---- evaluation helpers
    def _evaluator(self):
        """The compiler's evaluator, where a bare `t` is the time since a burn began."""
        from .quantity import Evaluator, Q

        base = self.c._evaluator()

        def resolve(ref, expect):
            if ref.name == "t" and not (ref.index or ref.member or ref.at):
                return Q(Var(BURN_TIME), TIME)
            return base.resolve(ref, expect)

        return Evaluator(resolve)

    def _q(self, node, dim, what: str, vector: bool = False):
        q = self._evaluator()(node, dim)
        if q.is_vector != vector:
            kind = "a vector such as (1, 0)" if vector else "a scalar"
            raise ProblemError(f"{what} needs {kind}", node.span, code="type")
        if q.dim != dim:
            raise ProblemError(f"{what} needs {describe(dim)}; got {describe(q.dim)}", node.span,
                               code="units")
        return q.value

    def _rate(self, node, what: str) -> E:
        """A mass rate; a weight rate (lb/s) becomes mass with the file's g."""
        # `lb/s` reads as a weight rate first (as `lb` reads as a weight), kg/s as a mass rate
        q = self._evaluator()(node, WEIGHT_RATE)
        if q.is_vector:
            raise ProblemError(f"{what} needs a scalar", node.span, code="type")
        if q.dim == WEIGHT_RATE:
            g = self.c.scene.g
            if g is None:
                raise ProblemError("a weight rate needs the file's g: declare gravity", node.span,
                                   code="name")
            return mul(q.value, Const(1.0 / g))
        if q.dim != MASS_RATE:
            raise ProblemError(f"{what} needs a mass rate such as 2 kg/s; got {describe(q.dim)}",
                               node.span, code="units")
        if isinstance(q.value, Const) and q.value.value < 0:
            raise ProblemError(f"{what} cannot be negative (an outflow is written `outflow`)",
                               node.span, code="number")
        return q.value

    def gain(self, g: S.GainDecl) -> None:
        """A particle gaining or losing mass over an interval (accretion.py)."""
        from .accretion import AccretionCompiler

        AccretionCompiler(self).compile(g)

    # ---- steady control volumes
    def steady(self, cv: S.SteadyDecl) -> None:
        c = self.c
        group = f"steady flow through {cv.name}"
        u = self._q(cv.moving, VELOCITY, "the control volume's velocity", True) \
            if cv.moving is not None else V2(Const(0.0), Const(0.0))
        fx, fy, mz = [], [], []
        mass_in, mass_out = [], []
        for f in cv.flows:
            at = self._q(f.at, LENGTH, "a position", True) if f.at is not None else \
                V2(Const(0.0), Const(0.0))
            if f.kind == "force":
                F = self._q(f.velocity, FORCE, "a force", True)
                fx.append(F.x)
                fy.append(F.y)
                mz.append(at.cross(F))
                self.rows.append(FlowRow(cv.name, "force", f.span.line, None, F, at, 1.0))
                continue
            if f.rate is None or f.velocity is None:
                raise ProblemError(f"an {f.kind} needs `rate` and `velocity`", f.span,
                                   code="name")
            mdot = self._rate(f.rate, f"an {f.kind}'s rate")
            v = self._q(f.velocity, VELOCITY, f"an {f.kind}'s velocity", True)
            if f.relative:
                v = u + v
            sign = 1.0 if f.kind == "inflow" else -1.0
            flux = v.scale(mul(Const(sign), mdot))
            fx.append(flux.x)
            fy.append(flux.y)
            mz.append(at.cross(flux))
            (mass_in if sign > 0 else mass_out).append(mdot)
            self.rows.append(FlowRow(cv.name, f.kind, f.span.line, mdot, v, at, sign))
        for s in cv.supports:
            Fx = c.unknown(f"Fx[{s}]", FORCE, "force", "N")
            Fy = c.unknown(f"Fy[{s}]", FORCE, "force", "N")
            M = c.unknown(f"M[{s}]", MOMENT, "moment", "N*m")
            fx.append(Fx)
            fy.append(Fy)
            mz.append(M)
        span = cv.span
        rate_x = rate_y = Const(0.0)  # dP/dt of the contents
        if cv.instant:
            group = f"open system {cv.name} at this instant"
            # dP/dt = m a + (dm/dt) v, with dm/dt = sum_in mdot - sum_out mdot
            m = self._q(cv.mass, MASS, "the contents' mass") if cv.mass is not None else None
            v = self._q(cv.velocity, VELOCITY, "the contents' velocity", True) \
                if cv.velocity is not None else u
            a = self._q(cv.acceleration, (0, 1, -2), "the contents' acceleration", True) \
                if cv.acceleration is not None else V2(Const(0.0), Const(0.0))
            if m is None:
                raise ProblemError("an instant's contents need a mass: `contents mass 2 kg, "
                                   "velocity (0, 1 m/s), acceleration (0, 0)`", cv.span,
                                   code="name")
            dm = add_all(mass_in + [neg(x) for x in mass_out])
            rate_x = add_all([mul(m, a.x), mul(dm, v.x)])
            rate_y = add_all([mul(m, a.y), mul(dm, v.y)])
            if self.c.scene.gravity is not None:  # the contents' weight
                gx, gy = self.c.scene.gravity
                fx.append(mul(m, Const(gx)))
                fy.append(mul(m, Const(gy)))
            what = "sum F + sum_in mdot v - sum_out mdot v = m a + (dm/dt) v"
        else:
            c.eq(add_all(mass_in), add_all(mass_out),
                 f"mass balance of {cv.name}: sum_in mdot = sum_out mdot", group, span,
                 "consistency")
            what = "sum F + sum_in mdot v - sum_out mdot v = 0"
        c.eq(add_all(fx), rate_x, f"momentum balance x of {cv.name}: {what}", group, span)
        c.eq(add_all(fy), rate_y, f"momentum balance y of {cv.name}: {what}", group, span)
        c.eq(add_all(mz), Const(0.0),
             f"angular momentum balance of {cv.name} about its origin: sum M + sum_in r x mdot v"
             " - sum_out r x mdot v = 0", group, span)

    # ---- burning bodies
    def burn(self, b: S.BurnDecl) -> None:
        c = self.c
        key = f"{b.before}->{b.after}"
        speed = self._q(b.exhaust, VELOCITY, "the exhaust speed", False)
        d = self._q(b.direction, NONE, "the exhaust direction", True)
        if not (isinstance(d.x, Const) and isinstance(d.y, Const)):
            raise ProblemError("the exhaust direction must be a constant", b.direction.span,
                               code="type")
        e = unit_direction(d.x.value, d.y.value, b.direction, "the exhaust direction")
        if b.rate is None:
            return self._burn_no_rate(b, speed, e)
        mdot = self._rate(b.rate, "the burn rate")
        if isinstance(mdot, Const) and (mdot.value < 0 or mdot.value == 0 and b.burned
                                        is not None):
            raise ProblemError("the burn rate must be positive", b.rate.span, code="number")
        m0 = c.mass(b.body, b.before)  # what earlier burns left, or the declared mass
        if BURN_TIME in variables(mdot) or BURN_TIME in variables(speed):
            return self._burn_integrated(b, mdot, speed, e, m0)
        if b.burned is not None:
            dm = self._q(b.burned, MASS, "the mass burned", False)
            t = mul(dm, power(mdot, -1.0))
        else:
            t = self._q(b.duration, TIME, "the burn's duration", False)
            dm = mul(mdot, t)
        m1 = self._burn_out(b, m0, dm)
        self.durations[key] = t
        if not (variables(m0) or variables(dm) or variables(t)):
            return self._burn_numbers(b, speed, e, evaluate(m0, {}), evaluate(dm, {}), t)
        self._burn_closed(b, mdot, speed, e, m0, m1, t)

    def _burn_closed(self, b: S.BurnDecl, mdot: E, speed: E, e, m0: E, m1: E, t: E) -> None:
        """The rocket equation and the path, in symbols (some of rate, time, mass unknown)."""
        c = self.c
        group = f"burn {b.body} {b.before} -> {b.after}"
        g = c.scene.gravity or (0.0, 0.0)
        ln = fn("ln", mul(m0, power(m1, -1.0)))
        i, j = b.before, b.after
        span = b.span
        v0, v1 = c.vel(b.body, i), c.vel(b.body, j)
        r0, r1 = c.pos(b.body, i), c.pos(b.body, j)
        drift = add_all([t, neg(mul(mul(m1, power(mdot, -1.0)), ln))])
        for comp, ek, gk, a0, a1, p0, p1 in (("x", e[0], g[0], v0.x, v1.x, r0.x, r1.x),
                                             ("y", e[1], g[1], v0.y, v1.y, r0.y, r1.y)):
            c.eq(a1, add_all([a0, mul(Const(-ek), mul(speed, ln)), mul(Const(gk), t)]),
                 f"rocket equation {comp} (closed form: constant exhaust speed and rate): "
                 "v1 = v0 - e c ln(m0/m1) + g t", group, span)
            c.eq(p1, add_all([p0, mul(a0, t), mul(Const(0.5 * gk), mul(t, t)),
                              mul(Const(-ek), mul(speed, drift))]),
                 f"position {comp} at the end of the burn (closed form): r1 = r0 + v0 t + g t^2/2"
                 " - e c (t - (m1/mdot) ln(m0/m1))", group, span)

    def _burn_out(self, b, m0: E, dm: E) -> E:
        """The body's mass after a burn takes dm out of m0 (what later phases see); a
        located error when nothing would be left."""
        m_before = evaluate(m0, {}) if not variables(m0) else None
        if isinstance(dm, Const) and m_before is not None and dm.value >= m_before:
            raise ProblemError(f"the burn takes {dm.value:g} kg out of a body of {m_before:g} "
                               "kg: no mass would be left", b.span, code="number")
        m1 = add_all([m0, neg(dm)])
        self.masses[(b.body, b.after)] = m1
        return m1

    def _burn_no_rate(self, b: S.BurnDecl, speed: E, e) -> None:
        """A burn given by the mass it burns alone: the rocket equation's change of velocity
        does not depend on the rate; the time (and so the path and gravity's share) does,
        so it needs a `duration` or no gravity along the motion."""
        c = self.c
        group = f"burn {b.body} {b.before} -> {b.after}"
        m0 = c.mass(b.body, b.before)
        dm = self._q(b.burned, MASS, "the mass burned", False)
        m1 = self._burn_out(b, m0, dm)
        key = f"{b.before}->{b.after}"
        if b.duration is not None:
            t = self._q(b.duration, TIME, "the burn's duration", False)
            self.durations[key] = t
            mdot = mul(dm, power(t, -1.0))
            if not (variables(m0) or variables(dm) or variables(t)):
                return self._burn_numbers(b, speed, e, evaluate(m0, {}), evaluate(dm, {}), t)
            return self._burn_closed(b, mdot, speed, e, m0, m1, t)
        g = c.scene.gravity or (0.0, 0.0)
        if g != (0.0, 0.0):
            raise ProblemError("under gravity a burn's time matters: give its `rate MASS_RATE` "
                               "or `duration TIME`", b.span, code="name")
        ln = fn("ln", mul(m0, power(m1, -1.0)))
        v0, v1 = c.vel(b.body, b.before), c.vel(b.body, b.after)
        for comp, ek, a0, a1 in (("x", e[0], v0.x, v1.x), ("y", e[1], v0.y, v1.y)):
            c.eq(a1, add_all([a0, mul(Const(-ek), mul(speed, ln))]),
                 f"rocket equation {comp} (constant exhaust speed, any rate): "
                 "v1 = v0 - e c ln(m0/m1)", group, b.span)

    def _burn_numbers(self, b: S.BurnDecl, speed: E, e, m0: float, dm: float,
                      t: E) -> None:
        """The rocket equation with known rate, time and mass: with the fraction burnt
        x = dm/m0, ln(m0/m1) = -log1p(-x) and t - (m1/mdot) ln(m0/m1) = t x D(x),
        D = 1/2 + x/6 + ... (massratio.py): exact down to a vanishing rate."""
        c = self.c
        group = f"burn {b.body} {b.before} -> {b.after}"
        x = dm / m0
        ln = Known("ln(m0/m1)", -math.log1p(-x))
        drift = mul(t, Known("x*D(x)", x * burn_drift(x)))
        g = c.scene.gravity or (0.0, 0.0)
        i, j = b.before, b.after
        v0, v1 = c.vel(b.body, i), c.vel(b.body, j)
        r0, r1 = c.pos(b.body, i), c.pos(b.body, j)
        for comp, ek, gk, a0, a1, p0, p1 in (("x", e[0], g[0], v0.x, v1.x, r0.x, r1.x),
                                             ("y", e[1], g[1], v0.y, v1.y, r0.y, r1.y)):
            c.eq(a1, add_all([a0, mul(Const(-ek), mul(speed, ln)), mul(Const(gk), t)]),
                 f"rocket equation {comp} (closed form: constant exhaust speed and rate): "
                 "v1 = v0 - e c ln(m0/m1) + g t, ln(m0/m1) = -ln(1 - x), x = mdot t/m0",
                 group, b.span)
            c.eq(p1, add_all([p0, mul(a0, t), mul(Const(0.5 * gk), mul(t, t)),
                              mul(Const(-ek), mul(speed, drift))]),
                 f"position {comp} at the end of the burn (closed form): r1 = r0 + v0 t + g t^2/2"
                 " - e c t x D(x), D = (1 - (1 - x) ln(1/(1 - x))/x)/x = 1/2 + x/6 + x^2/12 + "
                 "... (series for small x)", group, b.span)

    def _burn_integrated(self, b: S.BurnDecl, mdot: E, speed: E, e, m0: E) -> None:
        """A burn whose rate or exhaust speed varies with its time t: no closed form, so an
        integration block (integration.py) of dM/dt = mdot, dV/dt = c mdot/(m0 - M),
        dX/dt = V (scipy's DOP853 at rtol 1e-10) that solve runs once m0 is known;
        v1 = v0 - e V + g T and r1 = r0 + v0 T + g T^2/2 - e X."""
        c = self.c
        for what, ex_, node in (("rate", mdot, b.rate), ("exhaust speed", speed, b.exhaust)):
            if variables(ex_) - {BURN_TIME}:
                raise ProblemError(f"a burn's {what} may depend on its time t and constants "
                                   "only", node.span, code="type")
        if b.duration is None:
            raise ProblemError("a burn whose rate varies with t needs a `duration`", b.span,
                               code="name")
        T = self._q(b.duration, TIME, "the burn's duration", False)
        if variables(T):
            raise ProblemError("a varying burn needs a known duration", b.span, code="type")
        T_val = evaluate(T, {})
        if T_val <= 0:
            raise ProblemError("a burn's duration must be positive", b.duration.span,
                               code="number")

        def negative_at(tau: float) -> None:
            """A located error where the rate or exhaust speed is negative (the body would
            gain mass, or push itself backwards), or not finite, at burn time tau."""
            env = {BURN_TIME: tau}
            for what, ex_, node in (("rate", mdot, b.rate),
                                    ("exhaust speed", speed, b.exhaust)):
                v = evaluate(ex_, env)
                if not math.isfinite(v) or v < 0:
                    raise ProblemError(f"the burn's {what} is {v:g} at t = {tau:g} s of its "
                                       f"{T_val:g} s: it must stay finite and not negative "
                                       "during the burn", node.span, code="number")

        for k in range(257):  # a grid first, so that a short dip is not stepped over
            negative_at(T_val * k / 256)

        key = f"{b.before}->{b.after}"
        group = f"burn {b.body} {b.before} -> {b.after}"
        how = f"integrated numerically: scipy DOP853, rtol {RTOL:g}"

        def run(start: dict) -> list[float]:
            return _integrate_burn(b, mdot, speed, T_val, start["mass"])

        names = [f"dv_thrust@{key}", f"dx_thrust@{key}", f"m_{b.body}@{b.after}"]
        for n, dim, unit in zip(names, (VELOCITY, LENGTH, MASS), ("m/s", "m", "kg")):
            c.unknown(n, dim, "derived", unit)
        integ = Integration(group, b.span, {"mass": m0}, names, run,
                            ["the speed the thrust adds", "the distance the thrust adds",
                             f"{b.body}'s mass at state {b.after}"], RTOL)
        emit(c, integ, f"{how}: dV/dt = c mdot/m, dX/dt = V", group, self.integrations)
        c.notes.note(f"{group}: the rate or exhaust speed varies with t, so solve integrates "
                     f"the motion numerically (scipy DOP853, rtol {RTOL:g})", b.span,
                     code="integrated")
        self.masses[(b.body, b.after)] = Var(names[2])
        self.durations[key] = Known(f"t@{key}", T_val)
        g = c.scene.gravity or (0.0, 0.0)
        i, j = b.before, b.after
        v0, v1 = c.vel(b.body, i), c.vel(b.body, j)
        r0, r1 = c.pos(b.body, i), c.pos(b.body, j)
        dv, dx = Var(names[0]), Var(names[1])
        Tk = self.durations[key]
        for comp, ek, gk, a0, a1, p0, p1 in (("x", e[0], g[0], v0.x, v1.x, r0.x, r1.x),
                                             ("y", e[1], g[1], v0.y, v1.y, r0.y, r1.y)):
            c.eq(a1, add_all([a0, mul(Const(-ek), dv), mul(Const(gk), Tk)]),
                 f"velocity {comp} after the burn ({how}): v1 = v0 - e dv_thrust + g t",
                 group, b.span)
            c.eq(p1, add_all([p0, mul(a0, Tk), mul(Const(0.5 * gk), mul(Tk, Tk)),
                              mul(Const(-ek), dx)]),
                 f"position {comp} after the burn ({how}): r1 = r0 + v0 t + g t^2/2 - e "
                 "dx_thrust", group, b.span)


def _integrate_burn(b: S.BurnDecl, mdot: E, speed: E, T: float, m_start: float) -> list:
    """[V, X, m1] of a varying burn from mass m_start (scipy DOP853)."""
    if not m_start > 0:
        raise ProblemError(f"{b.body} has no mass at state {b.before}", b.span, code="number")
    from scipy.integrate import solve_ivp

    def rhs(tau, y):
        env = {BURN_TIME: tau}
        md, cc = evaluate(mdot, env), evaluate(speed, env)
        return [md, cc * md / (m_start - y[0]), y[1]]

    def empty(tau, y):
        return m_start - y[0]

    empty.terminal = True
    try:
        sol = solve_ivp(rhs, (0.0, T), [0.0, 0.0, 0.0], method="DOP853", rtol=RTOL,
                        atol=[RTOL * m_start, 1e-12, 1e-12], events=empty)
    except (ValueError, ZeroDivisionError, OverflowError) as exc:
        raise ProblemError(f"the burn cannot be integrated: {exc}", b.span,
                           code="number") from None
    if sol.status == 1 or not sol.success:
        raise ProblemError("the burn runs out of mass before its duration ends: no mass "
                           "would be left", b.span, code="number")
    M, V, X = (float(v) for v in sol.y[:, -1])
    return [V, X, m_start - M]
