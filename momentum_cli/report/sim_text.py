"""Plain text of a simulation's report (the dict from sim/output.build): deterministic,
ASCII, numbers to N significant figures, no wall times or step counts (they depend on
the machine and the scipy version); this is what the `.sim.out` golden files hold.
"""
from __future__ import annotations

import math

from ..numbers import fmt_num
from .text import table


def vec(v, k=0, sig=6):
    return f"({fmt_num(v[k], sig)}, {fmt_num(v[k + 1], sig)})"


def render(rep: dict, sig: int = 6) -> str:
    f = lambda x: "-" if x is None else fmt_num(x, sig)  # noqa: E731
    out = [f"== {rep['file']}: {rep['title'] or '(untitled problem)'}", ""]
    how = f"fixed step dt = {f(rep['dt'])} s" if rep["dt"] else f"rtol {fmt_num(rep['rtol'], 2)}"
    when = "" if rep["stop"].startswith("t = ") else f", t = {f(rep['t_end'])} s"
    out.append(f"Simulation from state {rep['start']} (line {rep['line']}), {how}; stopped at "
               f"{rep['stop']}{when}")
    out += ["", "Effects declared (nothing else acts)"] + ["  " + e for e in rep["effects"]]
    rows = []
    for e in rep["events"]:
        first = True
        for b in e["bodies"] or [None]:
            cells = [f(e["t"]) if first else "", e["kind"] if first else "",
                     e["what"] if first else ""]
            if b is None:
                cells += ["", "", "", "", "", ""]
            else:
                bf = b["before"]
                cells += [b["body"], "-" if bf is None else vec(bf, 0, sig),
                          "-" if bf is None else f(bf[2]), vec(b["after"], 0, sig),
                          f(b["after"][2])]
                cells.append(f(e["energy_lost"]) if first and e["energy_lost"] is not None
                             else "")
            rows.append(cells)
            first = False
    out += ["", "Events"]
    out += table(["t (s)", "event", "what", "body", "v before (m/s)", "omega before",
                  "v after (m/s)", "omega after", "energy lost (J)"], rows)
    imp = [(e, k, v) for e in rep["events"] for k, v in e["impulses"].items()]
    if imp:
        out += ["", "Impulses (N*s) and friction regimes"]
        out += table(["t (s)", "impulse", "value", "regime"],
                     [[f(e["t"]), k, f(v), e["note"]] for e, k, v in imp])
    out += ["", "Phases (motion between events)"]
    out += table(["from (s)", "to (s)", "method"],
                 [[f(p["start"]), f(p["end"]), p["method"]] for p in rep["phases"]])
    out += ["", f"Final state at t = {f(rep['t_end'])} s"]
    out += table(["body", "x (m)", "y (m)", "angle (deg)", "vx (m/s)", "vy (m/s)",
                  "omega (rad/s)"],
                 [[s["body"], f(s["x"]), f(s["y"]),
                   "-" if s["angle"] is None else f(math.degrees(s["angle"])),
                   f(s["vx"]), f(s["vy"]), f(s["omega"])] for s in rep["final"]])
    if rep["forces"]:
        out += ["", "Constraint forces at the end (N; N*m for moments)"]
        out += table(["force", "value"], [[k, f(v)] for k, v in rep["forces"].items()])
    out += ["", "Checks"] + [f"  {c['name']}: {c['status']}: {c['detail']}"
                             for c in rep["checks"]]
    return "\n".join(out) + "\n"
