"""Math for the document formats: a box tree (`math_tree`) written as LaTeX or MathML.

Stage: report. In: boxes from the report model (equations), names and units as the
model holds them. Out: LaTeX source (Markdown's `$…$` and the LaTeX document) and
MathML elements (the HTML page); both from the same structure, so they agree.
"""
from __future__ import annotations

import re
from html import escape

from .math_tree import GREEK_CHAR, name_box

_LATEX_GREEK = {c: "\\" + n for n, c in GREEK_CHAR.items()}
_LATEX_OPS = {"−": "-", "×": "\\times", "·": "\\cdot", "→": "\\to", "∫": "\\int", "=": "=",
              "+": "+", ",": ",", "°": "^{\\circ}"}
_LATEX_FUNCS = {"sin", "cos", "tan", "arcsin", "arccos", "arctan", "exp", "ln"}

# text that pdflatex cannot take as it is (its default fonts are 7-bit): commands
_TEXT_CHARS = {
    "\\": "$\\backslash$", "{": "\\{", "}": "\\}", "$": "\\$", "&": "\\&", "#": "\\#",
    "_": "\\_", "%": "\\%", "~": "$\\sim$", "^": "\\^{}",
    "<": "$<$", ">": "$>$", "|": "$|$",
    "→": "$\\to$", "←": "$\\leftarrow$", "×": "$\\times$", "·": "$\\cdot$",
    "°": "$^{\\circ}$", "±": "$\\pm$", "−": "-", "≤": "$\\le$", "≥": "$\\ge$",
    "≈": "$\\approx$", "²": "$^2$", "³": "$^3$", "µ": "$\\mu$", "′": "$'$", "″": "$''$",
    "‘": "`", "’": "'", "“": "``", "”": "''", "–": "--", "—": "---", "…": "\\ldots{}",
    "•": "$\\bullet$", "√": "$\\surd$", "∞": "$\\infty$", "Δ": "$\\Delta$",
    "ṁ": "$\\dot{m}$", "\u00a0": "~",
}


def latex_text(s: str) -> str:
    """Plain text for a LaTeX document: special characters escaped, symbols and Greek
    letters as commands (math mode: the default OT1 fonts lack them, and a TS1 font
    would be made as a bitmap at compile time), any other non-ASCII character by its
    code point."""
    out = []
    for ch in str(s).replace("->", "→"):
        if ch in _TEXT_CHARS:
            out.append(_TEXT_CHARS[ch])
        elif ch in _LATEX_GREEK:
            out.append(f"${_LATEX_GREEK[ch]}$")
        elif ord(ch) < 128:
            out.append(ch)
        else:
            out.append(f"[U+{ord(ch):04X}]")
    return "".join(out)


# ---- LaTeX ----------------------------------------------------------------------------
def to_latex(box: tuple) -> str:
    """A box tree as LaTeX math (amsmath's \\text; no other package)."""
    kind = box[0]
    if kind == "mi":
        s = box[1]
        if s in _LATEX_GREEK:
            return _LATEX_GREEK[s]
        return s if len(s) == 1 else f"\\mathrm{{{s}}}"
    if kind == "mn":
        return box[1].replace("−", "-")
    if kind == "mo":
        return _LATEX_OPS.get(box[1], box[1].replace("′", "'"))
    if kind == "mtext":
        return f"\\text{{{latex_text(box[1])}}}"
    if kind == "fn":
        return f"\\{box[1]}" if box[1] in _LATEX_FUNCS else f"\\operatorname{{{box[1]}}}"
    if kind == "row":
        return "".join(_spaced(to_latex(b)) for b in box[1]).strip()
    if kind == "sub":
        return f"{_base(box[1])}_{{{to_latex(box[2])}}}"
    if kind == "sup":
        return f"{_base(box[1])}^{{{to_latex(box[2])}}}"
    if kind == "subsup":
        return f"{_base(box[1])}_{{{to_latex(box[2])}}}^{{{to_latex(box[3])}}}"
    if kind == "frac":
        return f"\\frac{{{to_latex(box[1])}}}{{{to_latex(box[2])}}}"
    if kind == "sqrt":
        return f"\\sqrt{{{to_latex(box[1])}}}"
    if kind == "paren":
        inner = to_latex(box[1])
        if _tall(box[1]):
            return f"\\left({inner}\\right)"
        return f"({inner})"
    if kind == "abs":
        return f"\\left\\lvert {to_latex(box[1])}\\right\\rvert "
    if kind == "space":
        return "\\,"
    if kind == "unit":
        return unit_latex(box[1])
    raise ValueError(f"unknown box {kind!r}")


