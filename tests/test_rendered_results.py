"""A worker ships a solved file as `Rendered` text (run.solve_many's `render`): the same
text and checks as rendering the report where it was made, for plain and -q output."""
from functools import partial
from pathlib import Path

import pytest

from momentum_cli.report.text import render, render_quiet
from momentum_cli.run import Rendered, read_source, solve_many, solve_source

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
FILES = ["seed_rod_drop_smooth.mom", "seed_pendulum_wall.mom", "collar_slides_on_spinning_rod.mom"]


@pytest.mark.parametrize("name", FILES)
@pytest.mark.parametrize("how", ["plain", "quiet"])
def test_rendered_equals_report_rendered_here(name, how):
    src = read_source(str(EXAMPLES / name))
    fn = partial(render, sig=6, detail="full") if how == "plain" else partial(render_quiet, sig=6)
    direct = solve_source(src, False, 6, "float")
    (shipped,) = list(solve_many([src], False, 6, "float", render=fn))
    assert isinstance(shipped.report, Rendered)
    assert shipped.report.text == fn(direct.report)
    assert shipped.report.checks == list(direct.report.checks)
    assert shipped.status == direct.status and shipped.diagnostics == direct.diagnostics


@pytest.mark.parametrize("name", FILES)
def test_rendered_parts_join_to_the_report_rendered_here(name, monkeypatch):
    """--plain's full text: a big report ships as pieces (streamed, never joined whole),
    a small one as one text (one string to pickle and to write); both are the text."""
    from momentum_cli import run
    from momentum_cli.report.text import render_parts

    src = read_source(str(EXAMPLES / name))
    direct = solve_source(src, False, 6, "float")
    (small,) = list(solve_many([src], False, 6, "float", render=partial(render_parts, sig=6)))
    assert small.report.parts is None and small.report.text == render(direct.report, 6)
    monkeypatch.setattr(run, "JOIN_LIMIT", 100)  # any report is "big" now
    (shipped,) = list(solve_many([src], False, 6, "float", render=partial(render_parts, sig=6)))
    assert shipped.report.parts is not None and shipped.report.text == ""
    assert "\n".join(shipped.report.parts) == render(direct.report, 6)


def test_failed_file_ships_no_report(tmp_path):
    p = tmp_path / "bad.mom"
    p.write_text('problem "x"\nbody a: particle(mass = 1 kg)\nfind a.vx@9\n', encoding="utf-8")
    (res,) = list(solve_many([read_source(str(p))], False, 6, "float", render=render_quiet))
    assert res.status == "error" and res.report is None


def test_a_missing_dependency_is_named_not_called_a_bug(monkeypatch):
    """A Python without one of momentum's dependencies (lark, say) gets one line naming
    the missing package and how to fix it, not 'this is a bug in momentum'."""
    from momentum_cli import run
    from momentum_cli.source import Source

    def broken(*_args, **_kw):
        raise ModuleNotFoundError("No module named 'lark'", name="lark")

    monkeypatch.setattr(run, "solve_source", broken)
    res = run._solve_job((Source("a.mom", "x"), False, 6, "float", (), "file", False, None))
    (d,) = res.diagnostics
    assert "'lark' is not installed" in d.message and "bug" not in d.message
