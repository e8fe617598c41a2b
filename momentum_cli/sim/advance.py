"""Advancing one phase to its first event: closed forms where they exist, else DOP853.

Each function returns a Segment: where the phase ended, what ended it, the states on
the way (for the time series and the energy check) and how it was computed.
  quadratic   constant accelerations, events that are quadratics in time: exact roots
  pendulum    bodies swinging on pins under gravity alone: elliptic functions, events
              bracketed by sampling 64 points a period and found by false position
  coasting    constant accelerations with events that are not quadratics (round bodies
              closing on each other, points of turning bodies): sampled the same way
  integrate   scipy's solve_ivp (DOP853 at rtol, or fixed steps dt), events located
              on its dense output
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..diagnostics import ProblemError
from .dynamics import Frame
from .events import Event, first_root
from .forces import instant

UNBOUNDED_EVALUATIONS = 100_000  # a run without `until t = ...` gives up after these


@dataclass
class Segment:
    t1: float  # absolute time the phase ended
    hit: Event | None  # what ended it (None: the stop time)
    states: list  # [(t, y)] after the start, the last at t1
    method: str  # closed form | DOP853 | fixed step
    steps: int
    evaluations: int


def _never_ends(sim) -> ProblemError:
    return ProblemError("the motion never ends: nothing stops it (add `until t = ...`)",
                        sim.spec.span, code="simulate")


def first_of(hits: list[Event]) -> Event | None:
    """Of events at one instant, a stop condition wins (the run ends there)."""
    for e in hits:
        if e.kind in ("until", "apex"):
            return e
    return hits[0] if hits else None


def quadratic(sim, evs, polys, inst) -> Segment:
    n, t0, y0 = sim.model.n, sim.t, sim.y.copy()
    horizon = sim.t_end - t0
    roots = [(first_root(p[0], p[1], p[2], e.direction, horizon), e)
             for e, p in zip(evs, polys)]
    roots = [(r, e) for r, e in roots if r is not None]
    best = min([r for r, _ in roots], default=horizon)
    hit = first_of([e for r, e in roots if r <= best * (1 + 1e-12)])
    if not math.isfinite(best):
        raise _never_ends(sim)
    a = inst.udot
    p0 = inst.power

    def at(s):
        y = y0.copy()
        y[:n] = y0[:n] + y0[n:2 * n] * s + 0.5 * a * s * s
        y[n:2 * n] = y0[n:2 * n] + a * s
        return y

    p1 = instant(sim.model, sim.phase, Frame(sim.model, at(best)[:n], at(best)[n:2 * n])).power
    states = []
    for k in range(1, 21):
        s = best * k / 20
        y = at(s)
        # the power of constant forces is linear in time along this motion
        y[2 * n] = y0[2 * n] + p0 * s + 0.5 * (p1 - p0) / best * s * s if best else y0[2 * n]
        states.append((t0 + s, y))
    return Segment(t0 + best, hit, states, "closed form", 1, 2)


def pendulum(sim, evs, flow) -> Segment:
    horizon = sim.t_end - sim.t
    span = horizon if math.isfinite(horizon) else 1.05 * flow.period
    if not math.isfinite(span):
        raise _never_ends(sim)
    h = min(span, flow.period / 64) if math.isfinite(flow.period) else span / 64
    return _sampled(sim, evs, flow.state, lambda s, y: h, span,
                    "the motion never ends: nothing stops it within a period")


def coasting(sim, evs, inst) -> Segment:
    """Constant accelerations, but an event that is not a quadratic in time (two round
    bodies closing, a point on a turning body): the closed form, sampled finely enough
    that nothing moves more than a fifth of the smallest size between samples."""
    model, n, y0, a = sim.model, sim.model.n, sim.y.copy(), inst.udot
    sizes = [r for w in model.watches for r in (w.ra, w.rb) if r > 0]
    size = min(sizes + [model.length_scale])
    acc = max([abs(x) for x in a] + [1e-300])

    def state(s):
        y = y0.copy()
        y[:n] = y0[:n] + y0[n:2 * n] * s + 0.5 * a * s * s
        y[n:2 * n] = y0[n:2 * n] + a * s
        return y

    def step(s, y):
        f = Frame(model, y[:n], y[n:2 * n])
        speed = max([max(abs(vx), abs(vy)) for vx, vy, _ in f.twist.values()] + [1e-300])
        turn = max([abs(w) for _, _, w in f.twist.values()] + [1e-300])
        return min(0.2 * size / speed, 0.2 / turn, math.sqrt(0.4 * size / acc))

    horizon = sim.t_end - sim.t
    seg = _sampled(sim, [e for e in evs if not e.needs_instant and e.kind != "drift"], state,
                   step, horizon, "the stop condition is not reached")
    t0, p0 = sim.t, inst.power
    y1 = seg.states[-1][1]
    p1 = instant(model, sim.phase, Frame(model, y1[:n], y1[n:2 * n])).power
    span = seg.t1 - t0
    for t, y in seg.states:  # the power of constant forces is linear in time here
        s = t - t0
        y[2 * n] = y0[2 * n] + p0 * s + (0.5 * (p1 - p0) / span * s * s if span else 0.0)
    return seg


def _sampled(sim, evs, state, step, span: float, never: str,
             max_samples: int = 100_000) -> Segment:
    """Events of a known motion `state(s)` (s: time since the phase began): bracketed by
    samples `step(s, y)` apart, then found by false position."""
    from .elliptic import root

    model, n, t0 = sim.model, sim.model.n, sim.t

    def g(e, s):
        y = state(s)
        return e.fn(Frame(model, y[:n], y[n:2 * n]), None)

    # the sign each function leaves the start with, a moment after it (a contact that
    # separates from a round-off overlap starts below zero, but is rising); None: zero
    first = min(step(0.0, state(0.0)), span) * 1e-9
    signs = []
    for e in evs:
        v0 = g(e, first)
        signs.append(math.copysign(1.0, v0) if v0 != 0 else None)
    prev, s, y = first, first, state(first)
    hit, best = None, span
    samples = []
    while s < span and hit is None:
        if len(samples) > max_samples:
            raise ProblemError(f"{never} by t = {t0 + s:.6g} s: add `until t = ...` to bound "
                               "the run", sim.spec.span, code="simulate")
        s = min(s + step(s, y), span)
        y = state(s)
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
                    found.append((root(lambda x: g(e, x), prev, s), e))
                signs[k] = math.copysign(1.0, v) if v != 0 else -signs[k]
        if found:
            best = min(r for r, _ in found)
            hit = first_of([e for r, e in found if r <= best * (1 + 1e-12)])
            break
        samples.append((s, y))
        prev = s
    if hit is None and not math.isfinite(span):
        raise _never_ends(sim)
    if hit is None and s < sim.t_end - t0:
        raise ProblemError(f"{never} (add `until t = ...`)", sim.spec.span, code="simulate")
    states = [(t0 + s_, y_) for s_, y_ in samples if s_ < best] + [(t0 + best, state(best))]
    return Segment(t0 + best, hit, states, "closed form", len(states), len(states))


def integrate(sim, evs) -> Segment:
    from scipy.integrate import solve_ivp

    model, phase, n = sim.model, sim.phase, sim.model.n
    t0, y0 = sim.t, sim.y.copy()
    counter = [0]

    def rhs(t, y):
        if not (math.isfinite(t) and np.all(np.isfinite(y))):
            raise ProblemError(f"the motion stopped being finite near t = {sim.t:.6g} s (the "
                               "integrator's step overflowed: a scale double precision cannot "
                               "follow)", sim.spec.span, code="simulate")
        f = Frame(model, y[:n], y[n:2 * n])
        inst = instant(model, phase, f)
        counter[0] += 1
        if sim.progress is not None and counter[0] % 256 == 0:
            sim.progress(t, sim.t_end)
        if counter[0] + sim.evaluations > UNBOUNDED_EVALUATIONS and \
                not math.isfinite(sim.t_end):
            raise ProblemError(f"the stop condition is not reached by t = {t:.6g} s "
                               f"({UNBOUNDED_EVALUATIONS:,} evaluations): add `until t = ...` "
                               "to bound the run", sim.spec.span, code="simulate")
        out = np.empty(2 * n + 1)
        out[:n] = y[n:2 * n]
        out[n:2 * n] = inst.udot
        out[2 * n] = inst.power
        return out

    fns = [_wrap(e, model, phase, t0, y0, rhs) for e in evs]
    horizon = sim.t_end
    if not math.isfinite(horizon):
        horizon = t0 + 1e6 * max(1.0, t0)
    kw = dict(method="DOP853", events=fns, rtol=sim.rtol, atol=sim.rtol * atol_scale(sim))
    if sim.dt is not None:
        # a step longer than the phase's span is clamped to it (scipy refuses it)
        kw.update(first_step=min(sim.dt, horizon - t0), max_step=sim.dt, rtol=1e3, atol=1e300)
    if sim.lift_off:
        kw["first_step"] = min(1e3 * sim.lift_off, kw.get("first_step", math.inf),
                               horizon - t0)
    sol = solve_ivp(rhs, (t0, horizon), y0, **kw)
    if sol.status == -1:
        raise ProblemError(f"the integration failed at t = {sol.t[-1]:.6g} s: {sol.message}",
                           sim.spec.span, code="simulate")
    hit, t_hit, y_hit = None, sol.t[-1], sol.y[:, -1]
    found = [(sol.t_events[k][0], k) for k in range(len(evs)) if len(sol.t_events[k])]
    if found:
        t_hit = min(t for t, _ in found)
        near = [k for t, k in found if t <= t_hit + 1e-12 * max(1.0, abs(t_hit))]
        hit = first_of([evs[k] for k in near])
        k = next(k for k in near if evs[k] is hit)
        t_hit, y_hit = sol.t_events[k][0], sol.y_events[k][0]
    if hit is None and not math.isfinite(sim.t_end):
        raise ProblemError(f"the stop condition is not reached by t = {t_hit:.6g} s: add "
                           "`until t = ...` to bound the run", sim.spec.span, code="simulate")
    states = [(float(sol.t[k]), sol.y[:, k].copy()) for k in range(1, len(sol.t))
              if sol.t[k] < t_hit]
    states.append((float(t_hit), np.array(y_hit, dtype=float)))
    return Segment(float(t_hit), hit, states, "fixed step" if sim.dt else "DOP853",
                   len(sol.t) - 1, sol.nfev)


def atol_scale(sim) -> np.ndarray:
    """Absolute tolerances per component: lengths, angles, speeds, work."""
    m, n = sim.model, sim.model.n
    L, V = m.length_scale, sim.v_scale
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
    s[2 * n] = max(abs(sim.E0), sum(b.mass for b in m.bodies) * V * V, 1e-300)
    return s * 1e-3


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