def _spaced(s: str) -> str:
    """A space after a command word, so that `\\omega` and `x` do not run together."""
    return s + " " if re.search(r"\\[A-Za-z]+$", s) else s


def _base(b: tuple) -> str:
    s = to_latex(b)
    return f"{{{s}}}" if b[0] in ("sub", "sup", "subsup", "row") else s


def _tall(b: tuple) -> bool:
    """A fraction or root inside: parentheses that grow with it (unbreakable, so only
    then)."""
    if b[0] in ("frac", "sqrt"):
        return True
    return any(_tall(x) for x in b[1:] if isinstance(x, tuple)) or \
        (b[0] == "row" and any(_tall(x) for x in b[1]))


# ---- MathML ---------------------------------------------------------------------------
def to_mathml(box: tuple, display: bool = False) -> str:
    """A box tree as one `<math>` element (MathML Core: what browsers render)."""
    # display style, but laid out inline: a block <math> is centred by browsers
    attr = ' displaystyle="true"' if display else ""
    return f'<math xmlns="http://www.w3.org/1998/Math/MathML"{attr}>{_ml(box)}</math>'


def to_mathml_broken(box: tuple) -> list[str]:
    """An equation as several `<math>` elements, split before its top-level =, + and −
    signs: the page can then wrap a long equation like text (a browser never breaks a
    line inside one `<math>`)."""
    items: list[tuple] = []
    for part in (box[1] if box[0] == "row" else (box,)):
        items += list(part[1]) if part[0] == "row" and _is_sum(part) else [part]
    chunks: list[list[str]] = []
    for b in items:
        if b[0] == "mo" and b[1] in ("=", "+", "−") and chunks and chunks[-1]:
            chunks.append([f'<mo form="infix">{escape(b[1])}</mo>'])
            continue
        if not chunks:
            chunks.append([])
        chunks[-1].append(_ml(b))
    return [f'<math xmlns="http://www.w3.org/1998/Math/MathML" displaystyle="true">'
            f"<mrow>{''.join(c)}</mrow></math>" for c in chunks]


def _is_sum(b: tuple) -> bool:
    """A row of terms joined by + and − (not a product, whose row has no such sign)."""
    return any(x[0] == "mo" and x[1] in ("+", "−") for x in b[1][1:])


