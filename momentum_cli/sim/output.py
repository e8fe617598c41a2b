"""A simulation's report as data (rendered by report/sim_text, sim_rich, sim_json), and
its time series as CSV and a plot.

Values of round-off size are snapped to 0 here, so that the plain text (golden files)
is deterministic; wall times and step counts are kept for the rich and JSON output.
"""
from __future__ import annotations

import math

from ..numbers import fmt_num
from .forces import energy
from .integrate import SimResult

SNAP = 1e-10  # values below this fraction of their scale print as 0


def _snap(x: float, scale: float, floor: float = SNAP) -> float:
    return 0.0 if abs(x) < floor * scale else float(x)


def _decade(x: float) -> str:
    """An upper bound as a power of ten (stable in golden files)."""
    if x <= 1e-15:
        return "1e-15"
    return f"1e{math.ceil(math.log10(x))}"


def build(name: str, res: SimResult) -> dict:
    """Everything the renderers print, in SI."""
    model, scene = res.model, res.model.scene
    sim = scene.simulations[0]
    L = model.length_scale
    V, scale = _scales(res)
    floor = max(SNAP, 10 * res.rtol) if res.dt is None else 1e-6  # below the integration error

    def snap(x, scale):
        return _snap(x, scale, floor)
    effects = []
    if model.gravity is not None:
        effects.append(f"gravity ({fmt_num(model.gravity[0])}, {fmt_num(model.gravity[1])}) m/s^2")
    for b in model.bodies:
        if b.size == 1:
            effects.append(f"{b.name} turns about the pin at ({fmt_num(b.pivot[0])}, "
                           f"{fmt_num(b.pivot[1])}) m: one coordinate, its angle")
    for j in model.joints:
        effects.append(f"{j.kind} {j.label} (constraint force, line {j.span.line})")
    for j in model.springs:
        effects.append(f"spring {j.label}: k = {fmt_num(j.stiffness)} N/m, free length "
                       f"{fmt_num(j.length)} m (line {j.span.line})")
    for j in model.dampers:
        effects.append(f"damper {j.label}: c = {fmt_num(j.stiffness)} N*s/m (line {j.span.line})")
    for F, p, span in model.forces:
        effects.append(f"force ({fmt_num(F[0])}, {fmt_num(F[1])}) N on {p.name} (line {span.line})")
    for Mo, body, span in model.moments:
        effects.append(f"moment {fmt_num(Mo)} N*m on {body} (line {span.line})")
    for label, torque in model.bearings.items():
        effects.append(f"bearing friction {fmt_num(torque)} N*m at {label}")
    for w in model.watches:
        s = w.spec
        law = f"restitution {fmt_num(s.restitution if s.restitution is not None else 0.0)}"
        law += ", " + (f"friction {fmt_num(s.mu)}" if s.mode == "friction" else s.mode)
        other = w.b.name if w.b is not None else (s.surface or "ground")
        effects.append(f"contact {w.label}: {w.a.name} with {other}: {law} (line {s.span.line})")
    if not effects:
        effects.append("none: bodies move freely")
    events = []
    for e in res.events:
        bodies = []
        for b in model.bodies:
            after = e.after.get(b.name)
            before = e.before.get(b.name)
            if after is None:
                continue
            if e.kind == "impact" and before is not None and all(
                    abs(x - y) <= SNAP * V for x, y in zip(before, after)):
                continue
            bodies.append(dict(
                body=b.name,
                before=None if before is None else [snap(x, V) for x in before[:2]] +
                [snap(before[2], V / L)],
                after=[snap(x, V) for x in after[:2]] + [snap(after[2], V / L)]))
        events.append(dict(t=float(e.t), kind=e.kind, what=e.what, bodies=bodies,
                           energy_lost=_snap(e.energy_lost, abs(res.energy0) + 1e-300)
                           if e.kind == "impact" else None,
                           impulses={k: _snap(v, 1.0) for k, v in sorted(e.impulses.items())
                                     if k.startswith(("J_n", "J_t"))},
                           note=e.note))
    frame = res.frame()
    final = []
    for b in model.bodies:
        x, y, th = frame.pose[b.name]
        vx, vy, w = frame.twist[b.name]
        final.append(dict(body=b.name, x=snap(x, L), y=snap(y, L),
                          angle=None if b.particle else snap(th, 1.0),
                          vx=snap(vx, V), vy=snap(vy, V),
                          omega=None if b.particle else snap(w, V / L)))
    forces = {}
    if res.phase is not None:  # the constraint forces that hold the final state
        from .forces import instant

        forces = {k: _snap(v, 1.0, 1e-12) for k, v in instant(model, res.phase, frame).lam.items()}
    drift = max([p.drift for p in res.phases], default=0.0)
    rel = drift / scale
    checks = []
    if res.dt is None:
        ok = rel <= 10 * res.rtol
        checks.append(dict(name="energy drift", status="ok" if ok else "warning",
                           detail=f"max |E - E0 - W| between events < {_decade(rel)} of the "
                                  f"energy scale ({'within' if ok else 'above'} 10 rtol = "
                                  f"{fmt_num(10 * res.rtol, 2)})",
                           value=rel))
    else:
        checks.append(dict(name="energy drift", status="info",
                           detail=f"max |E - E0 - W| between events < {_decade(rel)} of the "
                                  f"energy scale (fixed step dt = {fmt_num(res.dt)} s)",
                           value=rel))
    if model.joints or any(e.kind in ("stick", "slip") for e in res.events) or \
            res.constraint_drift or res.projections:
        tol = res.drift_tolerance * L
        ok = res.constraint_drift <= tol * (1 + 1e-6) and not res.drift_raised
        checks.append(dict(
            name="constraint drift", status="ok" if ok else "warning",
            detail=f"joints and resting contacts held within {fmt_num(res.drift_tolerance, 1)} "
                   "of the size "
                   f"({fmt_num(tol, 2)} m); " + (
                       "positions never needed projecting back" if not res.projections else
                       f"positions projected back {res.projections} time"
                       f"{'s' if res.projections > 1 else ''}") + (
                       "; the coordinates were too coarse for the stated tolerance, which was "
                       "loosened to this" if res.drift_raised else ""),
            value=res.constraint_drift))
    phases = [dict(start=p.t0, end=p.t1, method=p.method, steps=p.steps,
                   evaluations=p.evaluations, drift=p.drift / scale) for p in res.phases]
    return dict(file=name, title=scene.title, start=sim.start, line=sim.span.line,
                stop=res.events[-1].what, t_end=float(res.events[-1].t), rtol=res.rtol,
                dt=res.dt, seconds=res.seconds, effects=effects, events=events,
                phases=phases, final=final, forces=forces, checks=checks,
                impacts=sum(1 for e in res.events if e.kind == "impact"))


