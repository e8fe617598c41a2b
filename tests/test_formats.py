"""The document formats: Markdown, LaTeX and HTML from the one report model, and --output.

Typesetting is checked on expression trees built here (their LaTeX written out by hand),
every example renders in all three formats with well-formed math, an impulse diagram
(a stand-in object with the diagram interface) reaches every format, and --output
writes whole files and never overwrites one without --force.
"""
from __future__ import annotations

import json
import re
import xml.etree.ElementTree as ET
from html.parser import HTMLParser
from types import SimpleNamespace

import pytest
from conftest import EXAMPLES
from typer.testing import CliRunner

from momentum_cli.cli import app
from momentum_cli.expr import Add, Const, Fn, Known, Mul, Pow, Var
from momentum_cli.report import html_out, latex_out, markdown_out
from momentum_cli.report.math_out import name_latex, to_latex, to_mathml, unit_latex
from momentum_cli.report.math_tree import equation_box, expr_box
from momentum_cli.run import read_source, solve_source

PROBLEMS = sorted(EXAMPLES.glob("*.mom"))
GOOD = EXAMPLES / "seed_plastic_collision.mom"
GOOD2 = EXAMPLES / "seed_disk_wall.mom"
runner = CliRunner()
MATHML = re.compile(r"<math\b.*?</math>", re.S)


def cli(args):
    return runner.invoke(app, [str(a) for a in args], prog_name="momentum")


def tex(e, numeric=False) -> str:
    return to_latex(expr_box(e, numeric))


def well_formed_mathml(fragment: str) -> ET.Element:
    root = ET.fromstring(fragment)
    assert root.tag == "{http://www.w3.org/1998/Math/MathML}math"
    assert "".join(root.itertext()).strip(), fragment
    return root


# ---- typesetting from the expression tree ---------------------------------------------
@pytest.mark.parametrize("name, want", [
    ("A.vx@2", "v_{A,x}^{(2)}"),
    ("rod.vy@1", r"v_{\mathrm{rod},y}^{(1)}"),
    ("rod.omega@3", r"\omega_{\mathrm{rod}}^{(3)}"),
    ("wheel.angle@1", r"\theta_{\mathrm{wheel}}^{(1)}"),
    ("m_A", "m_{A}"),
    ("I_rod", r"I_{\mathrm{rod}}"),
    ("J_n[A-B]@1->2", r"J_{n,\text{A-B}}^{(1\to 2)}"),
    ("e[A-B]", r"e_{\text{A-B}}"),
    ("Fy[hub]", r"F_{\mathrm{hub},y}"),
    ("T_lost@1->2", r"T_{\mathrm{lost}}^{(1\to 2)}"),
    ("mu", r"\mu"),
    ("x*D(x)", r"\text{x*D(x)}"),  # not a name: kept as written
])
def test_names_are_typeset_with_subscripts_states_and_greek(name, want):
    assert name_latex(name) == want


def test_products_sums_and_signs():
    # m_A (v_A^(2) - v_A^(1)) = -J
    lhs = Mul((Known("m_A", 2.0), Add((Var("A.vx@2"), Mul((Const(-1.0), Var("A.vx@1")))))))
    rhs = Mul((Const(-1.0), Var("J_n[A-B]@1->2")))
    assert to_latex(equation_box(lhs, rhs)) == \
        r"m_{A}(v_{A,x}^{(2)}-v_{A,x}^{(1)})=-J_{n,\text{A-B}}^{(1\to 2)}"
    # with numbers: the known by its value, a dot before a number after a number
    assert to_latex(equation_box(lhs, rhs, numeric=True)) == \
        r"2(v_{A,x}^{(2)}-v_{A,x}^{(1)})=-J_{n,\text{A-B}}^{(1\to 2)}"
    assert tex(Mul((Const(2.0), Known("k", 3.0))), numeric=True) == r"2\cdot 3"
    assert tex(Mul((Known("k", 0.0), Add((Known("a", 3.0), Const(-1.0))))), numeric=True) \
        == r"0\cdot (3-1)"


