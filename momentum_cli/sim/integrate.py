"""The simulation loop: phases of smooth motion between events, impacts at events.

Each phase is advanced (advance.py) in closed form where one exists: constant
accelerations (free flight, constant forces, a body spinning down against a fixed
contact) with events that are quadratics in time, or bodies swinging on pins under
gravity alone (elliptic functions); otherwise scipy's solve_ivp integrates it (DOP853
at `rtol`, or fixed steps `dt`). At an event the impulse solver resolves impacts, and
the persistent contacts, stuck or sliding friction and locked bearings are chosen
again; constraint drift is projected away (drift.py).
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from ..diagnostics import ProblemError
from ..elements.kinds import JointKind, Regime, Tangential
from ..scene import Scene
from ..source import Span
from . import advance
from .drift import drift_event, project, reference, tolerance
from .dynamics import Frame, contact_geometry, gap_rate, relative_velocity
from .events import (
    Event,
    apex_event,
    bearing_events,
    gap_event,
    separation_event,
    slip_event,
    stick_limit_event,
    touching,
    until_qty,
)
from .forces import Phase, energy, instant, kinetic, relative_spin
from .impacts import resolve
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
    phase: object = None  # what held at the end (persistent contacts, locked bearings)
    drift_raised: bool = False  # positions too coarse for the stated drift tolerance

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
    """The contacts to watch: the simulate block's, then the transitions' (placed where
    the file says they touch); labels made unique."""
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
    """One run: the state, the phase that holds, and what has happened so far."""

    def __init__(self, scene: Scene, spec, rtol: float = 1e-9, dt: float | None = None,
                 progress=None, closed_forms: bool = True, max_events: int = MAX_EVENTS,
                 max_time: float | None = None):
        self.scene, self.spec, self.rtol, self.dt = scene, spec, rtol, dt
        self.closed_forms = closed_forms
        self.max_events = max_events
        self.deadline = None if max_time is None else time.perf_counter() + max_time
        self.max_time = max_time
        self.shown = progress
        self.progress = self._tick  # called now and then by every phase that takes steps
        self.model = model = build_model(scene, spec)
        start = state_values(scene, spec.start, True, spec.span)
        _watches(model, scene, spec)
        for u in spec.untils:
            if u.kind == "impacts" and not model.watches:
                raise ProblemError("no contact is watched, so there will be no impacts: add "
                                   "`contact A with B: restitution e` to the simulate block",
                                   u.span, code="simulate")
        self.y = _initial(model, start)
        self.t = 0.0
        self.t_end = min([u.value for u in spec.untils if u.kind == "time"], default=math.inf)
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
        self.evaluations = 0  # of the accelerations, over the run
        self.drift_raised = False  # the drift tolerance had to be loosened (see _project)
        self.phase = Phase()
        self.stop_what = "stop condition"  # the `until` that ended the run
        self.lift_off = 0.0  # set by _events for the phase about to be advanced

    def frame(self, y=None) -> Frame:
        y = self.y if y is None else y
        n = self.model.n
        return Frame(self.model, y[:n], y[n:2 * n])

    def _tick(self, t: float, t_end: float = math.inf) -> None:
        """Now and then during a run: the limit on computing time, then the progress bar."""
        if self.deadline is not None and time.perf_counter() > self.deadline:
            raise ProblemError(f"the run takes longer than --max-time {self.max_time:g} s of "
                               f"computing (stopped at t = {t:.6g} s of simulated time, after "
                               f"{self.impacts} impacts)", self.spec.span, code="simulate",
                               notes=["bound the run with `until t = ...`, or raise "
                                      "--max-time"])
        if self.shown is not None:
            self.shown(t, t_end)

    # ---- the loop
    def run(self) -> SimResult:
        began = time.perf_counter()
        self.events.append(EventRow(0.0, "start", f"state {self.spec.start}", {},
                                    _velocities(self.frame(), self.model)))
        stop = None
        still, last_t = 0, -1.0
        for _ in range(self.max_events):
            self._tick(self.t, self.t_end)
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
            raise ProblemError(f"the stop condition is not reached in {self.max_events:,} "
                               f"events (at t = {self.t:.6g} s, after {self.impacts} impacts)",
                               self.spec.span, code="simulate",
                               notes=["bound the run with `until t = ...` or fewer impacts, "
                                      "or raise --max-events"])
        self.events.append(EventRow(self.t, "stop", _stop_text(stop, self), {},
                                    _velocities(self.frame(), self.model)))
        return SimResult(self.model, self.events, self.phases, self.times, self.states, stop,
                         self.rtol, self.dt, time.perf_counter() - began, self.E0,
                         self.max_drift, self.projections, self.drift, self.phase,
                         self.drift_raised)

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
            note = ", ".join(f"{k.split(':', 1)[-1]} {'sticks' if v == 'stick' else 'slides'}"
                             for k, v in sorted(regimes.items()))
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
            v = relative_velocity(frame, w, geo)
            slip = -v[0] * geo[1][1] + v[1] * geo[1][0]
            phase.contacts[w.label] = w.element.tangential.sim_regime(slip, 10 * self.v_tol)
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
                if mode != Regime.STICK:
                    continue
                w = next(x for x in model.watches if x.label == label)
                Ft = inst.lam.get(f"F_t[{label}]", 0.0)
                N = inst.lam.get(f"N[{label}]", 0.0)
                if not w.element.tangential.stick_holds(Ft, N):
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
        before, after = project(self.model, self.phase, self.y, self.ref, self.drift)
        self.max_drift = max(self.max_drift, before)
        L = self.model.length_scale
        if after > 0.5 * self.drift * L:  # coordinates too coarse to hold the tolerance
            self.drift = 2 * after / L
            self.drift_raised = True

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
            elif mode == Regime.STICK and w.element.tangential.kind is Tangential.FRICTION:
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
            if j.kind is JointKind.WELD or j.a.offset != (0.0, 0.0) or \
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
            return self._finish(advance.integrate(self, evs))
        if PendulumFlow.applies(self.model, self.phase) and \
                not any(e.needs_instant for e in evs):
            try:
                flow = PendulumFlow(self.model, self.y)
            except ValueError:  # exactly on the separatrix: integrate
                flow = None
            if flow is not None:
                return self._finish(advance.pendulum(self, evs, flow))
        if self._constant_acceleration():
            frame = self.frame()
            inst = instant(self.model, self.phase, frame)
            polys = [e.poly(frame, inst.udot) if e.poly else None for e in evs]
            if all(p is not None for p in polys):
                return self._finish(advance.quadratic(self, evs, polys, inst))
            return self._finish(advance.coasting(self, evs, inst))
        return self._finish(advance.integrate(self, evs))

    def _finish(self, seg) -> str | None:
        """Record a phase that ended at seg.t1, and what ended it."""
        y0 = self.y.copy()
        for t, y in seg.states:
            self.times.append(t)
            self.states.append(y)
        drift = self._drift([y0] + [y for _, y in seg.states])
        self.phases.append(PhaseRow(self.t, seg.t1, seg.method, seg.steps, seg.evaluations,
                                    drift))
        self.evaluations += seg.evaluations
        self.t, self.y = seg.t1, seg.states[-1][1].copy()
        if seg.hit is not None and seg.hit.kind == "drift" and seg.steps < 4:
            # drifting out again within a few steps of a projection: the coordinates are
            # too coarse (huge angles or positions) for the tolerance; loosen it
            self.drift *= 10
            self.drift_raised = True
        self.progress(self.t, self.t_end)
        return self._after(seg.hit)

    def _drift(self, ys) -> float:
        """max |E - W - (E - W at the phase's start)|: energy not accounted for by the
        work of the non-potential forces (constraint forces do none)."""
        n = self.model.n

        def level(y):
            return energy(self.model, Frame(self.model, y[:n], y[n:2 * n])) - y[2 * n]

        ref = level(ys[0])
        return max(abs(level(y) - ref) for y in ys)

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


def _stop_text(stop: str, sim: Simulator) -> str:
    texts = {"time": f"t = {sim.t_end:g} s", "impacts": f"{sim.impacts} impacts",
             "apex": "apex", "until": sim.stop_what}
    return texts.get(stop, stop)


def simulate(scene: Scene, index: int = 0, rtol: float = 1e-9, dt: float | None = None,
             progress=None, closed_forms: bool = True, max_events: int = MAX_EVENTS,
             max_time: float | None = None) -> SimResult:
    """Run the scene's simulation. The options must be finite and positive (ValueError
    otherwise: the command line refuses them first)."""
    for name, v in (("rtol", rtol), ("dt", dt), ("max_time", max_time)):
        if v is not None and not (math.isfinite(v) and v > 0):
            raise ValueError(f"{name} must be a finite positive number; got {v!r}")
    if max_events < 1:
        raise ValueError(f"max_events must be at least 1; got {max_events!r}")
    if not scene.simulations:
        raise ProblemError("nothing to simulate: add a block `simulate from 1:` with a stop "
                           "condition such as `until t = 2 s`", Span(1, 1), code="simulate",
                           caret=False)
    return Simulator(scene, scene.simulations[index], rtol, dt, progress,
                     closed_forms=closed_forms, max_events=max_events,
                     max_time=max_time).run()
