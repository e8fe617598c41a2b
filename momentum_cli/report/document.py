"""The solution sheet as a list of blocks that Markdown, LaTeX and HTML each write out.

Stage: report. In: a `Report` (the one model every format renders). Out: blocks --
headings, paragraphs, lists, tables, display equations, impulse diagrams -- whose text
is a list of inline pieces (plain text, math boxes, code). The three document formats
share this outline, so they show the same content in the same order; no physics here.
"""
from __future__ import annotations

from ..numbers import fmt_num, fmt_tiny
from .math_tree import line_box, name_box, number_box
from .model import Report
from .text import key_checks

# Inline pieces: a str is plain text; ("math", box), ("code", text), ("strong", text),
# ("em", text), ("unit", unit label).
# Blocks: ("heading", level, inlines), ("para", inlines), ("list", [inlines, ...]),
# ("table", headers, rows, aligns) with cells as inlines and aligns "l"/"r" per column,
# ("eqlabel", number, text, role or None) an equation's number, principle and role;
# ("equation", box or None, plain text), ("diagram", diagram object), ("rule",).


def math(box) -> tuple:
    return ("math", box)


def qty(name: str, value, unit: str, sig: int) -> list:
    """`name = value unit` as one math piece."""
    items = (name_box(name), ("mo", "="), number_box(value, sig) if value is not None
             else ("mtext", "-"))
    if unit:
        items += (("space",), ("unit", unit))
    return [math(("row", items))]


def outline(rep: Report, sig: int = 6, detail: str = "full") -> list[tuple]:
    """Every block of one report, in the order of the plain report; `detail` "brief"
    (--steps brief) keeps what `text.render_brief` keeps: the principles with their
    solved or checked equations, the answers and the key checks."""
    brief = detail == "brief"
    f = lambda x: fmt_num(x, sig) if x is not None else "-"  # noqa: E731
    out: list[tuple] = [("heading", 1, [rep.title or "(untitled problem)"]),
                        ("para", ["Problem file ", ("code", rep.file), "."])]
    # the reader's units where the model has them (`units`, shown_* and value beside SI)
    u = getattr(rep, "units", None) or {}
    if rep.bodies:
        out.append(("heading", 2, ["Bodies"]))
        rows = [[[b["name"]], [b["shape"]], [f(b.get("shown_mass", b["mass"]))],
                 ["-" if b["particle"] else f(b.get("shown_inertia", b["inertia"]))],
                 [("code", b["formula"]), " (mass = W/g)" if b["weight"] else ""]]
                for b in rep.bodies]
        out.append(("table", [["body"], ["shape"], ["mass (", ("unit", u.get("mass", "kg")), ")"],
                              [math(("sub", ("mi", "I"), ("mi", "G"))), " (",
                               ("unit", u.get("inertia", "kg*m^2")), ")"], ["inertia formula"]],
                    rows, "llrrl"))
    out.append(("heading", 2, ["Effects and constraints"]))
    out.append(("list", [[e] for e in rep.effects]))
    if rep.knowns:
        out.append(("heading", 2, [f"Knowns ({u.get('name', 'SI')})"]))
        rows = []
        for k in rep.knowns:
            given: list = []
            units = k.get("units") or [""] * len(k["items"])
            for (n, v, unit), hint_unit in zip(k["items"], units):
                if given:
                    given.append(", ")
                if unit == "hint":
                    name, _, rel = n.partition(" ")
                    items = (name_box(f"{name}@{k['id']}"), ("mo", rel), number_box(v, sig))
                    if hint_unit:
                        items += (("space",), ("unit", hint_unit))
                    given += [math(("row", items)), " (hint)"]
                else:
                    given += qty(f"{n}@{k['id']}", v, unit, sig)
            rows.append([[str(k["id"])], [k["label"]], given or ["(nothing given)"]])
        out.append(("table", [["state"], ["label"], ["given"]], rows, "lll"))
    out += _flows(rep, f)
    # an impact's or interval's impulse diagram opens its section (the first step of a
    # textbook solution); one that names no transition is shown before them all
    diagrams = list(getattr(rep, "diagrams", None) or [])
    placed = {_of(d.kind, d.key): d for d in diagrams if getattr(d, "kind", None)}
    loose = [d for d in diagrams
             if not any(_of(t["kind"], t.get("key")) == _of(getattr(d, "kind", None),
                                                          getattr(d, "key", None))
                        for t in rep.transitions)]
    if loose:
        out.append(("heading", 2, ["Impulse diagrams"]))
        out += [("diagram", d) for d in loose]
    for t in rep.transitions:
        arrow = [t["kind"].capitalize() + " ", math(("row", (("mn", str(t["before"])), ("mo", "→"),
                                                            ("mn", str(t["after"]))))),
                 f" (line {t['line']})"]
        out.append(("heading", 2, arrow))
        if _of(t["kind"], t.get("key")) in placed:
            out.append(("diagram", placed[_of(t["kind"], t.get("key"))]))
        if t["why"]:
            out.append(("list", [[("em", "why: "), w] for w in t["why"]]))
        out += _system(t)
        for r in t["equations"]:
            if not brief or r.role in ("solved", "check"):
                out += _equation(r)
    for group, rows in rep.other_equations.items():
        rows = [r for r in rows if not brief or r.role in ("solved", "check")]
        if brief and (group.startswith("state ") or not rows):
            continue  # the constraint bookkeeping of each state is in --steps full
        out.append(("heading", 2, [group[0].upper() + group[1:]]))
        for r in rows:
            out += _equation(r)
    if not brief:
        out += _blocks(rep, f)
    if not brief:
        out.append(("heading", 2, [f"Solution ({u.get('name', 'SI')})"]))
        out.append(("table", [["unknown"], ["value"], ["unit"]],
                    [[[math(name_box(x["name"]))], [f(x.get("value", x["si_value"]))],
                      [("unit", x.get("shown_unit", x["unit"]))]] for x in rep.unknowns],
                    "lrl"))
    if rep.regimes:
        out.append(("heading", 2, ["Friction regimes"]))
        out.append(("list", [[f"{r['contact']} ({r['transition']}): ", ("strong", r["regime"])]
                             for r in rep.regimes]))
    out.append(("heading", 2, ["Checks"]))
    checks = key_checks(rep) if brief else rep.checks
    if checks:
        out.append(("table", [["check"], ["status"], ["detail"]],
                    [[[c.name], [("strong", c.status)] if c.status != "ok" else [c.status],
                      [c.detail]] for c in checks], "lll"))
    else:
        out.append(("para", ["None: no impact, control volume or redundant equation to check."]))
    out.append(("heading", 2, ["Answers"]))
    way = any(a.get("direction") for a in rep.answers)  # clockwise, to the left, ...
    out.append(("table", [["quantity"], ["value"], ["unit"]] + ([["direction"]] if way else []),
                [[[math(name_box(a["name"]))], [("strong", f(a["value"]))], [("unit", a["unit"])]]
                 + ([[a.get("direction") or ""]] if way else []) for a in rep.answers],
                "lrll" if way else "lrl"))
    return out


