"""Plain text: deterministic, no colour, ASCII only, fixed number formatting.

This is what golden files hold and what a pipe receives: the same content as the
rich report, laid out with spaces so that locale and terminal width cannot change it.
"""
from __future__ import annotations

from ..numbers import fmt_num, fmt_tiny
from .abbrev import abbreviate
from .model import Report, diagram_lines, equation_text, part_of, rows_of


_FORMATS: dict = {}  # (indent, column widths) -> (line format, rule): small tables recur


def table(headers: list[str], rows: list[list[str]], indent: str = "  ") -> list[str]:
    """Columns padded to their widest cell; the last column is not padded."""
    n = len(headers)
    if n > 1 and all(len(r) == n for r in rows):
        # the usual case: every row as wide as the header
        return column_table(headers, list(zip(*rows)) if rows else [()] * n, indent)
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


def column_table(headers: list[str], cols: list, indent: str = "  ") -> list[str]:
    """`table(headers, rows)` of rows given as columns (each as long, one per header, two
    or more): each column measured once (max over it) and every line made by one
    format call over the columns; no row is made."""
    widths = tuple([max(len(h), max(map(len, c), default=0)) for h, c in zip(headers, cols)])
    got = _FORMATS.get((indent, widths))
    if got is None:
        if len(_FORMATS) > 256:
            _FORMATS.clear()
        got = _FORMATS[indent, widths] = (
            indent + "  ".join(f"{{:<{w}}}" for w in widths[:-1]) + "  {}",
            indent + "  ".join("-" * w for w in widths))
    fmt = got[0]
    out = [fmt.format(*headers).rstrip(), got[1]]
    if cols and cols[0]:
        out += [s.rstrip() for s in map(fmt.format, *cols)]
    return out


def formatter(sig: int):
    """`fmt_num(x, sig)` ("-" for None), each value formatted once: a big report repeats
    the same numbers (0, 1, a mass, a matrix's entries) thousands of times. Equal numbers
    print the same (0.0 and -0.0 both as 0, an int as the float it equals)."""
    cache: dict = {}

    def f(x) -> str:
        if x is None:
            return "-"
        s = cache.get(x)
        if s is None:
            s = cache[x] = fmt_num(x, sig)
        return s
    f.cache = cache  # for a loop that reads it inline (never holds None)
    f.matrices = {}  # `_matrix`'s texts of a kind of block, at this precision
    return f


def render(rep: Report, sig: int = 6, steps: bool = True, detail: str = "full") -> str:
    """`detail` full: every section; brief: the principles with their equations and
    numbers, the answers and the key checks (see `render_brief`)."""
    if steps and detail == "brief":
        return render_brief(rep, sig)
    return "\n".join(iter_parts(rep, sig, steps))


def render_parts(rep: Report, sig: int = 6, steps: bool = True) -> list[str]:
    """`render`'s full text as pieces (a line, or a run of lines) to join with
    newlines: a caller that frees the report (and a lazy one's solution) before joining
    holds the text once, not beside them."""
    return list(iter_parts(rep, sig, steps))


def until_failure(parts, failed: list):
    """The pieces of `parts` until one fails to be made; its exception goes to `failed`
    (a write's own errors, raised in the writer, are not caught here): the text before
    a bug is written, then the bug is reported as any other."""
    try:
        yield from parts
    except Exception as exc:
        failed.append(exc)


RUN_LINES = 4096  # lines of a long section joined into one piece


def _in_runs(lines: list):
    """`lines` as pieces of up to RUN_LINES lines joined (the same text once joined with
    newlines): a long table reaches the writer in bounded pieces, not as one copy."""
    if len(lines) <= RUN_LINES:
        yield "\n".join(lines)
        return
    for i in range(0, len(lines), RUN_LINES):
        yield "\n".join(lines[i:i + RUN_LINES])


