"""Rich rendering for a terminal: the same content as the plain report, as tables.

Imported only when stdout is a terminal (or `--format rich`): rich costs ~70 ms to
import, which plain and JSON output never pay.
"""
from __future__ import annotations

from ..numbers import fmt_num
from .abbrev import name_list
from .model import Report, diagram_for
from .text import _items


def render(rep: Report, console, sig: int = 6, steps: bool = True,
           detail: str = "full") -> None:
    from rich import box
    from rich.markup import escape
    from rich.table import Table
    from rich.text import Text

    if steps and detail == "brief":
        return render_brief(rep, console, sig)
    f = lambda x: fmt_num(x, sig) if x is not None else "-"  # noqa: E731
    uu = rep.units or {}
    console.rule(Text(f"{rep.file}: {rep.title or '(untitled problem)'}", style="bold"))
    if steps:
        t = Table(title="Bodies", box=box.SIMPLE_HEAD, title_justify="left")
        for h in ("body", "shape", f"mass ({uu.get('mass', 'kg')})",
                  f"I_G ({uu.get('inertia', 'kg*m^2')})", "inertia formula"):
            t.add_column(h, justify="right" if "(" in h else "left")
        for b in rep.bodies:
            t.add_row(escape(b["name"]), b["shape"], f(b.get("shown_mass", b["mass"])),
                      "-" if b["particle"] else f(b.get("shown_inertia", b["inertia"])),
                      escape(b["formula"] + (" (mass = W/g)" if b["weight"] else "")))
        if rep.bodies:
            console.print(t)
        for e in rep.effects:
            console.print(f"  [dim]•[/dim] {escape(e)}")
        t = Table(title=f"Knowns ({uu.get('name', 'SI')})", box=box.SIMPLE_HEAD,
                  title_justify="left")
        t.add_column("state")
        t.add_column("given")
        for k in rep.knowns:
            items = _items(k, f) or "(nothing given)"
            t.add_row(escape(f"{k['id']} {k['label']}".strip()), escape(items))
        if rep.knowns:
            console.print(t)
        for volume in dict.fromkeys(x["volume"] for x in rep.flows):
            t = Table(title=f"Control volume {volume}: momentum fluxes (+ in, - out)",
                      box=box.SIMPLE_HEAD, title_justify="left")
            for h in ("", "line", "ṁ (kg/s)", "v (m/s)", "ṁv or F (N)", "r × (ṁv or F) (N·m)"):
                t.add_column(h, justify="left" if not h else "right")
            for x in rep.flows:
                if x["volume"] == volume:
                    v = f"({f(x['vx'])}, {f(x['vy'])})" if x["rate"] is not None else "-"
                    t.add_row(x["what"], str(x["line"]), f(x["rate"]), v,
                              f"({f(x['flux_x'])}, {f(x['flux_y'])})", f(x["moment"]))
            console.print(t)
        sections = [(f"{t['kind'].capitalize()} {t['before']} → {t['after']} (line {t['line']})",
                     t["why"], t["equations"], diagram_for(rep, t)) for t in rep.transitions]
        sections += [(g[0].upper() + g[1:], [], rows, None)
                     for g, rows in rep.other_equations.items()]
        for title, why, rows, diagram in sections:
            console.print(Text(title, style="bold cyan"))
            if diagram is not None:
                _diagram(console, diagram)
            for w in why:
                console.print(f"  [green]why:[/green] {escape(w)}")
            t = Table(box=box.SIMPLE, show_header=True, pad_edge=False)
            t.add_column("#", justify="right", style="dim")
            t.add_column("principle")
            t.add_column("equation (symbolic / numbers)")
            for r in rows:
                tag = "" if r.role == "solved" else f" [dim]\\[{r.role}][/dim]"
                eqn = escape(r.symbolic)
                if r.numeric != r.symbolic:
                    eqn += "\n[dim]" + escape(r.numeric) + "[/dim]"
                line = f"line {r.line}" if r.line else "scene"
                t.add_row(str(r.index + 1), escape(f"{r.principle} ({line})") + tag, eqn)
            console.print(t)
        console.print(Text("Solving, block by block", style="bold cyan"))
        for b in rep.blocks:
            how = (f"linear, cond {f(b['condition_number'])}" if b["method"] == "linear"
                   else "integrated" if b["method"] == "integrated"
                   else f"Newton, {b['iterations']} iterations")
            console.print(f"  block {b['index']}: "
                          f"[bold]{escape(name_list(b['unknowns'], 'unknowns'))}[/bold]"
                          f" ({how})")
            if "matrix" in b:
                t = Table(box=box.MINIMAL, pad_edge=False)
                for u in b["unknowns"]:
                    t.add_column(escape(u), justify="right")
                t.add_column("rhs", justify="right", style="yellow")
                for row, rhs in zip(b["matrix"], b["rhs"]):
                    t.add_row(*[f(x) for x in row], f(rhs))
                console.print(t)
        t = Table(title=f"Solution ({uu.get('name', 'SI')})", box=box.SIMPLE_HEAD,
                  title_justify="left")
        t.add_column("unknown")
        t.add_column("value", justify="right")
        t.add_column("unit")
        for x in rep.unknowns:
            t.add_row(escape(x["name"]), f(x.get("value", x["si_value"])),
                      x.get("shown_unit", x["unit"]))
        console.print(t)
        t = Table(title="Checks", box=box.SIMPLE_HEAD, title_justify="left")
        t.add_column("check")
        t.add_column("status")
        t.add_column("detail")
        colours = {"ok": "green", "warning": "yellow", "error": "red", "info": "blue"}
        for c in rep.checks:
            t.add_row(escape(c.name), f"[{colours.get(c.status, 'white')}]{c.status}[/]",
                      escape(c.detail))
        if rep.checks:
            console.print(t)
        else:
            console.print("Checks: none (no impact, control volume or redundant equation)")
        for r in rep.regimes:
            console.print(f"  friction at {escape(r['contact'])} ({r['transition']}): "
                          f"[bold]{r['regime']}[/bold]")
    _answers(rep, console, sig)


