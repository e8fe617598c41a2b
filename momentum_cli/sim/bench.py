"""`momentum bench simulate`: what each integration tolerance costs, on the seed scenes.

For each seed whose file has a `simulate` block, one quantity of the simulation is
compared with the value `solve` gives for the same file (its closed form): the
pendulum's rebound angle, the disk's stopping time, the rod's spin after the impact,
and so on. Each tolerance (and fixed step) is timed as the median of a few runs, from
the parsed scene to the result (start-up and parsing excluded).
"""
from __future__ import annotations

import math
import os
import statistics
import time
from dataclasses import dataclass

# file -> (what the simulation measures, the solve value it must equal, unit, label)
# what it measures is (when, body, qty): `final` at the end of the run; `impact` /
# `lock` just after the first such event; `stop_time` when the run stopped.
CASES = {
    "seed_pendulum_wall.mom": (("final", "pendulum", "angle"), "pendulum.angle@4", "deg",
                               "pendulum rebound angle"),
    "seed_disk_wall.mom": (("stop_time", None, None), "t@1->2", "s", "disk stopping time"),
    "seed_rod_drop_smooth.mom": (("impact", "rod", "omega"), "rod.omega@3", "rad/s",
                                 "rod spin after a smooth impact"),
    "seed_rod_drop_rough.mom": (("impact", "rod", "omega"), "rod.omega@3", "rad/s",
                                "rod spin after a rough impact"),
    "seed_billiards_elastic.mom": (("impact", "C", "vx"), "C.vx@2", "m/s", "billiard ball C"),
    "seed_rod_disk_bearing.mom": (("lock", "rod", "omega"), "rod.omega@2", "rad/s",
                                  "rod and disk after the bearing locks"),
}
RTOLS = tuple(10.0 ** -k for k in range(3, 13))
STEPS = (1e-2, 1e-3)


@dataclass
class Row:
    case: str
    setting: str  # "rtol 1e-06" or "dt 0.001 s"
    value: float
    error: float  # absolute, in `unit`
    unit: str
    seconds: float
    steps: int
    evaluations: int


def _measure(res, how: tuple) -> float:
    f = res.frame()
    kind, body, qty = how
    if kind == "stop_time":
        return float(res.events[-1].t)
    k = {"vx": 0, "vy": 1, "omega": 2}
    if kind == "final":
        if qty == "angle":
            return f.pose[body][2]
        return f.twist[body][k[qty]]
    ev = next(e for e in res.events if e.kind == kind)
    return ev.after[body][k[qty]]


def cases(root: str) -> list[tuple[str, str, str, str, str]]:
    out = []
    for name, (how, key, unit, label) in CASES.items():
        path = os.path.join(root, "examples", name)
        if os.path.exists(path):
            out.append((path, how, key, unit, label))
    return out


def run(paths_cases, repeat: int = 3, rtols=RTOLS, steps=STEPS, progress=None) -> list[Row]:
    from ..scene import build
    from ..solve import solve_scene
    from ..source import Source
    from ..syntax import parse
    from .integrate import simulate

    import scipy.integrate  # noqa: F401  (imported once here, not timed in the first run)

    rows = []  # the default run, then every phase integrated at each rtol and fixed step
    for path, how, key, unit, label in paths_cases:
        with open(path, encoding="utf-8") as fh:
            scene = build(parse(Source(path, fh.read())))
        exact = solve_scene(scene, solve_all=True).values[key]
        settings = [("closed", None)] + [("rtol", r) for r in rtols] + [("dt", d) for d in steps]
        for kind, x in settings:
            times = []
            for _ in range(repeat):
                t0 = time.perf_counter()
                res = simulate(scene, rtol=x if kind == "rtol" else 1e-9,
                               dt=x if kind == "dt" else None, closed_forms=kind == "closed")
                times.append(time.perf_counter() - t0)
            got = _measure(res, how)
            scale = math.degrees(1) if unit == "deg" else 1.0
            if kind == "closed":
                setting = "default: closed forms, rtol 1e-9"
            else:
                setting = f"integrated, rtol {x:.0e}" if kind == "rtol" else \
                    f"integrated, dt {x:g} s"
            rows.append(Row(label, setting,
                            got * scale, abs(got - exact) * scale, unit,
                            statistics.median(times), sum(p.steps for p in res.phases),
                            sum(p.evaluations for p in res.phases)))
            if progress:
                progress(label, rows[-1].setting)
    return rows


def table(rows: list[Row]) -> list[list[str]]:
    from ..numbers import fmt_num

    return [[r.case, r.setting, fmt_num(r.error, 2) + " " + r.unit,
             f"{r.seconds * 1e3:.3g}", str(r.steps), str(r.evaluations)] for r in rows]


HEADERS = ["scene", "setting", "error vs solve", "time (ms)", "steps", "evaluations"]


def markdown(rows: list[Row]) -> str:
    """Two Markdown tables: every setting on the first scene (the pendulum), then each
    other scene's default run."""
    from ..numbers import fmt_num

    def err(r):
        return "0" if r.error == 0 else f"{fmt_num(r.error, 2)} {r.unit}"

    def ms(r):
        x = r.seconds * 1e3
        return f"{x:.0f} ms" if x >= 100 else f"{x:.2g} ms"
    first = rows[0].case if rows else ""
    out = [f"| {first}: setting | error against `solve` | time | steps |", "|---|---:|---:|---:|"]
    out += [f"| {r.setting} | {err(r)} | {ms(r)} | {r.steps} |"
            for r in rows if r.case == first]
    out += ["", "| seed scene, default run | error against `solve` | time |", "|---|---:|---:|"]
    out += [f"| {r.case} | {err(r)} | {ms(r)} |" for r in rows
            if r.case != first and r.setting.startswith("default")]
    return "\n".join(out) + "\n"


def plot(rows: list[Row], path: str) -> None:
    """Error against time, one line per scene (matplotlib, the `plot` extra)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(8, 5))
    for case in dict.fromkeys(r.case for r in rows):
        mine = [r for r in rows if r.case == case and "rtol 1e-" in r.setting
                and r.setting.startswith("integrated")]
        ax.loglog([r.seconds * 1e3 for r in mine], [max(r.error, 1e-16) for r in mine],
                  "o-", label=case)
    ax.set_xlabel("wall time (ms)")
    ax.set_ylabel("error against solve (in the quantity's unit)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize="small")
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)