def iter_parts(rep: Report, sig: int = 6, steps: bool = True, start=None, stop=None):
    """`render`'s full text as pieces to join with newlines, made as they are read: a
    caller that writes each piece as it comes (solve_cmd._write_text) never holds the
    whole text beside the report (~120 MB for 10^5 balls). Every piece is non-empty
    text or a line of its own (an empty piece is an empty line).

    `start`, `stop`: cuts in the transitions' section (`_transition_parts`), None for the
    text's beginning and its end: the pieces between the two only. The pieces of the
    ranges between consecutive cuts, joined with newlines, are the whole text (two
    processes make them: forked_text); each range is at least one piece."""
    f = formatter(sig)
    u = rep.units or {}
    if start is None:
        yield from _head(rep, f, u, steps)
    if not steps:
        yield from _ending(rep, sig)
        return
    yield from _transition_parts(rep, start, stop)
    if stop is not None:
        return
    for group, rows in rep.other_equations.items():
        yield ""
        yield group[0].upper() + group[1:]
        yield from _equation_texts(rows)
    yield ""
    yield "Solving, block by block"
    out: list[str] = []
    add = out.append
    shown = f.cache
    plain = getattr(rep.blocks, "texts", None)  # a lazy report's: tuples, no dicts
    for index, unknowns, method, cond, iterations, residual, lines, matrix, rhs in (
            plain() if plain is not None else
            ((b["index"], b["unknowns"], b["method"], b["condition_number"],
              b["iterations"], b["residual"], b["lines"], b.get("matrix"), b.get("rhs"))
             for b in rep.blocks)):
        how = (f"linear, condition number {shown[cond] if cond in shown else f(cond)}"
               if method == "linear" else
               "integrated numerically from its inputs" if method == "integrated" else
               f"Newton, {iterations} iterations, residual {fmt_tiny(residual or 0)}")
        # a block of thousands: its first and last unknowns and lines, and how many
        if len(unknowns) == 1 and len(lines) == 1:  # as `abbreviate` shows one name
            add(f"  block {index}: {unknowns[0]} ({how}; lines {lines[0]})")
        else:
            names, n = abbreviate(unknowns)
            lines, n_lines = abbreviate(lines)
            lines = f"{n_lines} lines: {lines}" if n_lines else f"lines {lines}"
            count = f"{n} unknowns; " if n else ""
            add(f"  block {index}: {names} ({count}{how}; {lines})")
        if matrix is not None:
            _matrix(unknowns, matrix, rhs, f, out)
        if len(out) >= RUN_LINES:  # a run of blocks' lines as one piece
            yield "\n".join(out)
            out.clear()
    if out:
        yield "\n".join(out)
    yield ""
    yield f"Solution ({u.get('name', 'SI')})"
    plain = getattr(rep.unknowns, "texts", None)  # a lazy report's: tuples, no dicts
    names: list = []  # the table's three columns, filled in one pass (no row made)
    texts: list = []
    units: list = []
    put_name, put_text, put_unit = names.append, texts.append, units.append
    for n, v, unit in (plain() if plain is not None else
                       ((x["name"], x.get("value", x["si_value"]),
                         x.get("shown_unit", x["unit"])) for x in rep.unknowns)):
        put_name(n)
        put_text(shown[v] if v in shown else f(v))
        put_unit(unit)
    lines = column_table(["unknown", "value", "unit"], [names, texts, units])
    names = texts = units = None  # not held while the lines are written
    yield from _in_runs(lines)
    lines = None
    out = []
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
    yield from out
    yield from _ending(rep, sig)


def _head(rep: Report, f, u: dict, steps: bool):
    """The title, then (with `steps`) the bodies, effects, knowns and control volumes."""
    out: list[str] = []
    title = rep.title or "(untitled problem)"
    out.append(f"== {rep.file}: {title}")
    if not steps:
        yield from out
        return
    if rep.bodies:
        out.append("")
        out.append("Bodies")
        yield from out
        out = []
        yield from _in_runs(table(
            ["body", "shape", f"mass ({u.get('mass', 'kg')})",
             f"I_G ({u.get('inertia', 'kg*m^2')})", "inertia formula"],
            [[b["name"], b["shape"], f(b.get("shown_mass", b["mass"])),
              "-" if b["particle"] else f(b.get("shown_inertia", b["inertia"])),
              b["formula"] + (" (mass = W/g)" if b["weight"] else "")]
             for b in rep.bodies]))
    out.append("")
    out.append("Effects and constraints")
    out.extend("  " + e for e in rep.effects)
    if rep.knowns:
        out.append("")
        out.append(f"Knowns ({u.get('name', 'SI')})")
    for k in rep.knowns:
        label = f' "{k["label"]}"' if k["label"] else ""
        items = _items(k, f) or "(nothing given)"
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
    yield from out