def _answers(rep: Report, console, sig: int) -> None:
    from rich import box
    from rich.markup import escape
    from rich.table import Table

    t = Table(title="Answers", box=box.ROUNDED, title_justify="left")
    t.add_column("quantity", style="bold")
    t.add_column("value", justify="right")
    t.add_column("unit")
    t.add_column("")
    for a in rep.answers:
        v = fmt_num(a["value"], sig) if a["value"] is not None else "-"
        t.add_row(escape(a["name"]), v, escape(a["unit"]), escape(a.get("direction") or ""))
    console.print(t)
    if rep.sensitivities:
        from .sensitivity import render_rich

        render_rich(rep.sensitivities, console, sig)


def render_brief(rep: Report, console, sig: int = 6) -> None:
    """The brief derivation (text.render_brief's content), headings in colour, the
    numeric lines dimmed under their symbolic lines, the answers as a table."""
    from rich.markup import escape
    from rich.text import Text

    from .text import render_brief as brief_text

    console.rule(Text(f"{rep.file}: {rep.title or '(untitled problem)'}", style="bold"))
    lines = brief_text(rep, sig, sensitivities=False).splitlines()[1:]
    cut = lines.index("Answers") if "Answers" in lines else len(lines)
    for i, line in enumerate(lines[:cut]):
        if line and not line.startswith(" "):
            console.print(Text(line, style="bold cyan"))
        elif line.startswith("  why: "):
            console.print(f"  [green]why:[/green] {escape(line[7:])}")
        elif line.startswith("      ") and i > 0 and lines[i - 1].startswith("      "):
            console.print(Text(line, style="dim"), soft_wrap=True)
        else:
            console.print(Text(line), soft_wrap=line.startswith("      "))
    _answers(rep, console, sig)
    colours = {"ok": "green", "warning": "yellow", "error": "red", "info": "blue"}
    for line in lines[cut:]:
        if line.startswith("  ") and ": " in line:
            status, rest = line.strip().split(": ", 1)
            console.print(f"  [{colours.get(status, 'white')}]{status}[/] {escape(rest)}")
        elif line == "Checks":
            console.print(Text(line, style="bold cyan"))


def _diagram(console, d) -> None:
    """The impulse diagram's list: its title, each body's impulses, what is dropped."""
    from rich.markup import escape

    lines = d.lines()
    console.print(f"  [bold magenta]{escape(lines[0])}[/bold magenta]")
    for x in lines[1:]:
        s = x.strip()
        style = "dim" if s.startswith(("dropped:", "note:")) else \
            ("bold" if not x.startswith("    ") else "")
        body = escape(x)
        console.print(f"  [{style}]{body}[/{style}]" if style else f"  {body}")