def test_fractions_roots_powers_and_functions():
    x, m = Var("x"), Known("m_rod", 3.0)
    assert tex(Mul((x, Pow(m, -1.0)))) == r"\frac{x}{m_{\mathrm{rod}}}"
    assert tex(Pow(Add((x, Const(1.0))), -1.0)) == r"\frac{1}{x+1}"
    assert tex(Pow(Add((x, m)), 0.5)) == r"\sqrt{x+m_{\mathrm{rod}}}"
    assert tex(Mul((x, x))) == "x^{2}"
    assert tex(Pow(Var("rod.omega@2"), 2.0)) == r"(\omega_{\mathrm{rod}}^{(2)})^{2}"
    assert tex(Fn("sin", Var("rod.angle@1"))) == r"\sin (\theta_{\mathrm{rod}}^{(1)})"
    assert tex(Const(1.5e-7)) == r"1.5\times 10^{-7}"
    assert tex(Const(-2.5)) == "-2.5"


def test_mathml_is_well_formed_and_uses_the_letters():
    e = equation_box(Mul((Known("I_G", 2.0), Var("rod.omega@2"))),
                     Mul((Var("x"), Pow(Known("m_rod", 3.0), -1.0))))
    root = well_formed_mathml(to_mathml(e, display=True))
    text = "".join(root.itertext())
    assert "ω" in text and "rod" in text
    ns = "{http://www.w3.org/1998/Math/MathML}"
    assert root.find(f".//{ns}mfrac") is not None
    assert root.find(f".//{ns}msubsup") is not None


def test_units_are_upright_with_a_dot_for_products():
    assert unit_latex("kg*m^2") == r"\mathrm{kg}\cdot \mathrm{m}^{2}"
    assert unit_latex("m/s") == r"\mathrm{m}/\mathrm{s}"
    assert unit_latex("") == ""


# ---- every example, every format ------------------------------------------------------
def _report(path):
    res = solve_source(read_source(str(path)))
    return res.report


@pytest.mark.parametrize("problem", PROBLEMS, ids=lambda p: p.stem)
def test_every_example_renders_in_every_document_format(problem):
    rep = _report(problem)
    if rep is None:
        pytest.skip("this example is meant to fail (its errors are tested elsewhere)")
    md = markdown_out.render([rep])
    assert md.startswith("# ") and "## Answers" in md
    assert md.count("$$") % 2 == 0
    for m in re.findall(r"\$\$\n(.*?)\n\$\$", md, re.S):
        assert m.count("{") == m.count("}"), m
    latex = latex_out.render([rep])
    assert latex.startswith("\\documentclass") and latex.rstrip().endswith("\\end{document}")
    body = re.sub(r"\\[{}]", "", latex)
    assert body.count("{") == body.count("}")
    page = html_out.render([rep])
    fragments = MATHML.findall(page)
    assert fragments, "no MathML in the page"
    for frag in fragments:
        well_formed_mathml(frag)
    _balanced_html(page)
    assert "<script" not in page
    assert not re.search(r"""(src|href)\s*=\s*["'](https?:|//)""", page)  # nothing fetched


class _Tags(HTMLParser):
    VOID = {"meta", "br", "hr", "wbr", "img", "link", "input", "mspace"}

    def __init__(self):
        super().__init__()
        self.stack: list[str] = []

    def handle_starttag(self, tag, attrs):
        if tag not in self.VOID:
            self.stack.append(tag)

    def handle_endtag(self, tag):
        if tag in self.VOID:
            return
        assert self.stack and self.stack[-1] == tag, f"</{tag}> closes <{self.stack[-1:]}>"
        self.stack.pop()


def _balanced_html(page: str) -> None:
    p = _Tags()
    p.feed(page)
    p.close()
    assert p.stack == [], p.stack