def _ml(box: tuple) -> str:
    kind = box[0]
    if kind == "mi":
        s = box[1]
        variant = ' mathvariant="normal"' if len(s) > 1 else ""
        return f"<mi{variant}>{escape(s)}</mi>"
    if kind == "mn":
        return f"<mn>{escape(box[1])}</mn>"
    if kind == "mo":
        return f"<mo>{escape(box[1])}</mo>"
    if kind == "mtext":
        return f"<mtext>{escape(box[1])}</mtext>"
    if kind == "fn":
        return f'<mi mathvariant="normal">{escape(box[1])}</mi><mo>&#x2061;</mo>'
    if kind == "row":
        return f"<mrow>{''.join(_ml(b) for b in box[1])}</mrow>"
    if kind == "sub":
        return f"<msub>{_ml(box[1])}{_ml(box[2])}</msub>"
    if kind == "sup":
        return f"<msup>{_ml(box[1])}{_ml(box[2])}</msup>"
    if kind == "subsup":
        return f"<msubsup>{_ml(box[1])}{_ml(box[2])}{_ml(box[3])}</msubsup>"
    if kind == "frac":
        return f"<mfrac>{_ml(box[1])}{_ml(box[2])}</mfrac>"
    if kind == "sqrt":
        return f"<msqrt>{_ml(box[1])}</msqrt>"
    if kind == "paren":
        if _tall(box[1]):
            return f"<mrow><mo>(</mo>{_ml(box[1])}<mo>)</mo></mrow>"
        # not stretched around sub- and superscripts (as LaTeX's plain parentheses)
        return (f'<mrow><mo stretchy="false">(</mo>{_ml(box[1])}'
                f'<mo stretchy="false">)</mo></mrow>')
    if kind == "abs":
        return f"<mrow><mo>|</mo>{_ml(box[1])}<mo>|</mo></mrow>"
    if kind == "space":
        return '<mspace width="0.2em"></mspace>'
    if kind == "unit":
        return unit_mathml(box[1])
    raise ValueError(f"unknown box {kind!r}")


# ---- units ----------------------------------------------------------------------------
_UNIT_TOKEN = re.compile(r"([A-Za-zµΩ°]+)(?:\^(-?\d+))?|([*/·])|(\S)")


def unit_box(unit: str) -> tuple | None:
    """A unit label (`kg*m^2`, `N*s`, `m/s`) as upright symbols with a thin dot; None
    for no unit."""
    unit = (unit or "").strip()
    if not unit:
        return None
    items: list[tuple] = []
    for m in _UNIT_TOKEN.finditer(unit):
        word, exp, op, other = m.groups()
        if word:
            b = ("mi", word)
            items.append(("sup", b, ("mn", exp.replace("-", "−"))) if exp else b)
        elif op:
            items.append(("mo", "/" if op == "/" else "·"))
        else:
            items.append(("mtext", other))
    return items[0] if len(items) == 1 else ("row", tuple(items))


def unit_latex(unit: str) -> str:
    """A unit as LaTeX math: upright (\\mathrm) letters."""
    b = unit_box(unit)
    if b is None:
        return ""
    return _unit_tex(b)


def _unit_tex(b: tuple) -> str:
    if b[0] == "mi":
        word = b[1]
        for ch, tex in (("µ", "\\mu "), ("Ω", "\\Omega "), ("°", "^{\\circ}")):
            word = word.replace(ch, f"}}{tex}\\mathrm{{")
        return f"\\mathrm{{{word}}}".replace("\\mathrm{}", "")
    if b[0] == "sup":
        return f"{_unit_tex(b[1])}^{{{b[2][1].replace('−', '-')}}}"
    if b[0] == "mo":
        return "/" if b[1] == "/" else "\\cdot "
    if b[0] == "row":
        return "".join(_unit_tex(x) for x in b[1])
    return f"\\text{{{latex_text(b[1])}}}"


def unit_mathml(unit: str) -> str:
    """A unit as MathML content (no `<math>` wrapper): upright letters."""
    b = unit_box(unit)
    return "" if b is None else _unit_ml(b)


def _unit_ml(b: tuple) -> str:
    if b[0] == "mi":
        return f'<mi mathvariant="normal">{escape(b[1])}</mi>'
    if b[0] == "sup":
        return f"<msup>{_unit_ml(b[1])}{_ml(b[2])}</msup>"
    if b[0] == "row":
        return f"<mrow>{''.join(_unit_ml(x) for x in b[1])}</mrow>"
    return _ml(b)


# ---- names and quantities -------------------------------------------------------------
def name_latex(name: str) -> str:
    """A quantity's name (`A.vx@2`) as LaTeX math."""
    return to_latex(name_box(name))


def name_mathml(name: str) -> str:
    """A quantity's name as one inline `<math>` element."""
    return to_mathml(name_box(name))
