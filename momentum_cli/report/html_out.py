"""HTML: the solution sheet as one self-contained page.

Stage: report. In: reports (the model), through the shared `document` outline. Out:
one HTML file with MathML equations (rendered by the browser itself), impulse
diagrams as inline SVG, inline CSS with print styles; no script, no font, nothing
fetched (its Content-Security-Policy forbids any request).
"""
from __future__ import annotations

from html import escape

from .document import diagram_items, outline
from .math_out import to_mathml, to_mathml_broken, unit_mathml

CSS = """
:root { color-scheme: light; --ink: #1d1f23; --muted: #5b6270; --rule: #d5d9e0;
        --accent: #1f5aa6; --soft: #f4f6f9; }
* { box-sizing: border-box; }
body { margin: 0; color: var(--ink); background: #fff;
       font: 16px/1.5 "Charter", "Bitstream Charter", "Georgia", "DejaVu Serif", serif; }
main { max-width: 58rem; margin: 0 auto; padding: 2rem 1.5rem 4rem; }
section.problem + section.problem { border-top: 2px solid var(--rule); margin-top: 3rem; }
h1 { font-size: 1.7rem; line-height: 1.25; margin: 1.2rem 0 0.3rem; }
h2 { font-size: 1.2rem; margin: 2rem 0 0.6rem; padding-bottom: 0.2rem;
     border-bottom: 1px solid var(--rule); color: var(--accent); }
h3 { font-size: 1.05rem; margin: 1.2rem 0 0.4rem; }
p { margin: 0.5rem 0; }
p.file { color: var(--muted); }
code { font: 0.88em/1.4 "DejaVu Sans Mono", "Menlo", "Consolas", monospace; }
ul { margin: 0.4rem 0 0.8rem; padding-left: 1.4rem; }
li { margin: 0.15rem 0; }
em.why { color: var(--muted); font-style: normal; font-weight: 600; }
.table-wrap { overflow-x: auto; margin: 0.5rem 0 1rem; }
table { border-collapse: collapse; font-size: 0.92rem; }
th, td { padding: 0.3rem 0.7rem; border-bottom: 1px solid var(--rule); vertical-align: top;
         text-align: left; }
th { background: var(--soft); font-weight: 600; white-space: nowrap; }
td.r, th.r { text-align: right; font-variant-numeric: tabular-nums; }
p.eqlabel { margin: 1rem 0 0.2rem; }
p.eqlabel .num { font-weight: 700; color: var(--accent); }
p.eqlabel .role { color: var(--muted); font-style: italic; }
div.eq { overflow-x: auto; padding: 0.15rem 0 0.15rem 3rem; text-indent: -1.5rem; }
div.eq.numeric { color: #30343b; }
div.eq math { font-size: 1.08em; }
div.eq math { margin: 0.2rem 0; }
pre.eq { margin: 0.2rem 0 0.2rem 1.5rem; }
figure.diagram { margin: 1rem 0 1.5rem; padding: 0.8rem; border: 1px solid var(--rule);
                 border-radius: 6px; background: #fff; }
figure.diagram figcaption { font-weight: 600; margin-bottom: 0.4rem; }
figure.diagram svg { display: block; max-width: 100%; height: auto; margin: 0.3rem auto; }
strong.status { color: #9a5b00; }
@media print {
  @page { margin: 16mm 14mm; }
  body { font-size: 10.5pt; }
  main { max-width: none; padding: 0; }
  h2 { break-after: avoid; color: #000; }
  h1, h2, h3, p.eqlabel { break-after: avoid; }
  div.eq, figure.diagram, tr { break-inside: avoid; }
  .table-wrap, div.eq { overflow: visible; }
  section.problem + section.problem { break-before: page; border-top: none; }
}
"""

CSP = "default-src 'none'; style-src 'unsafe-inline'; img-src data:"


def inline(pieces) -> str:
    out = []
    for p in pieces:
        if isinstance(p, str):
            out.append(escape(p))
        elif p[0] == "math":
            out.append(to_mathml(p[1]))
        elif p[0] == "unit":
            out.append(f'<math xmlns="http://www.w3.org/1998/Math/MathML">'
                       f"{unit_mathml(p[1])}</math>" if p[1] else "")
        elif p[0] == "code":
            out.append(f"<code>{escape(p[1])}</code>")
        elif p[0] == "strong":
            out.append(f"<strong>{escape(p[1])}</strong>")
        elif p[0] == "em":
            out.append(f'<em class="why">{escape(p[1])}</em>')
    return "".join(out)