# ---- impulse diagrams (the `diagram` helper's objects: title, lines(), svg()) ----------
class FakeDiagram:
    title = "Impulse diagram, impact 1 -> 2"
    kind, key = "impact", "1->2"  # the transition it belongs to

    def lines(self):
        return [self.title, "  A:", "    J_n = 3.6 N*s at the contact A-B, along -x",
                "  dropped: weight of A: finite, not impulsive"]

    def svg(self):
        return ('<svg xmlns="http://www.w3.org/2000/svg" width="160" height="80" '
                'viewBox="0 0 160 80"><circle cx="40" cy="40" r="20" fill="#ddd" '
                'stroke="#222"/><line x1="60" y1="40" x2="140" y2="40" stroke="#c00" '
                'stroke-width="3"/><text x="100" y="30">J_n</text></svg>')


def with_diagram(rep):
    """The report with one stand-in diagram (the model gets `diagrams` from `diagram`)."""
    fields = {f: getattr(rep, f) for f in type(rep)._fields}
    fields["diagrams"] = [FakeDiagram()]
    return SimpleNamespace(**fields)


def test_an_impulse_diagram_reaches_every_format():
    rep = with_diagram(_report(GOOD))
    md = markdown_out.render([rep])
    assert "**Impulse diagram, impact 1 -> 2**" in md and "<svg" in md
    assert "\n- A:\n  - J\\_n = 3.6 N\\*s at the contact A-B, along -x\n- dropped: " in md
    assert md.count("Impulse diagram, impact 1 -> 2") == 1  # the caption, not the list too
    latex = latex_out.render([rep])
    assert "\\subsubsection*{Impulse diagram, impact 1 $\\to$ 2}" in latex and "<svg" not in latex
    assert "\\item A:\n\\begin{itemize}\n  \\item J\\_n = 3.6 N*s" in latex
    assert latex.count("\\begin{itemize}") == latex.count("\\end{itemize}")
    page = html_out.render([rep])
    assert page.count("<svg") == 1 and "<figcaption>Impulse diagram" in page
    assert "<li>A:<ul><li>J_n = 3.6 N*s" in page.replace("\n", "")
    _balanced_html(page)
    # it opens its impact's section, before the equations: a textbook's first step
    assert page.index("<h2>Impact") < page.index("<svg") < page.index('class="eqlabel"')


def test_a_diagram_of_no_transition_comes_before_them():
    rep = with_diagram(_report(GOOD))
    rep.diagrams[0].kind = None
    md = markdown_out.render([rep])
    assert md.index("## Impulse diagrams") < md.index("**Impulse diagram,") < md.index("## Impact")


# ---- the command line: --format and --output -------------------------------------------
def test_format_markdown_on_standard_output():
    res = cli(["solve", "--format", "markdown", GOOD])
    assert res.exit_code == 0, res.output
    assert res.stdout.startswith("# Perfectly plastic collision of two particles\n")


def test_output_writes_the_document_and_never_overwrites_without_force(tmp_path):
    out = tmp_path / "sheet.md"
    res = cli(["solve", "--output", out, GOOD])  # the format from the suffix
    assert res.exit_code == 0, res.output
    assert res.stdout == ""
    text = out.read_text(encoding="utf-8")
    assert text == cli(["solve", "--format", "markdown", GOOD]).stdout
    again = cli(["solve", "--format", "html", "--output", out, GOOD])
    assert again.exit_code == 2
    assert "exists; add --force" in again.stderr
    assert out.read_text(encoding="utf-8") == text
    forced = cli(["solve", "--format", "html", "--output", out, "--force", GOOD])
    assert forced.exit_code == 0
    assert out.read_text(encoding="utf-8").startswith("<!DOCTYPE html>")


@pytest.mark.parametrize("args, suffix", [(["--plain"], "txt"), (["--json"], "out"),
                                          ([], "json"), ([], "tex"), ([], "html")])
