"""What accuracy pymunk (a fixed-step 2D game physics engine) reaches, and at what wall
time, on the lecture-notes pendulum that hits a wall. A benchmark, not a test; pymunk is
a benchmark-only dependency (`pip install pymunk`), never imported by momentum.

Scene: a 4 kg uniform rod of length 2 m pinned at one end O (the origin), with a 10 kg
solid sphere of radius 0.3 m centred on its far end; gravity 9.81 m/s^2 down. Released
from rest with the rod horizontal (angle 0), it swings down; when the rod is vertical
(angle -90 deg) the ball strikes a smooth wall (normal +x, restitution e = 0.6) and
rebounds. Exact rebound angle, from the horizontal: asin(1 - e^2) = 39.7918195 deg.
Reported: the largest angle reached after the first impact, and its error.

Model in pymunk (stock engine, nothing patched):
  * one dynamic body, mass 14 kg, centre of gravity at the composite centre of mass
    (24/14 m from O along the rod), moment about that point I_O - m d^2 (pymunk's
    moment is about the centre of gravity); the body's origin is at O;
  * a PivotJoint between it and the space's static body at O;
  * the ball is a Circle shape (r = 0.3 m, elasticity 0.6, friction 0) centred 2 m
    along the rod; the wall is a static Segment (radius 0, elasticity 1, friction 0)
    at x = -0.3 m, so that the ball's surface touches it exactly when the rod is
    vertical (pymunk multiplies the two elasticities: 0.6 * 1 = 0.6);
  * space.collision_slop = 1e-9 m (default 0.1 m); the impact is pymunk's own contact,
    detected at the end of the step in which the ball first overlaps the wall.
The run stops at the first step after the impact at which the angular velocity is
no longer positive; the rebound angle is the largest sampled angle (the discrete
apex, as pymunk reports it). The apex of a parabola through the three samples around
it is in the JSON output (`rebound_interp_deg`) but not in the table: it moves the
result by at most a*dt^2/8 (a ~ 4 rad/s^2 at the apex), less than the error or
within its step-to-step scatter, so it is not useful here.

Three solver settings are swept:
  * pymunk defaults (space.iterations = 10, pin error_bias = pymunk's default, which
    leaves 10 % of the pin's drift after 1/60 s uncorrected);
  * space.iterations = 100;
  * a stiff pin: PivotJoint.error_bias = 0 (all pin drift corrected at the next step).
Time steps dt = 1/60 ... 1/64000 s; a dt whose run would take more than 20 s is
skipped. Wall time: time.perf_counter around one whole run (building the space,
stepping, apex detection in a Python loop), median of 3 runs, import time excluded.

    python bench/pymunk_pendulum.py           # Markdown tables
    python bench/pymunk_pendulum.py --json    # a JSON list of rows
"""
from __future__ import annotations

import argparse
import json
import math
import statistics
import sys
import time
from dataclasses import asdict, dataclass

try:
    import pymunk
except ImportError:  # pragma: no cover - benchmark-only dependency
    sys.exit("pymunk is not installed: pip install pymunk")

# ---- the scene ------------------------------------------------------------------------------

ROD_MASS = 4.0  # kg
ROD_LENGTH = 2.0  # m
BALL_MASS = 10.0  # kg
BALL_RADIUS = 0.3  # m
GRAVITY = 9.81  # m/s^2
RESTITUTION = 0.6

MASS = ROD_MASS + BALL_MASS
COM = (ROD_MASS * ROD_LENGTH / 2 + BALL_MASS * ROD_LENGTH) / MASS  # from O, along the rod
I_O = (ROD_MASS * ROD_LENGTH**2 / 3 + BALL_MASS * ROD_LENGTH**2
       + 2 / 5 * BALL_MASS * BALL_RADIUS**2)
I_COM = I_O - MASS * COM**2  # pymunk's moment is about the centre of gravity
EXACT_DEG = math.degrees(math.asin(1 - RESTITUTION**2))

# ---- the benchmark --------------------------------------------------------------------------

DTS = (1 / 60, 1 / 240, 1 / 1000, 1 / 4000, 1 / 16000, 1 / 64000)
TIME_LIMIT_S = 20.0
COLLISION_SLOP = 1e-9  # m
MAX_SIM_TIME_S = 10.0  # the apex comes after about 1.6 s
DEFAULT_ERROR_BIAS = pymunk.Space().collision_bias  # = a joint's default: (1 - 0.1)^60


@dataclass(frozen=True)
class Solver:
    name: str
    iterations: int
    pin_error_bias: float | None  # None: pymunk's default


SOLVERS = (
    Solver("pymunk defaults (iterations=10, default pin error_bias)", 10, None),
    Solver("space.iterations=100", 100, None),
    Solver("stiff pin: PivotJoint.error_bias=0 (iterations=10)", 10, 0.0),
)


@dataclass
class Row:
    solver: str
    iterations: int
    pin_error_bias: float
    dt: float
    steps: int
    rebound_deg: float
    rebound_interp_deg: float
    error_deg: float
    pin_drift_m: float  # distance of the body's pin point from O at the impact
    wall_ms: float
    pymunk: str = pymunk.version


