"""Grades as tables: plain text and rich (the report side of `momentum grade`).

In: a `grading.GradeResult`. Out: a table per student, per-student and per-problem
summaries and the class statistics, laid out as plain text or rich tables.
"""
from __future__ import annotations

from ..grading import CLASSES, per_problem, per_student, statistics
from .text import table


def tables(result):
    """(title, headers, rows) of every table, for the plain and rich renderers."""
    out = []
    for s in result.students:
        rows = [[g.problem, g.quantity, g.key, g.answer or "-", g.verdict]
                for g in result.grades if g.student == s]
        out.append((f"Student {s}", ["problem", "quantity", "key", "answer", "verdict"], rows))
    out.append(("Students", ["student", "score"] + list(CLASSES),
                [[r["student"], f"{r['right']}/{r['total']}"] + [str(r[k]) for k in CLASSES]
                 for r in per_student(result)]))
    out.append(("Problems", ["problem", "quantity", "key", "right", "most common mistake"],
                [[r["problem"], r["quantity"], r["key"], f"{r['right']}/{r['students']}",
                  r["most_common_mistake"] or "-"] for r in per_problem(result)]))
    st = statistics(result)
    out.append(("Class", ["students", "answers", "mean score"] + list(CLASSES),
                [[str(st["students"]), str(st["answers"]), f"{100 * st['mean_score']:.0f} %"]
                 + [str(st[k]) for k in CLASSES]]))
    return out


def render_plain(result) -> str:

    out = []
    for title, headers, rows in tables(result):
        out += [title] + table(headers, rows) + [""]
    return "\n".join(out)


def render_rich(result) -> None:
    from rich.console import Console
    from rich.table import Table

    console = Console()
    colours = {"right": "green", "rounding": "yellow", "sign error": "red",
               "unit slip": "magenta", "wrong": "red", "missing": "dim"}
    for title, headers, rows in tables(result):
        t = Table(title=title, title_justify="left")
        for h in headers:
            t.add_column(h)
        for r in rows:
            t.add_row(*[f"[{colours[c]}]{c}[/]" if c in colours else c.replace("[", r"\[")
                        for c in r])
        console.print(t)