def _ending(rep: Report, sig: int):
    """The answers' lines, the sensitivities, and the final newline."""
    out = _answers(rep, sig)
    if rep.sensitivities:
        from .sensitivity import text_lines

        out.extend(text_lines(rep.sensitivities, sig, table))
    out.append("")  # the final newline
    yield from out


def _transition_parts(rep: Report, start, stop):
    """The transitions' section from cut `start` to cut `stop`. A cut `(i, r)` is the
    place before row `r` of transition `i`'s equations (`r` 0: before its heading and
    diagram), `(len(rep.transitions), 0)` the section's end; None is its beginning (as
    `start`) or its end (as `stop`). A range that begins inside a transition makes only
    its rows (`rows_of`): its statements and diagram are the range before's."""
    ts = rep.transitions
    i, r = start if start is not None else (0, 0)
    j, s = stop if stop is not None else (len(ts), 0)
    if r:  # the rest of a transition whose heading an earlier range made
        rows = rows_of(ts, i)
        yield from _equation_texts(part_of(rows, r, s if j == i else len(rows)))
        i += 1
    if start is None and stop is None:
        items = ts
    else:  # the transitions whose heading is in the range: i .. j (j only with rows of it)
        items = part_of(ts, i, j + 1 if s else j)
    for k, t in enumerate(items, i):
        out = [""]
        out.append(f"{t['kind'].capitalize()} {t['before']} -> {t['after']} (line {t['line']})")
        d = diagram_lines(rep, t, "  ")
        if d is not None and len(d) <= RUN_LINES:
            out.append("\n".join(d))
        elif d is not None:  # in runs (the same text joined), freed before the rows:
            yield from out  # 10^5 bodies' diagram is ~80 MB of lines and their join
            out = []
            yield from _in_runs(d)
        d = None
        for w in t["why"]:
            out.append(f"  why: {w}")
        out.extend(_system(t))
        yield from out
        out = []  # a system's long sums are not held while the rows are written
        rows = t["equations"]
        if k == j:  # the range ends inside this transition's rows
            rows = part_of(rows, 0, s)
        yield from _equation_texts(rows)  # one piece an equation, as made


def _matrix(unknowns: list, matrix: list, rhs: list, f, out: list) -> None:
    """A block's matrix as `table(unknowns + ["", "rhs"], rows, "      ")` lays it out:
    the cells formatted column by column through the number cache, each column's width
    measured once, every line from one format string (cached by the widths). A sequence
    of like blocks (a cradle's impacts) repeats one matrix and right side under other
    unknowns: their cells and widths, and at the same widths their rows, are made once
    per kind (kept by the formatter, whose precision they have); only the heading is
    made per block."""
    n = len(unknowns)
    key = got = None
    if n <= 8 and len(rhs) == len(matrix):  # a small block: its numbers are the key
        try:
            key = (n, tuple(map(tuple, matrix)), tuple(rhs))
            got = f.matrices.get(key)
        except TypeError:  # an unhashable cell: made as below, not kept
            key = None
    if got is None:
        shown = f.cache
        cols = [[shown[x] if x in shown else f(x) for x in col] for col in zip(*matrix)]
        last = [f(x) for x in rhs]
        if not matrix or len(cols) != n or len(last) != len(matrix) or \
                any(len(r) != n for r in matrix):  # empty or ragged: the general table
            rows = [[shown[x] if x in shown else f(x) for x in row] + ["|", f(r)]
                    for row, r in zip(matrix, rhs)]
            out.extend(table(unknowns + ["", "rhs"], rows, indent="      "))
            return
        got = (cols, last, [max(map(len, c), default=0) for c in cols],
               max(3, max(map(len, last))), {})
        if key is not None:
            if len(f.matrices) > 256:
                f.matrices.clear()
            f.matrices[key] = got
    cols, last, cells, wide, bodies = got
    widths = tuple([max(len(h), w) for h, w in zip(unknowns, cells)] + [1, wide])
    fmts = _FORMATS.get(("      ", widths))
    if fmts is None:
        if len(_FORMATS) > 256:
            _FORMATS.clear()
        fmts = _FORMATS["      ", widths] = (
            "      " + "  ".join(f"{{:<{w}}}" for w in widths[:-1]) + "  {}",
            "      " + "  ".join("-" * w for w in widths))
    fmt = fmts[0].format
    out.append(fmt(*unknowns, "", "rhs").rstrip())
    out.append(fmts[1])
    body = bodies.get(widths)
    if body is None:
        bar = ["|"] * len(last)
        body = [s.rstrip() for s in map(fmt, *cols, bar, last)]
        if len(bodies) < 64:
            bodies[widths] = body
    out += body


