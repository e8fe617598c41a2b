"""Markdown: the solution sheet for GitHub, Jupyter and lecture notes.

Stage: report. In: reports (the model), through the shared `document` outline. Out:
one Markdown text with headings, pipe tables and `$…$` / `$$…$$` math (LaTeX that
GitHub's and Jupyter's MathJax render); impulse diagrams as a list and inline SVG.
"""
from __future__ import annotations

import re

from .document import diagram_items, outline
from .math_out import to_latex, unit_latex

_SPECIAL = re.compile(r"([\\`*_\[\]<$|#~])")


def text(s: str) -> str:
    """Plain text with every character Markdown (or its math) would take as syntax
    escaped."""
    return _SPECIAL.sub(r"\\\1", str(s))


def inline(pieces) -> str:
    out = []
    for p in pieces:
        if isinstance(p, str):
            out.append(text(p))
        elif p[0] == "math":
            out.append(f"${to_latex(p[1])}$")
        elif p[0] == "unit":
            out.append(f"${unit_latex(p[1])}$" if p[1] else "")
        elif p[0] == "code":
            out.append(f"`{p[1]}`" if "`" not in p[1] else text(p[1]))
        elif p[0] == "strong":
            out.append(f"**{text(p[1].strip())}**" + (" " if p[1].endswith(" ") else "")
                       if p[1].strip() else "")
        elif p[0] == "em":
            out.append(f"*{text(p[1]).strip()}*" + (" " if p[1].endswith(" ") else ""))
    return "".join(out)


def _cell(pieces) -> str:
    return inline(pieces).replace("\n", " ") or " "


def block(b) -> list[str]:
    kind = b[0]
    if kind == "heading":
        return ["#" * b[1] + " " + inline(b[2]), ""]
    if kind == "para":
        return [inline(b[1]), ""]
    if kind == "eqlabel":
        role = f" *{text(b[3])}*" if b[3] else ""
        return [f"**{text(b[1])}** {text(b[2])}{role}", ""]
    if kind == "list":
        return [f"- {inline(item)}" for item in b[1]] + [""]
    if kind == "table":
        headers, rows, aligns = b[1], b[2], b[3]
        out = ["| " + " | ".join(_cell(h) for h in headers) + " |",
               "|" + "|".join(" ---: " if a == "r" else " --- " for a in aligns) + "|"]
        out += ["| " + " | ".join(_cell(c) for c in row) + " |" for row in rows]
        return out + [""]
    if kind == "equation":
        box, plain = b[1], b[2]
        if box is None:
            return ["```", plain, "```", ""]
        return ["$$", to_latex(box), "$$", ""]
    if kind == "diagram":
        d = b[1]
        out = [f"**{text(d.title)}**", ""]
        out += [f"{'  ' * depth}- {text(line)}" for depth, line in diagram_items(d)] + [""]
        svg = getattr(d, "svg", None)
        if svg is not None:
            out += ['<div class="impulse-diagram">', "", svg().strip(), "", "</div>", ""]
        return out
    if kind == "rule":
        return ["---", ""]
    raise ValueError(f"unknown block {kind!r}")


def render(reports, sig: int = 6, detail: str = "full") -> str:
    """One Markdown document for one or more reports (a rule between them)."""
    lines: list[str] = []
    for i, rep in enumerate(reports):
        if i:
            lines += ["---", ""]
        for b in outline(rep, sig, detail):
            lines += block(b)
    while lines and lines[-1] == "":
        lines.pop()
    return "\n".join(lines) + "\n"