def test_output_works_for_every_format(tmp_path, args, suffix):
    out = tmp_path / f"result.{suffix}"
    res = cli(["solve", *args, "-o", out, GOOD])
    assert res.exit_code == 0, res.output
    text = out.read_text(encoding="utf-8")
    if "--json" in args or suffix == "json":
        assert json.loads(text)["results"][0]["status"] == "solved"
    elif suffix == "tex":
        assert text.startswith("\\documentclass")
    elif suffix == "html":
        assert text.startswith("<!DOCTYPE html>")
    else:
        assert text == cli(["solve", "--plain", GOOD]).stdout


def test_output_refuses_an_input_file_and_writes_nothing_for_a_failed_file(tmp_path):
    res = cli(["solve", "--format", "markdown", "--output", GOOD, "--force", GOOD])
    assert res.exit_code == 2 and "input file" in res.stderr
    bad = tmp_path / "bad.mom"
    bad.write_text('problem "x"\nbody rod: rod(mass = 10 kg, length = 1 m\n')
    out = tmp_path / "bad.md"
    res = cli(["solve", "--output", out, bad])
    assert res.exit_code == 1
    assert not out.exists()


def test_several_files_make_one_document(tmp_path):
    res = cli(["solve", "--format", "latex", GOOD, GOOD2])
    assert res.exit_code == 0
    assert res.stdout.count("\\begin{document}") == 1
    assert res.stdout.count("\\section*{") == 2
    md = cli(["solve", "--format", "markdown", GOOD, GOOD2]).stdout
    assert md.count("\n# ") + md.startswith("# ") == 2 and "\n---\n" in md


def test_text_from_the_file_is_escaped_in_every_format():
    """A title is the user's text: markup in it stays text in every format."""
    fields = {f: getattr(_report(GOOD), f) for f in type(_report(GOOD))._fields}
    fields["title"] = "<script>alert(1)</script> & $x$ 50% #1 {a_b} \\ ~ ^ | *y* → ω"
    rep = SimpleNamespace(**fields)
    page = html_out.render([rep])
    assert "<script>" not in page and "&lt;script&gt;" in page
    md = markdown_out.render([rep])
    assert md.splitlines()[0] == ("# \\<script\\>alert(1)\\</script\\> & \\$x\\$ 50% \\#1 "
                                  "{a\\_b} \\\\ \\~ ^ \\| \\*y\\* → ω").replace("\\>", ">")
    latex = latex_out.render([rep])
    head = next(line for line in latex.splitlines() if line.startswith("\\section*"))
    assert head == ("\\section*{$<$script$>$alert(1)$<$/script$>$ \\& \\$x\\$ 50\\% \\#1 "
                    "\\{a\\_b\\} $\\backslash$ $\\sim$ \\^{} $|$ *y* $\\to$ $\\omega$}")


# ---- lines that reach the report only as text ------------------------------------------
@pytest.mark.parametrize("problem", PROBLEMS, ids=lambda p: p.stem)
def test_a_line_read_back_is_typeset_like_its_tree(problem):
    """The documents typeset each line as the plain report prints it, read back into a
    tree (`line_box`): on every equation of every example this gives what the solver's
    own tree gives, symbolically and with numbers (a known named by a formula, such as
    `x*D(x)`, is the one exception: read back, it is typeset as that formula)."""
    from momentum_cli.diagnostics import ProblemError
    from momentum_cli.expr import to_text
    from momentum_cli.report.math_tree import _NAME, line_box
    from momentum_cli.run import _build_scene
    from momentum_cli.solve import solve_scene

    try:
        sol = solve_scene(_build_scene(read_source(str(problem))))
    except ProblemError:
        pytest.skip("this example is meant to fail")
    checked = 0
    for e in sol.system.equations:
        for numeric in (False, True):
            text = e.text(numeric=numeric)
            if text != f"{to_text(e.lhs, numeric)} = {to_text(e.rhs, numeric)}":
                continue  # it prints itself in words ("integrated from the given start")
            if not numeric and any(not _NAME.match(n) for n in _names(e)):
                continue  # a known named by a formula
            assert to_latex(line_box(text)) == to_latex(equation_box(e.lhs, e.rhs, numeric)), \
                text
            checked += 1
    assert checked or not sol.system.equations