def _items(k: dict, f) -> str:
    """A state's givens, `name = value unit`, and its bounds, `name > value unit`."""
    units = k.get("units") or [""] * len(k["items"])
    return ", ".join(f"{n} = {f(v)} {u}".rstrip() if u != "hint" else f"{n} {f(v)} {un}".rstrip()
                     for (n, v, u), un in zip(k["items"], units))


def _answers(rep: Report, sig: int) -> list[str]:
    out = []
    for a in rep.answers:
        v = fmt_num(a["value"], sig) if a["value"] is not None else "-"
        way = f" ({a['direction']})" if a.get("direction") else ""
        out.append(f"  {a['name']} = {v} {a['unit']}".rstrip() + way)
    return out


# checks a brief derivation keeps: what the reader must see (energy, expectations, trouble)
KEY_CHECKS = ("kinetic energy", "expect", "friction", "flux signs")


def key_checks(rep: Report) -> list:
    return [c for c in rep.checks
            if c.status in ("warning", "error") or c.name.startswith(KEY_CHECKS)]


def render_brief(rep: Report, sig: int = 6, sensitivities: bool = True) -> str:
    """One screen: the givens, each principle with its equations (symbolic, then with
    numbers), the stated principles, the answers and the key checks. The constraint
    bookkeeping of each state, the matrices and the conditioning are in --steps full."""
    u = rep.units or {}
    f = lambda x: fmt_num(x, sig) if x is not None else "-"  # noqa: E731
    out = [f"== {rep.file}: {rep.title or '(untitled problem)'}"]
    if rep.knowns:
        out.append("")
        out.append(f"Given ({u.get('name', 'SI')})")
        for k in rep.knowns:
            items = _items(k, f)
            if items:
                out.append(f"  state {k['id']}: {items}")
    sections = [(f"{t['kind'].capitalize()} {t['before']} -> {t['after']} (line {t['line']})",
                 t["why"][:1], t["equations"], t) for t in rep.transitions]
    sections += [(g[0].upper() + g[1:], [], rows, None)
                 for g, rows in rep.other_equations.items() if not g.startswith("state ")]
    for title, why, rows, t in sections:
        rows = [r for r in rows if r.role in ("solved", "check")]
        if not rows and not why:
            continue
        out.append("")
        out.append(title)
        d = diagram_lines(rep, t, "  ") if t is not None else None
        if d is not None:  # the first step of a textbook solution
            out.extend(d)
        out.extend(f"  why: {w}" for w in why)
        out.extend(_system(t) if t is not None else [])
        for r in rows:
            out.extend(_equation(r))
    out.append("")
    out.append("Answers")
    out.extend(_answers(rep, sig))
    checks = key_checks(rep)
    if checks:
        out.append("")
        out.append("Checks")
        out.extend(f"  {c.status}: {c.name}: {c.detail}" for c in checks)
    if sensitivities and rep.sensitivities:
        from .sensitivity import text_lines

        out.extend(text_lines(rep.sensitivities, sig, table))
    return "\n".join(out) + "\n"


def _system(t: dict) -> list[str]:
    """The principles for the system, then (in the rows after it) body by body."""
    out = []
    for s in t.get("system", ()):
        out.append(f"  * {s['principle']}")
        out.append(f"      because {s['why']}")
        out.extend(f"      {x}" for x in s["steps"])
        out.append(f"      {s['symbolic']}")
        if s["numeric"] != s["symbolic"]:
            out.append(f"      {s['numeric']}")
        out.extend(f"      {x}" for x in s["result"])
    if out:
        out.append("  body by body:")
    return out


def _equation_texts(rows):
    """`_equation` of each row as one piece (its lines joined: the same text once
    joined); a lazy report's rows as text, never made."""
    texts = getattr(rows, "texts", None)
    if texts is not None:
        return texts()
    return (equation_text(r.index, r.principle, r.line, r.role, r.symbolic, r.numeric)
            for r in rows)


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
