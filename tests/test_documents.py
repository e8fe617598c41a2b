"""The documents in a real browser and a real TeX: what a reader would open.

(a) The HTML of the seeds and a few other examples is loaded in headless Chromium (the
OS package, driven over DevTools by tools/browser.py): no console error, no blocked
request, MathML and SVG present, non-empty and laid out, and a screenshot that is not
one colour. (b) The LaTeX of every seed compiles with `pdflatex -halt-on-error`.
Each part skips, saying why, when its tool is not installed (`.ci/run` installs both).
"""
from __future__ import annotations

import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from conftest import EXAMPLES, ROOT

from momentum_cli.report import html_out, latex_out
from momentum_cli.run import read_source, solve_source

sys.path.insert(0, str(ROOT / "tools"))
import browser  # noqa: E402  (tools/browser.py: the DevTools client)

SEEDS = sorted(EXAMPLES.glob("seed_*.mom"))
OTHERS = [EXAMPLES / f"{n}.mom" for n in ("ballistic_pendulum", "crash_cars_lock_skid",
                                          "flow_rocket_free_space", "centre_of_percussion")]
PAGES = SEEDS + [p for p in OTHERS if p.exists()]
CHROMIUM = browser.find_chromium()
PDFLATEX = shutil.which("pdflatex")

needs_chromium = pytest.mark.skipif(
    CHROMIUM is None, reason="Chromium is not installed (apt-get install chromium; "
    ".ci/run does): the HTML documents are not checked in a browser")
needs_pdflatex = pytest.mark.skipif(
    PDFLATEX is None, reason="pdflatex is not installed (apt-get install "
    "texlive-latex-base texlive-latex-recommended; .ci/run does): the LaTeX documents "
    "are not compiled")


def _report(path: Path):
    res = solve_source(read_source(str(path)))
    assert res.report is not None, res.diagnostics
    return res.report


@pytest.fixture(scope="module")
def chromium():
    with browser.Chromium(CHROMIUM) as b:
        yield b


def _check_page(chromium, path: Path, diagrams: int) -> dict:
    info = browser.load(chromium, path)
    assert info["errors"] == [], info["errors"]
    assert info["scripts"] == 0
    assert info["math"] > 0 and info["math_empty"] == 0
    assert info["math_unrendered"] == 0, "a <math> element with no size: MathML not laid out"
    assert info["math_display"] > 0
    assert info["svg"] >= diagrams and info["svg_empty"] == 0
    return info


@needs_chromium
@pytest.mark.parametrize("problem", PAGES, ids=lambda p: p.stem)
def test_html_in_a_real_browser(problem, chromium, tmp_path):
    rep = _report(problem)
    page = tmp_path / f"{problem.stem}.html"
    page.write_text(html_out.render([rep]), encoding="utf-8")
    _check_page(chromium, page, len(getattr(rep, "diagrams", None) or []))
    png = browser.screenshot(chromium, tmp_path / "shot.png", height=1200, scale=0.5)
    assert browser.png_colours(png) > 2, "the screenshot is blank"


@needs_chromium
def test_an_impulse_diagram_svg_is_drawn_in_the_browser(chromium, tmp_path):
    from test_formats import with_diagram

    rep = with_diagram(_report(EXAMPLES / "seed_plastic_collision.mom"))
    page = tmp_path / "diagram.html"
    page.write_text(html_out.render([rep]), encoding="utf-8")
    info = _check_page(chromium, page, 1)
    assert info["svg"] == 1


@needs_chromium
def test_html_prints(chromium, tmp_path):
    """Printed (the page's print styles, A4) it makes a PDF of several pages."""
    rep = _report(EXAMPLES / "seed_pendulum_wall.mom")
    page = tmp_path / "print.html"
    page.write_text(html_out.render([rep]), encoding="utf-8")
    assert browser.load(chromium, page)["errors"] == []
    pdf = browser.print_pdf(chromium, tmp_path / "print.pdf")
    assert pdf[:5] == b"%PDF-"
    assert len(re.findall(rb"/Type\s*/Page\b", pdf)) >= 2


@needs_chromium
def test_a_page_that_fetches_is_caught(chromium, tmp_path):
    """The check itself works: a request the page's policy blocks is an error."""
    rep = _report(EXAMPLES / "seed_plastic_collision.mom")
    page = tmp_path / "fetch.html"
    page.write_text(html_out.render([rep]).replace(
        "</main>", '<img src="https://example.invalid/x.png" alt=""></main>'),
        encoding="utf-8")
    info = browser.load(chromium, page)
    assert info["errors"], "a blocked request was not reported"


def _pdflatex(tmp_path: Path, source: str) -> None:
    (tmp_path / "sheet.tex").write_text(source, encoding="utf-8")
    proc = subprocess.run([PDFLATEX, "-interaction=nonstopmode", "-halt-on-error",
                           "sheet.tex"], cwd=tmp_path, stdin=subprocess.DEVNULL,
                          capture_output=True, text=True, errors="replace", timeout=300)
    assert proc.returncode == 0, proc.stdout[-3000:]
    pdf = tmp_path / "sheet.pdf"
    assert pdf.exists() and pdf.read_bytes()[:5] == b"%PDF-"
    assert "Missing character" not in (tmp_path / "sheet.log").read_text(errors="replace")


@needs_pdflatex
@pytest.mark.parametrize("problem", SEEDS, ids=lambda p: p.stem)
def test_latex_compiles_with_pdflatex(problem, tmp_path):
    _pdflatex(tmp_path, latex_out.render([_report(problem)]))


@needs_pdflatex
def test_latex_of_text_full_of_tex_specials_compiles(tmp_path):
    from types import SimpleNamespace

    rep = _report(EXAMPLES / "seed_plastic_collision.mom")
    fields = {f: getattr(rep, f) for f in type(rep)._fields}
    fields["title"] = "Test \\ {a_b} $x$ 50% #1 & ~ ^ | <> → ω ° µ ‘q’ “q” – — ṁ ✓"
    _pdflatex(tmp_path, latex_out.render([SimpleNamespace(**fields)]))