def _scales(res: SimResult) -> tuple[float, float]:
    """The largest speed along the run (omega times the length scale for turning) and the
    energy it moves around (|E0|, or the largest kinetic energy: E0 alone is 0 for a
    body released at the height chosen as zero), in one pass over the states."""
    n, L = res.model.n, res.model.length_scale
    from .dynamics import Frame
    from .forces import kinetic

    speed, E = 1e-30, abs(res.energy0)
    for y in res.states:
        f = Frame(res.model, y[:n], y[n:2 * n])
        for vx, vy, w in f.twist.values():
            speed = max(speed, abs(vx), abs(vy), abs(w) * L)
        E = max(E, kinetic(res.model, f))
    return speed, max(E, 1e-300)


def csv_text(res: SimResult) -> str:
    """The time series: every integrator step and event, one row per time."""
    model, n = res.model, res.model.n
    from .dynamics import Frame

    cols = ["t"]
    for b in model.bodies:
        cols += [f"{b.name}.{q}" for q in ("x", "y", "angle", "vx", "vy", "omega")]
    cols += ["energy", "work"]
    lines = [",".join(cols)]
    for t, y in zip(res.times, res.states):
        f = Frame(model, y[:n], y[n:2 * n])
        row = [t]
        for b in model.bodies:
            row += list(f.pose[b.name]) + list(f.twist[b.name])
        row += [energy(model, f), y[2 * n]]
        lines.append(",".join(repr(float(x)) for x in row))
    return "\n".join(lines) + "\n"


def plot(res: SimResult, path: str) -> None:
    """Positions, velocities and energy against time (matplotlib, the `plot` extra)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from .dynamics import Frame

    model, n = res.model, res.model.n
    frames = [Frame(model, y[:n], y[n:2 * n]) for y in res.states]
    fig, axes = plt.subplots(3, 1, figsize=(8, 9), sharex=True)
    for b in model.bodies:
        axes[0].plot(res.times, [f.pose[b.name][0] for f in frames], label=f"{b.name}.x")
        axes[0].plot(res.times, [f.pose[b.name][1] for f in frames], label=f"{b.name}.y")
        axes[1].plot(res.times, [f.twist[b.name][0] for f in frames], label=f"{b.name}.vx")
        axes[1].plot(res.times, [f.twist[b.name][1] for f in frames], label=f"{b.name}.vy")
        if not b.particle:
            axes[1].plot(res.times, [f.twist[b.name][2] for f in frames], "--",
                         label=f"{b.name}.omega")
    axes[2].plot(res.times, [energy(model, f) for f in frames], label="E = T + V")
    axes[2].plot(res.times, [res.energy0 + y[2 * n] for y in res.states], ":",
                 label="E0 + work of other forces")
    for ax, lab in zip(axes, ("position (m)", "velocity (m/s, rad/s)", "energy (J)")):
        ax.set_ylabel(lab)
        ax.legend(loc="best", fontsize="small")
        ax.grid(True, alpha=0.3)
    for e in res.events:
        if e.kind == "impact":
            for ax in axes:
                ax.axvline(e.t, color="grey", lw=0.5)
    axes[2].set_xlabel("t (s)")
    fig.suptitle(model.scene.title or "simulation")
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)