def build_space(solver: Solver) -> tuple[pymunk.Space, pymunk.Body]:
    """The pendulum, its pin and the wall, at rest with the rod horizontal."""
    space = pymunk.Space()
    space.gravity = (0.0, -GRAVITY)
    space.iterations = solver.iterations
    space.collision_slop = COLLISION_SLOP

    body = pymunk.Body(MASS, I_COM)
    body.center_of_gravity = (COM, 0.0)  # body frame: origin at O, rod along +x
    body.position = (0.0, 0.0)
    body.angle = 0.0

    ball = pymunk.Circle(body, BALL_RADIUS, offset=(ROD_LENGTH, 0.0))
    ball.elasticity, ball.friction = RESTITUTION, 0.0

    # the ball's centre is at (0, -2) when the rod is vertical: its surface at x = -0.3
    wall = pymunk.Segment(space.static_body, (-BALL_RADIUS, -ROD_LENGTH - 1.0),
                          (-BALL_RADIUS, -ROD_LENGTH + 1.0), 0.0)
    wall.elasticity, wall.friction = 1.0, 0.0

    pin = pymunk.PivotJoint(space.static_body, body, (0.0, 0.0))
    if solver.pin_error_bias is not None:
        pin.error_bias = solver.pin_error_bias

    space.add(body, ball, wall, pin)
    return space, body


def parabola_vertex(a0: float, a1: float, a2: float) -> float:
    """The extreme value of the parabola through three equally spaced samples."""
    curvature = a0 - 2 * a1 + a2
    return a1 if curvature == 0 else a1 - (a2 - a0) ** 2 / (8 * curvature)


def simulate(dt: float, solver: Solver) -> tuple[int, float, float, float]:
    """Release, impact, first apex after the impact. Returns (steps to the apex,
    discrete apex angle, interpolated apex angle, pin drift at the impact), angles in
    radians, measured as pymunk's body angle (negative below the horizontal)."""
    space, body = build_space(solver)
    max_steps = int(MAX_SIM_TIME_S / dt)
    rebounded = False
    before = angle = drift = 0.0
    for step in range(1, max_steps + 1):
        before = angle
        space.step(dt)
        angle, omega = body.angle, body.angular_velocity
        if not rebounded:
            rebounded = omega > 0  # the wall reversed the swing
            if rebounded:  # fastest point of the swing: largest drift of the pin
                drift = body.local_to_world((0.0, 0.0)).length
        elif omega <= 0:  # angle[step] is the largest sample: apex
            space.step(dt)
            after = body.angle
            return step, angle, parabola_vertex(before, angle, after), drift
    raise RuntimeError(f"no apex after the impact within {MAX_SIM_TIME_S} s (dt={dt})")


def measure(dt: float, solver: Solver, repeat: int) -> Row:
    """One row: the result of a run and the median wall time of `repeat` runs (a single
    run if it already takes longer than the time limit)."""
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        steps, apex, apex_interp, drift = simulate(dt, solver)
        times.append(time.perf_counter() - t0)
        if times[-1] > TIME_LIMIT_S:
            break
    rebound = -math.degrees(apex)
    return Row(solver=solver.name, iterations=solver.iterations,
               pin_error_bias=(DEFAULT_ERROR_BIAS if solver.pin_error_bias is None
                               else solver.pin_error_bias),
               dt=dt, steps=steps, rebound_deg=rebound,
               rebound_interp_deg=-math.degrees(apex_interp),
               error_deg=abs(rebound - EXACT_DEG), pin_drift_m=drift,
               wall_ms=statistics.median(times) * 1e3)


def sweep(solver: Solver, dts: tuple[float, ...], repeat: int) -> list[Row]:
    """All time steps, finest last; a dt whose run is predicted (from the previous one,
    time proportional to the number of steps) to take more than the limit is skipped."""
    rows: list[Row] = []
    for dt in dts:
        if rows and rows[-1].wall_ms / 1e3 * rows[-1].dt / dt > TIME_LIMIT_S:
            print(f"  skipped dt={dt:.3g} s: predicted > {TIME_LIMIT_S:g} s", file=sys.stderr)
            continue
        rows.append(measure(dt, solver, repeat))
    return rows


def dt_label(dt: float) -> str:
    return f"1/{round(1 / dt)} s"


def markdown(solver: Solver, rows: list[Row]) -> str:
    lines = [f"**{solver.name}**", "",
             "| pymunk dt | steps | rebound angle (deg) | error (deg) | wall time (ms) |",
             "|---|---:|---:|---:|---:|"]
    for r in rows:
        lines.append(f"| {dt_label(r.dt)} | {r.steps} | {r.rebound_deg:.9f} | "
                     f"{r.error_deg:.2e} | {r.wall_ms:.3g} |")
    return "\n".join(lines)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--json", action="store_true", help="print a JSON list of rows")
    ap.add_argument("--repeat", type=int, default=3, help="timed runs per dt (median)")
    args = ap.parse_args()

    results = [(s, sweep(s, DTS, args.repeat)) for s in SOLVERS]
    if args.json:
        print(json.dumps([asdict(r) for _, rows in results for r in rows], indent=2))
        return
    print(f"pymunk {pymunk.version}, Python {sys.version.split()[0]}; "
          f"exact rebound angle asin(1 - e^2) = {EXACT_DEG:.9f} deg\n")
    print("\n\n".join(markdown(s, rows) for s, rows in results))


if __name__ == "__main__":
    main()
