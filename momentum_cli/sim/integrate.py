"""The simulation loop: phases of smooth motion between events, impacts at events.

A phase is advanced in closed form when its accelerations are constant (free flight,
constant forces, a body spinning down against a fixed contact) and every event that
can end it is a quadratic in time; otherwise scipy's solve_ivp integrates it (DOP853,
`rtol`; or fixed steps `dt`) and locates its events on the dense output. At an event
the impulse solver resolves impacts, and the set of persistent contacts, stuck or
sliding friction and locked bearings is chosen again.
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from ..diagnostics import ProblemError
from ..scene import Scene
from .dynamics import Frame, contact_geometry, gap_rate, relative_velocity
from .events import (
    Event,
    apex_event,
    bearing_events,
    first_root,
    gap_event,
    separation_event,
    slip_event,
    stick_limit_event,
    touching,
    until_qty,
)
from .forces import Phase, energy, instant, kinetic, relative_spin
from .impacts import resolve
from .drift import drift_event, project, reference, tolerance
from .model import Model, build_model, watch_for
from .states import state_values

MAX_EVENTS = 10000


@dataclass
class EventRow:
    t: float
    kind: str  # start | impact | contact | separate | stick | slip | lock | unlock | stop
    what: str
    before: dict  # body -> (vx, vy, omega)
    after: dict
    energy_lost: float = 0.0
    impulses: dict = field(default_factory=dict)
    note: str = ""


@dataclass
class PhaseRow:
    t0: float
    t1: float
    method: str  # closed form | DOP853 | fixed step
    steps: int
    evaluations: int
    drift: float  # max |E - E0 - W| over the phase, J


@dataclass
class SimResult:
    model: Model
    events: list[EventRow]
    phases: list[PhaseRow]
    times: list[float]
    states: list[np.ndarray]  # [q, u, W] at each time
    stop: str
    rtol: float
    dt: float | None
    seconds: float
    energy0: float
    constraint_drift: float = 0.0  # largest violation before a projection (m)
    projections: int = 0  # times the drift reached its tolerance and was projected away
    drift_tolerance: float = 0.0  # of the length scale

    def frame(self, k: int = -1) -> Frame:
        y = self.states[k]
        n = self.model.n
        return Frame(self.model, y[:n], y[n:2 * n])


def _initial(model: Model, start: dict) -> np.ndarray:
    n = model.n
    y = np.zeros(2 * n + 1)
    for b in model.bodies:
        s, i = start[b.name], b.index
        if b.size == 1:
            y[i], y[n + i] = s["angle"], s["omega"]
        else:
            y[i], y[i + 1], y[n + i], y[n + i + 1] = s["x"], s["y"], s["vx"], s["vy"]
            if b.size == 3:
                y[i + 2], y[n + i + 2] = s["angle"], s["omega"]
    return y


def _watches(model: Model, scene: Scene, spec) -> None:
    declared = {(c.a.name, c.b.name if c.b else c.surface or "ground") for c in spec.contacts}
    model.watches = [watch_for(model, c, None) for c in spec.contacts]
    placed: dict[str, dict] = {}
    for t in scene.transitions:
        for c in t.contacts:
            key = (c.a.name, c.b.name if c.b else c.surface or "ground")
            if key in declared:
                continue
            declared.add(key)
            if t.before not in placed:
                vals = state_values(scene, t.before, False, spec.span)
                placed[t.before] = {b: (v["x"], v["y"], v["angle"]) for b, v in vals.items()}
            model.watches.append(watch_for(model, c, placed[t.before]))
    seen = set()
    for w in model.watches:
        if w.label in seen:
            w.label = f"{w.label}#{len(seen)}"
        seen.add(w.label)


def _velocities(frame: Frame, model: Model) -> dict:
    return {b.name: frame.twist[b.name] for b in model.bodies}


class Simulator:
    def __init__(self, scene: Scene, spec, rtol: float = 1e-9, dt: float | None = None,
                 progress=None, max_time: float | None = None, closed_forms: bool = True):
        self.scene, self.spec, self.rtol, self.dt = scene, spec, rtol, dt
        self.closed_forms = closed_forms
        self.progress = progress
        self.model = model = build_model(scene, spec)
        start = state_values(scene, spec.start, True, spec.span)
        _watches(model, scene, spec)
        self.y = _initial(model, start)
        self.t = 0.0
        self.t_end = min([u.value for u in spec.untils if u.kind == "time"] +
                         ([max_time] if max_time else []), default=math.inf)
        self.max_impacts = min([int(u.value) for u in spec.untils if u.kind == "impacts"],
                               default=None)
        self.spec_qty = [u for u in spec.untils if u.kind == "qty"]
        self.stop_events: list[Event] = [until_qty(model, u) for u in self.spec_qty]
        for u in spec.untils:
            if u.kind == "apex":
                if model.gravity is None:
                    raise ProblemError("`until apex` needs gravity in the plane of motion",
                                       u.span, code="name")
                self.stop_events.append(apex_event(model))
        L = model.length_scale
        frame = self.frame()
        g = math.hypot(*model.gravity) if model.gravity else 0.0
        speeds = [abs(x) for b in model.bodies for x in frame.twist[b.name][:2]]
        speeds += [abs(frame.twist[b.name][2]) * L for b in model.bodies]
        self.v_scale = max(speeds + [math.sqrt(g * L), 1e-30])
        self.gap_tol = 1e-9 * L
        self.v_tol = 1e-9 * self.v_scale
        # a contact whose rebound would not clear the contact tolerance rests
        self.v_rest = max(10 * self.v_tol, math.sqrt(2 * g * self.gap_tol))
        mass = sum(b.mass for b in model.bodies)
        self.f_tol = 1e-12 * mass * max(g, self.v_scale ** 2 / L, 1e-300)
        self.events: list[EventRow] = []
        self.phases: list[PhaseRow] = []
        self.times = [0.0]
        self.states = [self.y.copy()]
        self.impacts = 0
        self.E0 = energy(model, frame)
        self.ref = reference(model, frame)
        self.drift = tolerance(None if dt is not None else rtol)
        self.max_drift = 0.0  # largest constraint violation met (before each projection)
        self.projections = 0
        self.phase = Phase()

    def frame(self, y=None) -> Frame:
        y = self.y if y is None else y
        n = self.model.n
        return Frame(self.model, y[:n], y[n:2 * n])

    # ---- the loop
    def run(self) -> SimResult:
        began = time.perf_counter()
        self.events.append(EventRow(0.0, "start", f"state {self.spec.start}", {},
                                    _velocities(self.frame(), self.model)))
        stop = None
        still, last_t = 0, -1.0
        for _ in range(MAX_EVENTS):
            still = still + 1 if self.t == last_t else 0
            last_t = self.t
            if still > 100:
                raise ProblemError(f"events do not let time advance at t = {self.t:.9g} s "
                                   "(contacts that chatter)", self.spec.span, code="simulate")
            stop = self._impacts()
            if stop:
                break
            self._choose_phase()
            if self.t >= self.t_end:
                stop = "time"
                break
            if self.t > 0 and self._reached():
                stop = "until"
                break
            stop = self._advance()
            if stop:
                break
        else:
            stop = "events"
        self.events.append(EventRow(self.t, "stop", _stop_text(stop, self), {},
                                    _velocities(self.frame(), self.model)))
        return SimResult(self.model, self.events, self.phases, self.times, self.states, stop,
                         self.rtol, self.dt, time.perf_counter() - began, self.E0,
                         self.max_drift, self.projections, self.drift)

    def _reached(self) -> bool:
        """A stop condition that holds at this event's instant (it was reached at the same
        moment as the event that ended the phase)."""
        frame = self.frame()
        L, V = self.model.length_scale, self.v_scale
        scale = {"x": L, "y": L, "angle": 1.0, "vx": V, "vy": V, "omega": V / L}
        for e, u in zip(self.stop_events, self.spec_qty):
            if abs(e.fn(frame, None)) <= 1e-9 * scale[u.qty]:
                self.stop_what = e.what
                return True
        return False

    def _set_velocities(self, vel: dict) -> None:
        n = self.model.n
        for b in self.model.bodies:
            vx, vy, w = vel[b.name]
            i = n + b.index
            if b.size == 1:
                self.y[i] = w
            else:
                self.y[i], self.y[i + 1] = vx, vy
                if b.size == 3:
                    self.y[i + 2] = w

    def _impacts(self) -> str | None:
        """Resolve every contact that is closing now; contacts that touch and would close
        after the impulse join it. Returns a stop reason."""
        for _ in range(50):
            frame = self.frame()
            near = touching(self.model, frame, self.gap_tol)
            hits = [(w, geo) for w, geo, vn in near if vn < -self.v_tol]
            if not hits:
                return None
            group = list(hits)
            for _round in range(len(near) + 1):
                before = _velocities(frame, self.model)
                after, impulses, regimes = resolve(self.model, frame, group)
                y_save = self.y.copy()
                self._set_velocities(after)
                f2 = self.frame()
                names = {w.label for w, _ in group}
                more = [(w, geo) for w, geo, _ in touching(self.model, f2, self.gap_tol)
                        if w.label not in names and gap_rate(f2, w, geo) < -self.v_tol]
                if not more:
                    break
                self.y = y_save
                group += more
            T0, T1 = kinetic(self.model, frame), kinetic(self.model, f2)
            what = ", ".join(w.label for w, _ in group)
            note = ", ".join(f"{k} {v}" for k, v in sorted(regimes.items()))
            self.events.append(EventRow(self.t, "impact", what, before, after, T0 - T1,
                                        impulses, note))
            self.impacts += 1
            self._record()
            if self.max_impacts is not None and self.impacts >= self.max_impacts:
                return "impacts"
        raise ProblemError("impacts do not settle at one instant (more than 50 rounds)",
                           self.spec.span, code="simulate")

    def _choose_phase(self) -> None:
        """Persistent contacts (touching, not separating), their friction state, bearings."""
        model = self.model
        frame = self.frame()
        phase = Phase()
        for w, geo, vn in touching(model, frame, self.gap_tol):
            if abs(vn) > self.v_rest:
                continue
            if w.spec.mode == "smooth":
                phase.contacts[w.label] = "rest"
                continue
            v = relative_velocity(frame, w, geo)
            slip = -v[0] * geo[1][1] + v[1] * geo[1][0]
            if w.spec.mode == "friction" and not w.spec.mu:
                phase.contacts[w.label] = "rest"  # mu = 0: smooth
            elif w.spec.mode == "rough" or abs(slip) <= 10 * self.v_tol:
                phase.contacts[w.label] = "stick"
            else:
                phase.contacts[w.label] = math.copysign(1.0, slip)
        for label in model.bearings:
            spin = relative_spin(frame, model, label)
            if abs(spin) * model.length_scale <= 10 * self.v_tol:
                phase.locked.add(label)
            else:
                phase.bearing_sign[label] = math.copysign(1.0, spin)
        for _ in range(4 * len(phase.contacts) + 4 * len(model.bearings) + 1):
            inst = instant(model, phase, frame)
            changed = False
            worst = None
            for label, mode in phase.contacts.items():
                N = inst.lam.get(f"N[{label}]", 0.0)
                if N <= self.f_tol and (worst is None or N < worst[1]):
                    worst = (label, N)  # pulling, or not pressed at all: not a contact
            if worst is not None:
                del phase.contacts[worst[0]]
                continue
            for label, mode in list(phase.contacts.items()):
                if mode != "stick":
                    continue
                w = next(x for x in model.watches if x.label == label)
                if w.spec.mode == "rough":
                    continue
                Ft = inst.lam.get(f"F_t[{label}]", 0.0)
                N = inst.lam.get(f"N[{label}]", 0.0)
                if abs(Ft) > w.spec.mu * N * (1 + 1e-12):
                    phase.contacts[label] = -math.copysign(1.0, Ft)
                    changed = True
            for label in list(phase.locked):
                if abs(inst.lam.get(f"M[{label}]", 0.0)) > model.bearings[label] * (1 + 1e-12):
                    phase.locked.discard(label)
                    phase.bearing_sign[label] = -math.copysign(1.0, inst.lam[f"M[{label}]"])
                    changed = True
            if not changed:
                break
        self.phase = phase
        self._project()

    def _project(self) -> None:
        """Put positions and velocities back on the phase's constraints (the mass-weighted
        least change), so drift never accumulates across phases."""
        self.max_drift = max(self.max_drift, project(self.model, self.phase, self.y, self.ref,
                                                          self.drift))

    def _events(self) -> list[Event]:
        model, phase = self.model, self.phase
        self.lift_off = 0.0  # time for separating contacts to clear a round-off overlap
        evs = []
        frame = self.frame()
        for w in model.watches:
            mode = phase.contacts.get(w.label)
            if mode is None:
                # touching and not separating, but not pressed: it closes if the gap goes
                # below -tol (resting at zero is not an event). Separating from a gap a
                # round-off below zero: the first step must end above zero, or a step that
                # spans the whole flight would see no sign change
                geo = contact_geometry(frame, w)
                shift = 0.0
                if geo[0] <= self.gap_tol:
                    rate = gap_rate(frame, w, geo)
                    if rate <= self.v_rest:
                        shift = self.gap_tol
                    elif geo[0] < 0:
                        self.lift_off = max(self.lift_off, -4 * geo[0] / rate)
                evs.append(gap_event(model, w, shift))
                continue
            evs.append(separation_event(w))
            if mode in (1.0, -1.0):
                evs.append(slip_event(w))
            elif mode == "stick" and w.spec.mode == "friction":
                evs.append(stick_limit_event(w))
        for label in model.bearings:
            evs.append(bearing_events(model, label, label in phase.locked))
        drift = drift_event(model, phase, self.ref, self.drift)
        return evs + self.stop_events + ([drift] if drift is not None else [])

    def _constant_acceleration(self) -> bool:
        """True when nothing in this phase depends on the configuration."""
        m = self.model
        if m.springs or m.dampers or m.bearings:
            return False
        if any(b.size == 1 and b.pin_offset != (0.0, 0.0) for b in m.bodies):
            return False
        for j in m.joints:
            if j.kind == "weld" or j.a.offset != (0.0, 0.0) or \
                    (j.b.body is not None and j.b.offset != (0.0, 0.0)):
                return False
        for F, p, _ in m.forces:
            if p.body is not None and p.offset != (0.0, 0.0) and \
                    not m.by_name[p.body].particle:
                return False
        for w in m.watches:
            if w.label in self.phase.contacts and (w.b is not None or
                                                   (w.a.offset != (0.0, 0.0) and w.ra == 0)):
                return False
        return True

    def _advance(self) -> str | None:
        evs = self._events()
        from .pendulum import PendulumFlow

        if not self.closed_forms:
            return self._integrate(evs)
        if PendulumFlow.applies(self.model, self.phase) and \
                not any(e.needs_instant for e in evs):
            try:
                flow = PendulumFlow(self.model, self.y)
            except ValueError:  # exactly on the separatrix: integrate
                flow = None
            if flow is not None:
                return self._flow_phase(evs, flow)
        if self._constant_acceleration():
            frame = self.frame()
            inst = instant(self.model, self.phase, frame)
            polys = [e.poly(frame, inst.udot) if e.poly else None for e in evs]
            if all(p is not None for p in polys):
                return self._closed_form(evs, polys, inst)
        return self._integrate(evs)

    def _closed_form(self, evs, polys, inst) -> str | None:
        n = self.model.n
        horizon = self.t_end - self.t
        roots = [(first_root(p[0], p[1], p[2], e.direction, horizon), e)
                 for e, p in zip(evs, polys)]
        roots = [(r, e) for r, e in roots if r is not None]
        best = min([r for r, _ in roots], default=horizon)
        hit = _first([e for r, e in roots if r <= best * (1 + 1e-12)])
        if not math.isfinite(best):
            raise ProblemError("the motion never ends: nothing stops it (add `until t = ...`)",
                               self.spec.span, code="simulate")
        y0 = self.y.copy()
        a = inst.udot

        def at(s):
            y = y0.copy()
            y[:n] = y0[:n] + y0[n:2 * n] * s + 0.5 * a * s * s
            y[n:2 * n] = y0[n:2 * n] + a * s
            return y

        p0 = inst.power
        p1 = instant(self.model, self.phase, self.frame(at(best))).power
        for k in range(1, 21):
            s = best * k / 20
            y = at(s)
            y[2 * n] = y0[2 * n] + p0 * s + 0.5 * (p1 - p0) / best * s * s if best else y0[2 * n]
            self.times.append(self.t + s)
            self.states.append(y)
        self.y = self.states[-1].copy()
        drift = self._drift([y0] + self.states[-20:])
        self.phases.append(PhaseRow(self.t, self.t + best, "closed form", 1, 2, drift))
        self.t += best
        return self._after(hit)

    def _flow_phase(self, evs, flow) -> str | None:
        """A phase whose state is a known function of time (the elliptic pendulum): its
        events are bracketed by sampling 64 points a period and found by false position."""
        from .elliptic import root

        model, n, t0 = self.model, self.model.n, self.t
        horizon = self.t_end - t0
        span = horizon if math.isfinite(horizon) else 1.05 * flow.period
        if not math.isfinite(span):
            raise ProblemError("the motion never ends: nothing stops it (add `until t = ...`)",
                               self.spec.span, code="simulate")
        h = min(span, flow.period / 64) if math.isfinite(flow.period) else span / 64

        def g(e, s):
            y = flow.state(s)
            return e.fn(Frame(model, y[:n], y[n:2 * n]), None)

        signs = []  # the sign each function leaves the start with (None: still zero)
        for e in evs:
            v0 = g(e, 0.0)
            signs.append(math.copysign(1.0, v0) if v0 != 0 else None)
        prev = 0.0
        hit, best = None, span
        samples = []
        s = 0.0
        while s < span and hit is None:
            s = min(s + h, span)
            y = flow.state(s)
            f = Frame(model, y[:n], y[n:2 * n])
            found = []
            for k, e in enumerate(evs):
                v = e.fn(f, None)
                if signs[k] is None:
                    signs[k] = math.copysign(1.0, v) if v != 0 else None
                    continue
                if v == 0 or math.copysign(1.0, v) != signs[k]:
                    rising = signs[k] < 0
                    if not e.direction or (e.direction > 0) == rising:
                        r = root(lambda x: g(e, x), prev, s)
                        found.append((r, e))
                    signs[k] = math.copysign(1.0, v) if v != 0 else -signs[k]
            if found:
                best = min(r for r, _ in found)
                hit = _first([e for r, e in found if r <= best * (1 + 1e-12)])
                break
            samples.append((s, y))
            prev = s
        if hit is None and s < horizon:
            raise ProblemError("the motion never ends: nothing stops it within a period "
                               "(add `until t = ...`)", self.spec.span, code="simulate")
        y0 = self.y.copy()
        for s_, y in samples:
            if s_ < best:
                self.times.append(t0 + s_)
                self.states.append(y)
        self.times.append(t0 + best)
        self.states.append(flow.state(best))
        self.y = self.states[-1].copy()
        drift = self._drift([y0] + [y for s_, y in samples if s_ < best] + [self.y])
        self.phases.append(PhaseRow(t0, t0 + best, "closed form", len(samples) + 1,
                                    len(samples) + 1, drift))
        self.t = t0 + best
        return self._after(hit)

    def _drift(self, ys) -> float:
        """max |E - W - (E - W at the phase's start)|: energy not accounted for by the
        work of the non-potential forces (constraint forces do none)."""
        n = self.model.n

        def level(y):
            return energy(self.model, Frame(self.model, y[:n], y[n:2 * n])) - y[2 * n]

        ref = level(ys[0])
        return max(abs(level(y) - ref) for y in ys)

    def _integrate(self, evs) -> str | None:
        from scipy.integrate import solve_ivp

        model, phase, n = self.model, self.phase, self.model.n
        t0, y0 = self.t, self.y.copy()
        counter = [0]

        def rhs(t, y):
            f = Frame(model, y[:n], y[n:2 * n])
            inst = instant(model, phase, f)
            counter[0] += 1
            if self.progress is not None and counter[0] % 256 == 0:
                self.progress(t, self.t_end)
            out = np.empty(2 * n + 1)
            out[:n] = y[n:2 * n]
            out[n:2 * n] = inst.udot
            out[2 * n] = inst.power
            return out

        fns = []
        for e in evs:
            fns.append(_wrap(e, model, phase, t0, y0, rhs))
        horizon = self.t_end
        if not math.isfinite(horizon):
            horizon = t0 + 1e6 * max(1.0, t0)
        kw = dict(method="DOP853", events=fns, rtol=self.rtol,
                  atol=self.rtol * self._atol_scale())
        if self.dt is not None:
            kw.update(first_step=self.dt, max_step=self.dt, rtol=1e3, atol=1e300)
        if self.lift_off:
            kw["first_step"] = min(1e3 * self.lift_off, kw.get("first_step", math.inf),
                                   horizon - t0)
        sol = solve_ivp(rhs, (t0, horizon), y0, **kw)
        if sol.status == -1:
            raise ProblemError(f"the integration failed at t = {sol.t[-1]:.6g} s: {sol.message}",
                               self.spec.span, code="simulate")
        hit, t_hit, y_hit = None, sol.t[-1], sol.y[:, -1]
        found = [(sol.t_events[k][0], k) for k in range(len(evs)) if len(sol.t_events[k])]
        if found:
            t_hit = min(t for t, _ in found)
            near = [k for t, k in found if t <= t_hit + 1e-12 * max(1.0, abs(t_hit))]
            hit = _first([evs[k] for k in near])
            k = next(k for k in near if evs[k] is hit)
            t_hit, y_hit = sol.t_events[k][0], sol.y_events[k][0]
        steps = len(sol.t) - 1
        first = len(self.states)
        for k in range(1, len(sol.t)):
            if sol.t[k] < t_hit:
                self.times.append(float(sol.t[k]))
                self.states.append(sol.y[:, k].copy())
        self.times.append(float(t_hit))
        self.states.append(np.array(y_hit, dtype=float))
        self.y = self.states[-1].copy()
        drift = self._drift([y0] + self.states[first:])
        self.phases.append(PhaseRow(t0, float(t_hit), "fixed step" if self.dt else "DOP853",
                                    steps, sol.nfev, drift))
        self.t = float(t_hit)
        if self.progress is not None:
            self.progress(self.t, self.t_end)
        return self._after(hit)

    def _atol_scale(self) -> np.ndarray:
        """Absolute tolerances per component: lengths, angles, speeds, work."""
        m, n = self.model, self.model.n
        L, V = m.length_scale, self.v_scale
        s = np.empty(2 * n + 1)
        for b in m.bodies:
            i = b.index
            if b.size == 1:
                s[i], s[n + i] = 1.0, V / L
            else:
                s[i] = s[i + 1] = L
                s[n + i] = s[n + i + 1] = V
                if b.size == 3:
                    s[i + 2], s[n + i + 2] = 1.0, V / L
        s[2 * n] = max(abs(self.E0), sum(b.mass for b in m.bodies) * V * V, 1e-300)
        return s * 1e-3

    def _after(self, hit: Event | None) -> str | None:
        if hit is None:
            return "time" if self.t >= self.t_end else None
        if hit.kind in ("until", "apex"):
            self.stop_what = hit.what
            return hit.kind
        if hit.kind == "drift":
            self.projections += 1
            return None
        if hit.kind != "contact":
            frame = self.frame()
            v = _velocities(frame, self.model)
            self.events.append(EventRow(self.t, hit.kind, hit.what, v, v))
        return None

    def _record(self) -> None:
        self.times.append(self.t)
        self.states.append(self.y.copy())


def _first(hits: list[Event]) -> Event | None:
    """Of events at one instant, a stop condition wins (the run ends there)."""
    for e in hits:
        if e.kind in ("until", "apex"):
            return e
    return hits[0] if hits else None


def _wrap(e: Event, model, phase, t0, y0, rhs):
    n = model.n

    def value(t, y):
        f = Frame(model, y[:n], y[n:2 * n])
        inst = instant(model, phase, f) if e.needs_instant else None
        return e.fn(f, inst)

    v0 = value(t0, y0)
    s0, shift = 0.0, 0.0
    if abs(v0) == 0.0:  # starts on zero: look at where it goes, so t0 is not an event
        h = 1e-9
        y1 = y0 + h * rhs(t0, y0)
        v1 = value(t0 + h, y1)
        if v1 == 0.0:
            y2 = y1 + h * rhs(t0 + h, y1)
            v1 = value(t0 + 2 * h, y2) - v1
        s0 = math.copysign(1e-300, v1) if v1 else 0.0
        if not v1:  # it stays on zero (a force that is not needed): only leaving it counts
            shift = -1e-300 if e.direction > 0 else 1e-300

    def fn(t, y):
        v = value(t, y) + shift
        # an exact zero while it has barely moved off its start is still the start
        return s0 if v == 0.0 and s0 else v

    fn.terminal = True
    fn.direction = e.direction
    return fn


def _stop_text(stop: str, sim: Simulator) -> str:
    return {"time": f"t = {sim.t_end:g} s", "impacts": f"{sim.impacts} impacts",
            "apex": "apex", "until": getattr(sim, "stop_what", "stop condition"), "events": "too many events"}.get(stop,
                                                                                         stop)


def simulate(scene: Scene, index: int = 0, rtol: float = 1e-9, dt: float | None = None,
             progress=None, closed_forms: bool = True) -> SimResult:
    if not scene.simulations:
        raise ProblemError("nothing to simulate: add a block `simulate from 1:` with a stop "
                           "condition such as `until t = 2 s`", None, code="simulate",
                           caret=False)
    return Simulator(scene, scene.simulations[index], rtol, dt, progress,
                     closed_forms=closed_forms).run()
