"""LaTeX: the solution sheet as a standalone document for `pdflatex` (or `tectonic`).

Stage: report. In: reports (the model), through the shared `document` outline. Out:
one `article` document using only amsmath, amssymb, geometry, array, longtable and
booktabs (texlive-latex-base and -recommended). Equations are set as display-style
math in a ragged paragraph, so that a long numeric line breaks at its signs instead of
running off the page. Impulse diagrams are given as lists (their `lines()`).
"""
from __future__ import annotations

from .document import diagram_items, outline
from .math_out import latex_text, to_latex, unit_latex

PREAMBLE = r"""\documentclass[11pt]{article}
\usepackage[utf8]{inputenc}
\usepackage{amsmath,amssymb}
\usepackage[a4paper,margin=2cm]{geometry}
\usepackage{array,longtable,booktabs}
\setlength{\parindent}{0pt}
\setlength{\parskip}{0.5ex plus 0.2ex}
\setlength{\LTleft}{0pt}
\setlength{\LTright}{0pt plus 1fill}
\newcommand{\eqline}[1]{\par\begingroup\raggedright\leftskip=2em\relax
  \hangindent=2em\relax$\displaystyle #1$\par\endgroup}
\sloppy
"""

MAX_MATRIX = 10  # wider block matrices are left out (they would not fit the page)


def inline(pieces) -> str:
    out = []
    for p in pieces:
        if isinstance(p, str):
            out.append(latex_text(p))
        elif p[0] == "math":
            out.append(f"${to_latex(p[1])}$")
        elif p[0] == "unit":
            out.append(f"${unit_latex(p[1])}$" if p[1] else "")
        elif p[0] == "code":
            out.append(f"\\texttt{{{latex_text(p[1])}}}")
        elif p[0] == "strong":
            out.append(f"\\textbf{{{latex_text(p[1])}}}")
        elif p[0] == "em":
            out.append(f"\\emph{{{latex_text(p[1])}}}")
    return "".join(out)


def _plain_len(pieces) -> int:
    n = 0
    for p in pieces:
        if isinstance(p, str):
            n += len(p)
        elif p[0] == "math":
            n += 8
        else:
            n += len(str(p[1]))
    return n


def _table(headers, rows, aligns) -> list[str]:
    if len(headers) > MAX_MATRIX:
        return [f"\\emph{{({len(rows)} rows, {len(headers)} columns: too wide for the page; "
                "see the plain or JSON output)}", ""]
    widths = [max([_plain_len(h)] + [_plain_len(r[i]) for r in rows])
              for i, h in enumerate(headers)]
    long_cols = [i for i, w in enumerate(widths) if w > 28]
    # about 90 characters fill a line: the short columns take what they need
    used = sum((w + 3) / 90 for i, w in enumerate(widths) if i not in long_cols)
    share = max(0.15, (0.94 - used) / max(1, len(long_cols)))
    spec = "".join(f">{{\\raggedright\\arraybackslash}}p{{{share:.2f}\\linewidth}}"
                   if i in long_cols else aligns[i] for i in range(len(headers)))
    small = len(headers) > 6
    out = (["{\\footnotesize"] if small else []) + [f"\\begin{{longtable}}{{{spec}}}",
                                                      "\\toprule"]
    out.append(" & ".join(inline(h) for h in headers) + " \\\\")
    out += ["\\midrule", "\\endhead"]
    out += [" & ".join(inline(c) for c in r) + " \\\\" for r in rows]
    out += ["\\bottomrule", "\\end{longtable}"] + (["}"] if small else []) + [""]
    return out


def block(b) -> list[str]:
    kind = b[0]
    if kind == "heading":
        cmd = {1: "section", 2: "subsection"}.get(b[1], "subsubsection")
        return [f"\\{cmd}*{{{inline(b[2])}}}", ""]
    if kind == "para":
        return [inline(b[1]), ""]
    if kind == "eqlabel":
        role = f" \\emph{{{latex_text(b[3])}}}" if b[3] else ""
        return [f"\\smallskip\\textbf{{{latex_text(b[1])}}} {latex_text(b[2])}{role}", ""]
    if kind == "list":
        return ["\\begin{itemize}"] + [f"  \\item {inline(i)}" for i in b[1]] + \
            ["\\end{itemize}", ""]
    if kind == "table":
        return _table(b[1], b[2], b[3])
    if kind == "equation":
        box, plain = b[1], b[2]
        if box is None:
            return [f"\\eqline{{\\texttt{{{latex_text(plain)}}}}}", ""]
        return [f"\\eqline{{{to_latex(box)}}}", ""]
    if kind == "diagram":
        d = b[1]
        out = [f"\\subsubsection*{{{latex_text(d.title)}}}", ""]
        depth = -1
        for level, line in diagram_items(d):
            level = min(level, depth + 1, 3)  # itemize nests four deep
            while depth < level:
                out.append("\\begin{itemize}")
                depth += 1
            while depth > level:
                out.append("\\end{itemize}")
                depth -= 1
            out.append(f"  \\item {latex_text(line)}")
        out += ["\\end{itemize}"] * (depth + 1)
        return out + [""]
    if kind == "rule":
        return ["\\bigskip\\hrule\\bigskip", ""]
    raise ValueError(f"unknown block {kind!r}")


def render(reports, sig: int = 6, detail: str = "full") -> str:
    """One LaTeX document for one or more reports (a new page for each after the first)."""
    lines = [PREAMBLE, "\\begin{document}", ""]
    for i, rep in enumerate(reports):
        if i:
            lines += ["\\clearpage", ""]
        for b in outline(rep, sig, detail):
            lines += block(b)
    lines += ["\\end{document}"]
    return "\n".join(lines) + "\n"
