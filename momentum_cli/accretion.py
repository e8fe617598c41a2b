"""Variable mass over an interval: a particle that gains or loses mass (part of `compile`).

In dt the particle (mass m, velocity v) and the mass dm joining it at velocity v_in
form one system, so
    d(m v)/dt = sum F + m g + mdot v_in,   i.e.   m a = sum F + m g + mdot (v_in - v),
with mdot < 0 for mass leaving at v_in (`lose`). With a constant rate, a constant
absolute v_in and a constant applied force (u = m0 + mdot t, K = F + mdot v_in):
    m1 v1 = m0 v0 + K t + g t (m0 + m1)/2
    r1 = r0 + phi v0 t + psi K t^2/m0 + (psi + 1/2) g t^2/2,
with x = mdot t/m0, phi = ln(1+x)/x and psi = (x - ln(1+x))/x^2 (massratio.py: exact
as mdot -> 0, where ln(m1/m0)/mdot would cancel). Otherwise (a rate that depends on t
or the body's state, a relative v_in, an end condition instead of a duration, a start
mass only known when solved) the phase is an integration block (integration.py) that
solve runs, with scipy's DOP853 at rtol 1e-10, once its start state is known.
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
    mul,
    neg,
    power,
    to_text,
    variables,
)
from .integration import Integration, emit
from .massratio import ln1p_over_x, x_minus_ln1p_over_x2
from .numbers import fmt_num
from .units import FORCE, LENGTH, MASS, TIME, VELOCITY, describe

MASS_RATE = (1, 0, -1)
WEIGHT_RATE = (1, 1, -3)
RTOL = 1e-10  # relative tolerance of the numerical integration
PHASE_TIME = "t"  # the phase's own time in `rate`, `velocity` and `force` expressions
MEMBERS = {"x": "m", "y": "m", "vx": "m/s", "vy": "m/s", "speed": "m/s", "mass": "kg"}
MAX_CALLS = 2_000_000  # right-hand-side evaluations before an end condition is given up on
HORIZON = 1e6  # s: how long an end condition is waited for


class AccretionCompiler:
    """Adds the equations of `gain` and `lose` statements to a compiler's system, and
    records the mass and duration they leave (in the flow compiler's tables)."""

    def __init__(self, flows):
        self.flows = flows
        self.c = flows.c

    # ---- reading the clauses
    def _evaluator(self, g: S.GainDecl):
        """The compiler's evaluator, where `t` is the phase's time and `BODY.vy` (no
        `@`) the body's state during the phase."""
        from .quantity import Evaluator, Q
        from .units import LENGTH

        base = self.c._evaluator()
        dims = {"x": LENGTH, "y": LENGTH, "vx": VELOCITY, "vy": VELOCITY,
                "speed": VELOCITY, "mass": MASS}

        def resolve(ref, expect):
            if ref.name == PHASE_TIME and not (ref.index or ref.member or ref.at):
                return Q(Var(PHASE_TIME), TIME)
            if ref.member and not ref.at and not ref.index and ref.name in self.c.scene.bodies:
                if ref.name != g.body or ref.member not in MEMBERS:
                    raise ProblemError(
                        f"during `{'lose' if g.is_loss else 'gain'} {g.body}` only t and "
                        f"{g.body}'s own state ({', '.join(g.body + '.' + m for m in MEMBERS)})"
                        " may be used", ref.span, code="name")
                return Q(Var(f"{g.body}.{ref.member}"), dims[ref.member])
            return base.resolve(ref, expect)

        return Evaluator(resolve)

    def _read(self, g: S.GainDecl, node, dim, what: str, vector: bool):
        q = self._evaluator(g)(node, dim)
        if q.is_vector != vector:
            kind = "a vector such as (1, 0)" if vector else "a scalar"
            raise ProblemError(f"{what} needs {kind}", node.span, code="type")
        if q.dim != dim:
            raise ProblemError(f"{what} needs {describe(dim)}; got {describe(q.dim)}",
                               node.span, code="units")
        return q.value

    def _rate(self, g: S.GainDecl) -> E:
        """The rate of mass joining the body (negative for a loss); lb/s is a weight rate."""
        node = g.rate
        q = self._evaluator(g)(node, WEIGHT_RATE)
        if q.is_vector:
            raise ProblemError("the rate needs a scalar", node.span, code="type")
        value = q.value
        if q.dim == WEIGHT_RATE:
            if self.c.scene.g is None:
                raise ProblemError("a weight rate needs the file's g: declare gravity",
                                   node.span, code="name")
            value = mul(value, Const(1.0 / self.c.scene.g))
        elif q.dim != MASS_RATE:
            raise ProblemError("the rate needs a mass rate such as 5 kg/s or 2 kg/m * "
                               f"{g.body}.vy; got {describe(q.dim)}", node.span, code="units")
        if isinstance(value, Const) and value.value < 0:
            other = "gain" if g.is_loss else "lose"
            flow = "joining" if g.is_loss else "leaving"
            raise ProblemError(f"the rate cannot be negative (mass {flow} is written "
                               f"`{other}`)", node.span, code="number")
        return neg(value) if g.is_loss else value

    def _allowed(self, g: S.GainDecl, e: E, node, what: str) -> None:
        own = {PHASE_TIME} | {f"{g.body}.{m}" for m in MEMBERS}
        if variables(e) - own:
            raise ProblemError(f"{what} may depend on t, {g.body}'s state and constants only",
                               node.span, code="type")

    # ---- the phase
    def compile(self, g: S.GainDecl) -> None:
        c = self.c
        mdot = self._rate(g)
        zero = V2(Const(0.0), Const(0.0))
        v_in = self._read(g, g.velocity, VELOCITY, "the velocity of the mass", True) \
            if g.velocity is not None else zero
        relative = g.is_relative or (g.is_loss and g.velocity is None)  # a loss: leaves at v
        force = self._read(g, g.force, FORCE, "the force", True) if g.force is not None \
            else zero
        self._allowed(g, mdot, g.rate, "the rate")
        if g.velocity is not None:
            self._allowed(g, v_in.x + v_in.y, g.velocity, "the velocity")
        if g.force is not None:
            self._allowed(g, force.x + force.y, g.force, "the force")
        duration = None
        if g.duration is not None:
            duration = self._read(g, g.duration, TIME, "the duration", False)
            if variables(duration):
                raise ProblemError("the duration must be a known time", g.duration.span,
                                   code="type")
            if evaluate(duration, {}) <= 0:
                raise ProblemError("the duration must be positive", g.duration.span,
                                   code="number")
        m0 = c.mass(g.body, g.before)
        constant = not (variables(mdot) or variables(v_in.x + v_in.y) or
                        variables(force.x + force.y))
        if constant and not relative and duration is not None and not variables(m0):
            self._closed_form(g, mdot, v_in, force, duration, m0)
        else:
            why = ("its start mass is known only once solved" if constant and not relative and
                   duration is not None else "no closed form")
            self._integrated(g, mdot, v_in, relative, force, duration, m0, why)

    def _names(self, g: S.GainDecl) -> tuple[str, str, str]:
        key = f"{g.before}->{g.after}"
        verb = "lose" if g.is_loss else "gain"
        return key, f"{verb} {g.body} {g.before} -> {g.after}", "loss" if g.is_loss else "gain"

    def _closed_form(self, g, mdot: E, v_in: V2, force: V2, duration: E, m0: E) -> None:
        """Constant rate, absolute velocity of the mass and force: the closed form, with
        x = mdot t/m0 and the factors ln(1+x)/x, (x - ln(1+x))/x^2 (massratio.py), which
        stay exact as mdot -> 0 (no ln(m1/m0)/mdot to cancel)."""
        c = self.c
        key, group, noun = self._names(g)
        md, T, m_start = evaluate(mdot, {}), evaluate(duration, {}), evaluate(m0, {})
        m_end = m_start + md * T
        if m_end <= 0:
            raise ProblemError(f"the body loses {-md * T:g} kg out of {m_start:g} kg: no mass "
                               "would be left", g.span, code="number")
        x = md * T / m_start
        t = Known(f"t@{key}", T)
        r = Known("mdot", md)
        m1 = Known(f"m_{g.body}@{g.after}", m_end)
        phi = Known(f"phi_{noun}", ln1p_over_x(x))
        psi = Known(f"psi_{noun}", x_minus_ln1p_over_x2(x))
        self.flows.masses[(g.body, g.after)] = m1
        self.flows.durations[key] = t
        grav = c.scene.gravity or (0.0, 0.0)
        i, j = g.before, g.after
        v0, v1 = c.vel(g.body, i), c.vel(g.body, j)
        p0, p1 = c.pos(g.body, i), c.pos(g.body, j)
        how = "closed form: constant rate, velocity of the mass and force"
        heavy = c.scene.gravity is not None
        law = ("d(m v)/dt = F + m g + mdot v_in, so m1 v1 = m0 v0 + (F + mdot v_in) t + g t "
               "(m0 + m1)/2" if heavy else
               "d(m v)/dt = F + mdot v_in, so m1 v1 = m0 v0 + (F + mdot v_in) t")
        factors = (", x = mdot t/m0, phi = ln(1+x)/x, psi = (x - ln(1+x))/x^2 (series for "
                   "small x)")
        path = ("r1 = r0 + phi v0 t + psi K t^2/m0 + (psi + 1/2) g t^2/2" if heavy else
                "r1 = r0 + phi v0 t + psi K t^2/m0") + ", K = F + mdot v_in" + factors
        half_sum = Const(0.5 * (m_start + m_end))
        for comp, F, vin, gk, a0, a1, q0, q1 in (
                ("x", force.x, v_in.x, grav[0], v0.x, v1.x, p0.x, p1.x),
                ("y", force.y, v_in.y, grav[1], v0.y, v1.y, p0.y, p1.y)):
            K = add_all([F, mul(r, vin)])  # F + mdot v_in
            gt = mul(Const(gk), mul(t, half_sum))  # the impulse of the growing weight
            c.eq(mul(m1, a1), add_all([mul(m0, a0), mul(K, t), gt]),
                 f"momentum {comp} over the {noun} ({how}): {law}", group, g.span)
            drift = add_all([mul(phi, mul(a0, t)),
                             mul(psi, mul(K, mul(mul(t, t), power(m0, -1.0)))),
                             mul(Const(0.5 * gk), mul(add_all([psi, Const(0.5)]), mul(t, t)))])
            c.eq(q1, add_all([q0, drift]),
                 f"position {comp} at the end of the {noun} ({how}): {path}", group, g.span)

    def _end_condition(self, g) -> tuple[str, float] | None:
        """What the end state gives of the body (one of x, y, vx, vy): the phase ends
        when the body reaches it."""
        st = self.c.scene.states[g.after]
        given = [(q, st.givens[(g.body, q)][0]) for q in ("x", "y", "vx", "vy")
                 if (g.body, q) in st.givens]
        if len(given) != 1:
            what = "nothing" if not given else ", ".join(f"{g.body}.{q}" for q, _ in given)
            raise ProblemError(f"without a `duration`, the {self._names(g)[2]} ends when "
                               f"{g.body} reaches one quantity given at state {g.after}; it "
                               f"gives {what}", g.span, code="name",
                               notes=[(f"add `duration 2 s`, or give one of {g.body}.x, .y, "
                                       f".vx, .vy at state {g.after}")])
        return given[0]

    def _integrated(self, g, mdot: E, v_in: V2, relative: bool, force: V2, duration,
                    m0: E, why: str) -> None:
        """No closed form: an integration block (integration.py) that solve runs when the
        start state is known; here, its description and v1 = v0 + dv, r1 = r0 + dr."""
        c = self.c
        key, group, noun = self._names(g)
        b = g.body
        used = set().union(*(variables(e) for e in (mdot, v_in.x, v_in.y, force.x, force.y)))
        end = self._end_condition(g) if duration is None else None
        need = {"vx", "vy", "mass"} | {q for q in ("x", "y") if f"{b}.{q}" in used}
        if end is not None and end[0] in ("x", "y"):
            need.add(end[0])
        inputs = {q: (m0 if q == "mass" else c.sv(b, q, g.before)) for q in sorted(need)}
        T = evaluate(duration, {}) if duration is not None else None
        grav = c.scene.gravity or (0.0, 0.0)
        line = c.scene.states[g.after].givens[(b, end[0])][1].line if end else None

        def run(start: dict) -> list[float]:
            return _integrate(g, noun, mdot, v_in, relative, force, grav, T, end, line, start)

        names = [f"dvx_{noun}@{key}", f"dvy_{noun}@{key}", f"dx_{noun}@{key}",
                 f"dy_{noun}@{key}", f"m_{b}@{g.after}"] + ([f"t@{key}"] if end else [])
        what = [f"the change of {b}.vx over the {noun}", f"the change of {b}.vy over the {noun}",
                f"the change of {b}.x over the {noun}", f"the change of {b}.y over the {noun}",
                f"{b}'s mass at state {g.after}"] + ([f"the {noun}'s duration"] if end else [])
        for n, dim, unit in zip(names, (VELOCITY, VELOCITY, LENGTH, LENGTH, MASS, TIME),
                                ("m/s", "m/s", "m", "m", "kg", "s")):
            c.unknown(n, dim, "duration" if unit == "s" else "derived", unit)
        how = f"integrated numerically: scipy DOP853, rtol {RTOL:g}"
        vin = "v + " if relative else ""
        rate = f"-({to_text(neg(mdot))}) (mass leaving)" if g.is_loss else to_text(mdot)
        balance = (f"m a = F + m g + mdot (v_in - v), mdot = {rate}, v_in = {vin}("
                   f"{to_text(v_in.x)}, {to_text(v_in.y)}), F = ({to_text(force.x)}, "
                   f"{to_text(force.y)})")
        until = (f"until {b}.{end[0]}@{g.after} = {fmt_num(end[1], 6)} {MEMBERS[end[0]]}"
                 if end else f"over t@{key} = {fmt_num(T, 6)} s")
        integ = Integration(group, g.span, inputs, names, run, what, RTOL)
        emit(c, integ, f"{how}, {until}: {balance}", group, self.flows.integrations)
        c.notes.note(f"{group}: {balance}; {why}: solve integrates it numerically "
                     f"once its start state is known (scipy DOP853, rtol {RTOL:g}), {until}",
                     g.span, code="integrated")
        self.flows.masses[(b, g.after)] = Var(names[4])
        self.flows.durations[key] = Var(names[5]) if end else Known(f"t@{key}", T)
        i, j = g.before, g.after
        v0, v1 = c.vel(b, i), c.vel(b, j)
        p0, p1 = c.pos(b, i), c.pos(b, j)
        skip = end[0] if end else None
        for comp, k, a0, a1, q0, q1 in (("x", 0, v0.x, v1.x, p0.x, p1.x),
                                        ("y", 1, v0.y, v1.y, p0.y, p1.y)):
            if skip != "v" + comp:
                c.eq(a1, add_all([a0, Var(names[k])]),
                     f"velocity {comp} at the end of the {noun} ({how}, {until})", group,
                     g.span)
            if skip != comp:
                c.eq(q1, add_all([q0, Var(names[k + 2])]),
                     f"position {comp} at the end of the {noun} ({how})", group, g.span)


def _integrate(g, noun: str, mdot: E, v_in: V2, relative: bool, force: V2, grav, T, end,
               line, start: dict) -> list[float]:
    """Integrate m, r and v over the phase from `start` (scipy DOP853): [dvx, dvy, dx,
    dy, m1] and the duration if the phase ends on a condition."""
    b = g.body
    m_start = start["mass"]
    if not m_start > 0:
        raise ProblemError(f"{b} has no mass at state {g.before}", g.span, code="number")
    x0, y0 = start.get("x", 0.0), start.get("y", 0.0)
    calls = [0]

    kx, ky, kvx, kvy, kspeed, kmass = (f"{b}.{q}" for q in ("x", "y", "vx", "vy", "speed",
                                                             "mass"))
    hypot = math.hypot

    def env(tau, s):  # the names made once: the integrator calls this hundreds of times
        m, dx, dy, vx, vy = s
        return {PHASE_TIME: tau, kx: x0 + dx, ky: y0 + dy, kvx: vx, kvy: vy,
                kspeed: hypot(vx, vy), kmass: m}

    def rhs(tau, s):
        calls[0] += 1
        if calls[0] > MAX_CALLS:
            raise _GaveUp()
        e = env(tau, s)
        m, vx, vy = s[0], s[3], s[4]
        md = evaluate(mdot, e)
        ux, uy = evaluate(v_in.x, e), evaluate(v_in.y, e)
        if not relative:
            ux, uy = ux - vx, uy - vy
        ax = (evaluate(force.x, e) + md * ux) / m + grav[0]
        ay = (evaluate(force.y, e) + md * uy) / m + grav[1]
        return [md, vx, vy, ax, ay]

    def empty(tau, s):
        return s[0] - 1e-9 * m_start

    empty.terminal = True
    events = [empty]
    s0 = [m_start, 0.0, 0.0, start["vx"], start["vy"]]
    index = {"x": 1, "y": 2, "vx": 3, "vy": 4}
    if end is not None:
        q, target = end
        k = index[q]
        origin = {"x": x0, "y": y0}.get(q, 0.0)
        sign = 1.0 if target >= origin + s0[k] else -1.0

        def reached(tau, s):
            return s[k] + origin - target

        reached.terminal = True
        events.append(reached)
        if q in ("x", "y"):
            def turns_back(tau, s):  # the velocity toward the target changes sign
                return s[k + 2]

            turns_back.terminal = True
            turns_back.direction = -sign
            events.append(turns_back)
    horizon = T if T is not None else HORIZON
    from scipy.integrate import solve_ivp

    try:
        sol = solve_ivp(rhs, (0.0, horizon), s0, method="DOP853", rtol=RTOL,
                        atol=[RTOL * m_start, 1e-12, 1e-12, 1e-12, 1e-12], events=events)
    except _GaveUp:
        sol = None
    except (ValueError, ZeroDivisionError, OverflowError) as exc:
        raise ProblemError(f"the {noun} cannot be integrated: {exc}", g.span,
                           code="number") from None
    if sol is not None and len(sol.t_events[0]):
        raise ProblemError(f"{b} loses all its mass at t = {sol.t_events[0][0]:.6g} s: no "
                           "mass would be left", g.span, code="number")
    if end is not None:
        q, target = end
        if sol is None or not len(sol.t_events[1]):
            why = ""
            if sol is not None and len(sol.t_events) > 2 and len(sol.t_events[2]):
                why = f": it turns back at t = {sol.t_events[2][0]:.6g} s"
            elif sol is None or sol.status == 0:
                why = f" within {HORIZON:g} s of integration"
            else:
                why = f": {sol.message}"
            raise ProblemError(f"the end condition {b}.{q} = {fmt_num(target, 6)} "
                               f"{MEMBERS[q]} (state {g.after}, line {line}) is never "
                               f"reached{why}", g.span, code="unreached")
        t_end = float(sol.t_events[1][0])
        final = [float(v) for v in sol.y_events[1][0]]
    else:
        if sol is None or not sol.success:
            raise ProblemError(f"the {noun} cannot be integrated"
                               + (f": {sol.message}" if sol is not None else ""), g.span,
                               code="number")
        t_end = T
        final = [float(v) for v in sol.y[:, -1]]
    out = [final[3] - start["vx"], final[4] - start["vy"], final[1], final[2], final[0]]
    return out + ([t_end] if end is not None else [])


class _GaveUp(Exception):
    """The integration took too many steps without reaching its end condition."""