def block(b, state: dict) -> list[str]:
    kind = b[0]
    if kind == "heading":
        n = min(b[1], 3)
        return [f"<h{n}>{inline(b[2])}</h{n}>"]
    if kind == "eqlabel":
        state["numeric"] = False
        role = f' <span class="role">{escape(b[3])}</span>' if b[3] else ""
        return [f'<p class="eqlabel"><span class="num">{escape(b[1])}</span> '
                f"{escape(b[2])}{role}</p>"]
    if kind == "para":
        cls = ' class="file"' if state.get("first_para", True) else ""
        state["first_para"] = False
        return [f"<p{cls}>{inline(b[1])}</p>"]
    if kind == "list":
        return ["<ul>"] + [f"<li>{inline(i)}</li>" for i in b[1]] + ["</ul>"]
    if kind == "table":
        headers, rows, aligns = b[1], b[2], b[3]
        cls = [' class="r"' if a == "r" else "" for a in aligns]
        out = ['<div class="table-wrap"><table>', "<thead><tr>" + "".join(
            f"<th{cls[i]}>{inline(h)}</th>" for i, h in enumerate(headers)) + "</tr></thead>",
            "<tbody>"]
        out += ["<tr>" + "".join(f"<td{cls[i]}>{inline(c)}</td>" for i, c in enumerate(r)) +
                "</tr>" for r in rows]
        return out + ["</tbody></table></div>"]
    if kind == "equation":
        box, plain = b[1], b[2]
        cls = "eq numeric" if state.get("numeric") else "eq"
        state["numeric"] = True  # the line after an equation's first is its numbers
        if box is None:
            return [f'<pre class="{cls}"><code>{escape(plain)}</code></pre>']
        return [f'<div class="{cls}" title="{escape(plain)}">' +
                "<wbr>".join(to_mathml_broken(box)) + "</div>"]
    if kind == "diagram":
        d = b[1]
        svg = getattr(d, "svg", None)
        drawing = svg().strip() if svg is not None else ""
        # a caption, unless the drawing already carries the title
        caption = "" if escape(d.title) in drawing else f"<figcaption>{escape(d.title)}</figcaption>"
        out = ['<figure class="diagram">'] + ([caption] if caption else [])
        if drawing:
            out.append(drawing)
        out += _nested(diagram_items(d))
        return out + ["</figure>"]
    if kind == "rule":
        return ["<hr>"]
    raise ValueError(f"unknown block {kind!r}")


def _nested(items) -> list[str]:
    """(depth, text) items as nested lists."""
    out: list[str] = []
    depth = -1
    for level, text in items:
        level = min(level, depth + 1)
        if level > depth:
            out.append("<ul>")
            depth = level
        else:
            out.append("</li>")
            while depth > level:
                out.append("</ul></li>")
                depth -= 1
        out.append(f"<li>{escape(text)}")
    if depth >= 0:
        out.append("</li>")
    while depth > 0:
        out.append("</ul></li>")
        depth -= 1
    return out + (["</ul>"] if items else [])


def render(reports, sig: int = 6, detail: str = "full") -> str:
    """One HTML page for one or more reports (a section each)."""
    title = " · ".join(r.title or r.file for r in reports) or "momentum"
    out = ["<!DOCTYPE html>", '<html lang="en">', "<head>", '<meta charset="utf-8">',
           f'<meta http-equiv="Content-Security-Policy" content="{CSP}">',
           '<meta name="viewport" content="width=device-width, initial-scale=1">',
           '<meta name="generator" content="momentum">',
           f"<title>{escape(title)}</title>", f"<style>{CSS}</style>", "</head>", "<body>",
           "<main>"]
    for rep in reports:
        out.append('<section class="problem">')
        state: dict = {}
        for b in outline(rep, sig, detail):
            out += block(b, state)
        out.append("</section>")
    out += ["</main>", "</body>", "</html>"]
    return "\n".join(out) + "\n"