def _of(kind, key) -> tuple:
    """A transition's identity as plain strings (a kind may be an Enum or its value)."""
    return (str(getattr(kind, "value", kind)), str(key))


def _equation(r) -> list[tuple]:
    line = f"line {r.line}" if r.line else "scene"
    out: list[tuple] = [("eqlabel", f"({r.index + 1})", f"{r.principle} ({line})",
                         None if r.role == "solved" else f"[{r.role}]")]
    out.append(("equation", typeset(r.symbolic), r.symbolic))
    if r.numeric != r.symbolic:
        out.append(("equation", typeset(r.numeric), r.numeric))
    return out


def typeset(text: str) -> tuple | None:
    """The box for a line exactly as the plain report prints it, read back into its tree
    (`math_tree.line_box`); None: not in the printer's form, shown as it is."""
    return line_box(text)


def _system(t: dict) -> list[tuple]:
    """A transition's principles stated for the system (a `system` list of dicts with
    principle, why, steps, symbolic, numeric, result), before the body-by-body rows."""
    out: list[tuple] = []
    for s in t.get("system", ()) or ():
        out.append(("eqlabel", "Σ", s.get("principle", ""), None))
        if s.get("why"):
            out.append(("para", [("em", "because "), s["why"]]))
        out += [("para", [x]) for x in s.get("steps", ())]
        out.append(("equation", typeset(s["symbolic"]), s["symbolic"]))
        if s.get("numeric") and s["numeric"] != s["symbolic"]:
            out.append(("equation", typeset(s["numeric"]), s["numeric"]))
        out += [("para", [x]) for x in s.get("result", ())]
    if out:
        out.append(("para", [("em", "Body by body:")]))
    return out


def _flows(rep: Report, f) -> list[tuple]:
    out: list[tuple] = []
    for volume in dict.fromkeys(r["volume"] for r in rep.flows):
        out.append(("heading", 2, [f"Control volume {volume}: momentum fluxes (+ in, - out) "
                                   "and forces"]))
        rows = [[[r["what"]], [str(r["line"])], [f(r["rate"])],
                 [f"({f(r['vx'])}, {f(r['vy'])})" if r["rate"] is not None else "-"],
                 [f"({f(r['flux_x'])}, {f(r['flux_y'])})"], [f(r["moment"])]]
                for r in rep.flows if r["volume"] == volume]
        out.append(("table", [[""], ["line"], ["ṁ (", ("unit", "kg/s"), ")"],
                              ["v (", ("unit", "m/s"), ")"], ["ṁv or F (", ("unit", "N"), ")"],
                              ["r × (ṁv or F) (", ("unit", "N*m"), ")"]], rows, "lrrrrr"))
    return out


def _blocks(rep: Report, f) -> list[tuple]:
    out: list[tuple] = [("heading", 2, ["Solving, block by block"])]
    for b in rep.blocks:
        how = (f"linear, condition number {f(b['condition_number'])}"
               if b["method"] == "linear" else
               "integrated numerically from its inputs" if b["method"] == "integrated" else
               f"Newton, {b['iterations']} iterations, residual {fmt_tiny(b['residual'] or 0)}")
        names: list = []
        for u in b["unknowns"]:
            names += ([", "] if names else []) + [math(name_box(u))]
        lines = ", ".join(map(str, b["lines"]))
        out.append(("para", [("strong", f"Block {b['index']}: ")] + names +
                    [f" ({how}; lines {lines})"]))
        if "matrix" in b:
            headers = [[math(name_box(u))] for u in b["unknowns"]] + [["rhs"]]
            rows = [[[f(x)] for x in row] + [[f(rhs)]] for row, rhs in zip(b["matrix"], b["rhs"])]
            out.append(("table", headers, rows, "r" * len(headers)))
    return out


def diagram_items(d) -> list[tuple[int, str]]:
    """A diagram's `lines()` as (depth, text), depth from the indentation (two spaces a
    level); a first line that repeats the title is left out (the caption shows it)."""
    lines = [x for x in d.lines() if x.strip()]
    if lines and lines[0].strip() == str(d.title).strip():
        lines = lines[1:]
    indents = sorted({len(x) - len(x.lstrip(" ")) for x in lines})
    return [(indents.index(len(x) - len(x.lstrip(" "))), x.strip()) for x in lines]
