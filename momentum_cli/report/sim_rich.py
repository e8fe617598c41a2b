"""Rich tables of a simulation's report for a terminal: the plain report's content plus
the wall time, steps and evaluations of each phase.
"""
from __future__ import annotations

import math

from ..numbers import fmt_num
from .sim_text import vec


def render(rep: dict, console, sig: int = 6) -> None:
    from rich.markup import escape as esc
    from rich.table import Table

    f = lambda x: "-" if x is None else fmt_num(x, sig)  # noqa: E731
    how = f"fixed step dt = {f(rep['dt'])} s" if rep["dt"] else f"rtol {fmt_num(rep['rtol'], 2)}"
    console.rule(f"[bold]{esc(rep['file'])}[/]: {esc(rep['title'] or '(untitled problem)')}")
    when = "" if rep["stop"].startswith("t = ") else f", t = {f(rep['t_end'])} s"
    console.print(f"Simulated from state {rep['start']} with {how}; stopped at "
                  f"[bold]{esc(rep['stop'])}[/]{when}, in {rep['seconds'] * 1e3:.3g} ms")
    console.print("[bold]Effects declared[/] (nothing else acts): " +
                  esc("; ".join(rep["effects"])))
    t = Table(title="Events", show_lines=False)
    for h in ("t (s)", "event", "what", "body", "v before (m/s)", "ω before", "v after (m/s)",
              "ω after", "energy lost (J)"):
        t.add_column(h, justify="right" if h[0] in "tvωe" and h != "event" else "left",
                     overflow="fold")  # a narrow terminal wraps numbers, never cuts them
    for e in rep["events"]:
        for k, b in enumerate(e["bodies"] or [None]):
            head = [f(e["t"]), e["kind"], esc(e["what"])] if k == 0 else ["", "", ""]
            if b is None:
                t.add_row(*head, "", "", "", "", "", "")
                continue
            bf = b["before"]
            t.add_row(*head, esc(b["body"]), "-" if bf is None else vec(bf, 0, sig),
                      "-" if bf is None else f(bf[2]), vec(b["after"], 0, sig),
                      f(b["after"][2]),
                      f(e["energy_lost"]) if k == 0 and e["energy_lost"] is not None else "")
    console.print(t)
    p = Table(title="Phases")
    for h in ("from (s)", "to (s)", "method", "steps", "evaluations", "energy drift"):
        p.add_column(h)
    for ph in rep["phases"]:
        p.add_row(f(ph["start"]), f(ph["end"]), ph["method"], str(ph["steps"]),
                  str(ph["evaluations"]), fmt_num(ph["drift"], 2))
    console.print(p)
    s = Table(title=f"Final state at t = {f(rep['t_end'])} s")
    for h in ("body", "x (m)", "y (m)", "angle (deg)", "vx (m/s)", "vy (m/s)", "ω (rad/s)"):
        s.add_column(h, justify="left" if h == "body" else "right")
    for r in rep["final"]:
        s.add_row(esc(r["body"]), f(r["x"]), f(r["y"]),
                  "-" if r["angle"] is None else f(math.degrees(r["angle"])), f(r["vx"]),
                  f(r["vy"]), f(r["omega"]))
    console.print(s)
    if rep["forces"]:
        c = Table(title="Constraint forces at the end (N; N·m for moments)")
        c.add_column("force")
        c.add_column("value", justify="right")
        for k, v in rep["forces"].items():
            c.add_row(esc(k), f(v))
        console.print(c)
    for c in rep["checks"]:
        colour = {"ok": "green", "warning": "yellow"}.get(c["status"], "cyan")
        console.print(f"[{colour}]{c['status']}[/] {esc(c['name'])}: {esc(c['detail'])}")