def _names(e) -> list[str]:
    from momentum_cli.expr import Add, Fn, Known, Mul, Pow, Var

    t = type(e)
    if t in (Var, Known):
        return [e.name]
    kids = e.terms if t is Add else e.factors if t is Mul else (e.base,) if t is Pow else \
        (e.arg,) if t is Fn else ()
    return [n for k in kids for n in _names(k)] if kids else \
        _names(e.lhs) + _names(e.rhs) if hasattr(e, "lhs") else []


def test_statements_for_the_system_are_typeset():
    """A transition may carry principles stated for the system (`system`: dicts with
    principle, why, steps, symbolic, numeric, result); each format shows them."""
    from momentum_cli.report.math_tree import line_box

    rep = _report(GOOD)
    fields = {f: getattr(rep, f) for f in type(rep)._fields}
    t = dict(rep.transitions[0])
    t["system"] = [dict(kind="linear", principle="linear momentum of {A, B} along x",
                        why="no external impulse acts on the system", steps=[],
                        symbolic="m_A*A.vx@1 + m_B*B.vx@1 = (m_A + m_B)*vx'@2",
                        numeric="2*3 + 3*0 = (2 + 3)*vx'@2",
                        result=["vx'@2 = 1.2 m/s: the bodies move together"])]
    fields["transitions"] = [t]
    rep2 = SimpleNamespace(**fields)
    md = markdown_out.render([rep2])
    assert "m_{A}v_{A,x}^{(1)}+m_{B}v_{B,x}^{(1)}=(m_{A}+m_{B}){v'}_{x}^{(2)}" in md
    assert "the bodies move together" in md
    latex = latex_out.render([rep2])
    assert "{v'}_{x}^{(2)}" in latex
    page = html_out.render([rep2])
    assert "because" in page and "<mo>′</mo>" in page
    assert to_latex(line_box("a = integrated from the given start")) == \
        r"a=\text{integrated from the given start}"


def test_the_readers_units_and_directions_when_the_model_has_them():
    rep = _report(GOOD)
    fields = {f: getattr(rep, f) for f in type(rep)._fields}
    fields["units"] = {"name": "US customary", "mass": "slug", "inertia": "slug*ft^2"}
    fields["answers"] = [dict(a, direction="to the right") for a in rep.answers]
    fields["unknowns"] = [dict(u, value=1.0, shown_unit="ft/s") for u in rep.unknowns]
    md = markdown_out.render([SimpleNamespace(**fields)])
    assert "## Knowns (US customary)" in md and "## Solution (US customary)" in md
    assert "mass ($\\mathrm{slug}$)" in md and "| to the right |" in md
    assert "| 1 | $\\mathrm{ft}/\\mathrm{s}$ |" in md


def test_lines_in_the_readers_units_are_typeset():
    from momentum_cli.report.math_tree import line_box

    assert to_latex(line_box("x@2 = 0.5*cos(-30 deg)*J   (SI)")) == \
        r"x^{(2)}=0.5\cos (-30^{\circ})J\,\text{(SI)}"
    assert line_box("T = 3 + 2 -") is None  # not the printer's form: shown as it is


@pytest.mark.parametrize("fmt", ["markdown", "latex", "html"])
def test_steps_brief_makes_a_short_document_with_the_same_answers(fmt):
    """--steps brief keeps the principles, the diagrams, the answers and the key checks;
    the unknowns table and the block matrices are in --steps full only."""
    path = EXAMPLES / "seed_pendulum_wall.mom"
    full = cli(["solve", "--format", fmt, path])
    brief = cli(["solve", "--format", fmt, "--steps", "brief", path])
    assert full.exit_code == brief.exit_code == 0
    assert len(brief.output) < 0.8 * len(full.output)
    assert "Solution (SI)" in full.output and "Solution (SI)" not in brief.output
    for word in ("Answers", "Impulse diagram", "Checks"):
        assert word in brief.output
