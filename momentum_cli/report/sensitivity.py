"""The sensitivities section of a report: one dict for JSON, plain text and rich.

Stage: report. In: `sensitivity.Sensitivities`. Out: the JSON section (`section`),
plain-text lines (`text_lines`) and a rich rendering (`render_rich`), each answer's
given numbers ranked by how much a 1 % change of the number moves it.
"""
from __future__ import annotations

from ..numbers import fmt_num

ZERO_REL = 1e-9  # |d a/d p * p| below this fraction of the answer's scale is round-off


def section(s) -> dict:
    """The JSON `sensitivities` section (also what the text renderers read)."""
    params = [dict(id=p.id, label=p.label, line=p.line, column=p.column, text=p.text,
                   value=p.value, unit=p.unit, skipped=s.skipped.get(p.id))
              for p in s.parameters]
    units = {p.id: p.unit for p in s.parameters}
    answers = []
    for a in s.answers:
        scale = max([abs(a.value), a.size] + [s.effect(a, k) for k in a.derivatives])
        rows = []
        for pid in s.ranked(a):
            d = a.derivatives[pid]
            small = s.effect(a, pid) <= ZERO_REL * scale
            rel = s.relative(a, pid)
            rows.append(dict(parameter=pid, derivative=0.0 if small else d,
                             unit=per(a.unit, units[pid]),
                             relative=None if rel is None else (0.0 if small else rel)))
        answers.append(dict(name=a.name, value=a.value, unit=a.unit, derivatives=rows))
    return dict(note=s.note, unavailable=s.unavailable, parameters=params, answers=answers)


def per(answer_unit: str, given_unit: str) -> str:
    """The unit of d answer / d given: `rad/s per kg`, `m/s` (per a pure number)."""
    if not given_unit:
        return answer_unit
    return f"{answer_unit} per {given_unit}" if answer_unit else f"per {given_unit}"


def text_lines(sec: dict, sig: int, table) -> list[str]:
    """The plain-text section: the given numbers, then each answer's ranked derivatives
    (the numbers that do not move an answer are named in one line); `table` is the plain
    report's table layout."""
    f = lambda x: fmt_num(x, sig) if x is not None else "-"  # noqa: E731
    out = ["", f"Sensitivities ({sec['note']})"]
    if sec["unavailable"]:
        out.append(f"  not available: {sec['unavailable']}")
        return out
    params = {p["id"]: p for p in sec["parameters"]}
    out.extend(table(["given", "what", "line", "value"],
                     [[p["id"], p["label"], str(p["line"]), p["text"]]
                      for p in sec["parameters"]]))
    for p in sec["parameters"]:
        if p["skipped"]:
            out.append(f"  {p['id']} has no derivative: {p['skipped']}")
    for a in sec["answers"]:
        out.append("")
        out.append(f"  {a['name']} = {f(a['value'])} {a['unit']}".rstrip())
        moving = [r for r in a["derivatives"] if r["derivative"] != 0]
        still = sorted((r["parameter"] for r in a["derivatives"] if r["derivative"] == 0),
                       key=lambda pid: int(pid[1:]))
        if moving:
            out.extend(table(["given", "d answer / d given", "relative (d ln / d ln)"],
                             [[f"{r['parameter']} {params[r['parameter']]['label']}",
                               f"{f(r['derivative'])} {r['unit']}".rstrip(), f(r["relative"])]
                              for r in moving], indent="    "))
        if still:
            out.append(f"    independent of: {', '.join(still)}")
    return out


def render_rich(sec: dict, console, sig: int = 6) -> None:
    """The same section as tables on a terminal."""
    from rich import box
    from rich.markup import escape
    from rich.table import Table
    from rich.text import Text

    f = lambda x: fmt_num(x, sig) if x is not None else "-"  # noqa: E731
    console.print(Text(f"Sensitivities ({sec['note']})", style="bold cyan"))
    if sec["unavailable"]:
        console.print(f"  not available: {escape(sec['unavailable'])}")
        return
    params = {p["id"]: p for p in sec["parameters"]}
    t = Table(title="Given numbers", box=box.SIMPLE_HEAD, title_justify="left")
    for h in ("given", "what", "line", "value"):
        t.add_column(h)
    for p in sec["parameters"]:
        t.add_row(p["id"], escape(p["label"]), str(p["line"]), escape(p["text"]))
    console.print(t)
    for p in sec["parameters"]:
        if p["skipped"]:
            console.print(f"  {p['id']} has no derivative: {escape(p['skipped'])}")
    for a in sec["answers"]:
        t = Table(title=escape(f"{a['name']} = {f(a['value'])} {a['unit']}"),
                  box=box.SIMPLE_HEAD, title_justify="left")
        t.add_column("given")
        t.add_column("∂answer/∂given", justify="right")
        t.add_column("∂ln/∂ln", justify="right")
        for r in a["derivatives"]:
            if r["derivative"] != 0:
                t.add_row(escape(f"{r['parameter']} {params[r['parameter']]['label']}"),
                          escape(f"{f(r['derivative'])} {r['unit']}"), f(r["relative"]))
        console.print(t)
