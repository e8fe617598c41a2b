"""Plain text: deterministic, no colour, ASCII only, fixed number formatting.

This is what golden files hold and what a pipe receives: the same content as the
rich report, laid out with spaces so that locale and terminal width cannot change it.
"""
from __future__ import annotations

from ..numbers import fmt_num, fmt_tiny
from .model import Report, diagram_for


def table(headers: list[str], rows: list[list[str]], indent: str = "  ") -> list[str]:
    """Columns padded to their widest cell; the last column is not padded."""
    widths = [len(h) for h in headers]
    for r in rows:
        for i, c in enumerate(r):
            widths[i] = max(widths[i], len(c))

    def line(cells):
        parts = [c.ljust(widths[i]) if i < len(cells) - 1 else c for i, c in enumerate(cells)]
        return (indent + "  ".join(parts)).rstrip()

    out = [line(headers), indent + "  ".join("-" * w for w in widths)]
    out.extend(line(r) for r in rows)
    return out


def render(rep: Report, sig: int = 6, steps: bool = True) -> str:
    f = lambda x: fmt_num(x, sig) if x is not None else "-"  # noqa: E731
    out: list[str] = []
    title = rep.title or "(untitled problem)"
    out.append(f"== {rep.file}: {title}")
    if steps:
        if rep.bodies:
            out.append("")
            out.append("Bodies")
        out.extend([] if not rep.bodies else table(["body", "shape", "mass (kg)", "I_G (kg*m^2)", "inertia formula"],
                         [[b["name"], b["shape"], f(b["mass"]),
                           "-" if b["particle"] else f(b["inertia"]),
                           b["formula"] + (" (mass = W/g)" if b["weight"] else "")]
                          for b in rep.bodies]))
        out.append("")
        out.append("Effects and constraints")
        out.extend("  " + e for e in rep.effects)
        if rep.knowns:
            out.append("")
            out.append("Knowns (SI)")
        for k in rep.knowns:
            label = f' "{k["label"]}"' if k["label"] else ""
            items = ", ".join(f"{n} = {f(v)} {u}".rstrip() if u != "hint" else f"{n} {f(v)}"
                              for n, v, u in k["items"]) or "(nothing given)"
            out.append(f"  state {k['id']}{label}: {items}")
        for volume in dict.fromkeys(r["volume"] for r in rep.flows):
            out.append("")
            out.append(f"Control volume {volume}: momentum fluxes (+ in, - out) and forces")
            out.extend(table(["", "line", "mdot (kg/s)", "v (m/s)", "mdot v or F (N)",
                              "r x (mdot v or F) (N*m)"],
                             [[r["what"], str(r["line"]), f(r["rate"]),
                               f"({f(r['vx'])}, {f(r['vy'])})" if r["rate"] is not None else "-",
                               f"({f(r['flux_x'])}, {f(r['flux_y'])})", f(r["moment"])]
                              for r in rep.flows if r["volume"] == volume]))
        for t in rep.transitions:
            out.append("")
            out.append(f"{t['kind'].capitalize()} {t['before']} -> {t['after']} (line {t['line']})")
            d = diagram_for(rep, t)
            if d is not None:
                out.extend("  " + x for x in d.lines())
            for w in t["why"]:
                out.append(f"  why: {w}")
            for r in t["equations"]:
                out.extend(_equation(r))
        for group, rows in rep.other_equations.items():
            out.append("")
            out.append(group[0].upper() + group[1:])
            for r in rows:
                out.extend(_equation(r))
        out.append("")
        out.append("Solving, block by block")
        for b in rep.blocks:
            how = (f"linear, condition number {f(b['condition_number'])}"
                   if b["method"] == "linear" else
                   "integrated numerically from its inputs" if b["method"] == "integrated" else
                   f"Newton, {b['iterations']} iterations, residual {fmt_tiny(b['residual'] or 0)}")
            lines = ", ".join(map(str, b["lines"]))
            out.append(f"  block {b['index']}: {', '.join(b['unknowns'])} ({how}; lines {lines})")
            if "matrix" in b:
                rows = [[f(x) for x in row] + ["|", f(rhs)] for row, rhs in
                        zip(b["matrix"], b["rhs"])]
                out.extend(table(b["unknowns"] + ["", "rhs"], rows, indent="      "))
        out.append("")
        out.append("Solution (SI)")
        out.extend(table(["unknown", "value", "unit"],
                         [[u["name"], f(u["si_value"]), u["unit"]] for u in rep.unknowns]))
        if rep.regimes:
            out.append("")
            out.append("Friction regimes")
            for r in rep.regimes:
                out.append(f"  {r['contact']} ({r['transition']}): {r['regime']}")
        out.append("")
        out.append("Checks")
        if rep.checks:
            out.extend(table(["check", "status", "detail"],
                             [[c.name, c.status, c.detail] for c in rep.checks]))
        else:
            out.append("  none: no impact, control volume or redundant equation to check")
        out.append("")
        out.append("Answers")
    for a in rep.answers:
        out.append(f"  {a['name']} = {f(a['value'])} {a['unit']}".rstrip())
    return "\n".join(out) + "\n"


def _equation(r) -> list[str]:
    line = f"line {r.line}" if r.line else "scene"
    tag = "" if r.role == "solved" else f" [{r.role}]"
    out = [f"  ({r.index + 1}) {r.principle} ({line}){tag}", f"      {r.symbolic}"]
    if r.numeric != r.symbolic:
        out.append(f"      {r.numeric}")
    return out


def render_quiet(rep: Report, sig: int = 6) -> str:
    return "".join(f"{a['name']} = {fmt_num(a['value'], sig) if a['value'] is not None else '-'}"
                   f" {a['unit']}".rstrip() + "\n" for a in rep.answers)
