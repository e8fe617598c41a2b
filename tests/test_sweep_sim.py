"""Sweeps of `simulate` scenes (`momentum sweep --simulate`) and `--plot` (issue 13): each
variant's simulation outputs against closed forms of the bounce, per-variant failures
kept in place, and the plot drawn for a grid and for drawn values."""
from __future__ import annotations

import math

import numpy as np
import pytest

from conftest import EXAMPLES
from momentum_cli.sweep.sim_batch import simulate_batch

BOUNCE = EXAMPLES / "sweep" / "bounce_height.mom"
G, R, M = 9.81, 0.033, 0.057


def _bounce(cols):
    return simulate_batch(BOUNCE.read_text(encoding="utf-8"), str(BOUNCE), cols)


def test_bounce_outputs_match_the_closed_forms():
    e = np.array([0.3, 0.55, 0.8, 1.0])
    h = np.array([0.5, 1.0, 2.0, 3.0])
    res = _bounce({"e": e, "h": h})
    assert list(res.status) == ["ok"] * 4
    fall = h - R  # the centre falls this far before the ball touches
    t_fall = np.sqrt(2 * fall / G)
    assert np.allclose(res.answers["ball.y"], R + e ** 2 * fall, rtol=1e-9)  # the apex
    assert np.allclose(res.answers["t_end"], t_fall * (1 + e), rtol=1e-9)  # fall + rise
    assert np.allclose(res.answers["energy_lost"], M * G * fall * (1 - e ** 2), rtol=1e-9,
                       atol=1e-12)
    assert np.allclose(res.answers["ball.vy"], 0, atol=1e-9)
    assert list(res.answers["impacts"]) == [1, 1, 1, 1]
    assert res.units["ball.y"] == "m" and res.units["t_end"] == "s"
    assert res.units["energy_lost"] == "J"
    assert "ball.angle" not in res.answers  # a particle has no angle


def test_values_are_set_in_si_whatever_unit_the_let_was_written_in():
    """`let r = 33 mm`: the column holds metres."""
    res = _bounce({"r": np.array([0.02, 0.05])})
    h, e = 1.5, 0.7
    r = np.array([0.02, 0.05])
    assert np.allclose(res.answers["ball.y"], r + e ** 2 * (h - r), rtol=1e-9)


def test_a_variant_that_does_not_run_keeps_its_row_and_reason():
    res = _bounce({"h": np.array([1.0, -1.0, 2.0])})
    assert res.status[0] == "ok" and res.status[2] == "ok"
    assert res.status[1].startswith("error: ") and "line" in res.status[1]
    assert math.isnan(res.answers["ball.y"][1])
    assert np.allclose(res.answers["ball.y"][[0, 2]],
                       R + 0.49 * (np.array([1.0, 2.0]) - R), rtol=1e-9)


def test_a_name_the_file_cannot_vary_is_refused():
    from momentum_cli.sweep.batch import SweepError

    with pytest.raises(SweepError, match="no `let m`"):
        _bounce({"m": np.array([1.0])})


THROW = """problem "thrown"
gravity 9.81 m/s^2 down
body ball: particle(mass = 1 kg)
state 1: ball.x = 0, ball.y = 0, ball.vx = 3 m/s, ball.vy = 4 m/s
simulate from 1:
    until apex
"""


def test_a_states_given_number_can_be_varied():
    """`ball.vy@1`: the start state's given number, as `solve` sweeps vary it."""
    vy = np.array([2.0, 4.0, 8.0])
    res = simulate_batch(THROW, "throw.mom", {"ball.vy@1": vy})
    assert list(res.status) == ["ok"] * 3
    assert np.allclose(res.answers["ball.y"], vy ** 2 / (2 * G), rtol=1e-9)
    assert np.allclose(res.answers["ball.x"], 3.0 * vy / G, rtol=1e-9)


@pytest.mark.parametrize("grid", [True, False])
def test_plot_draws_a_grid_or_histograms(tmp_path, grid):
    pytest.importorskip("matplotlib", reason="matplotlib is not installed (the `plot` extra)")
    from momentum_cli.sweep.plot import draw

    e = np.linspace(0.5, 0.9, 5) if grid else np.random.default_rng(1).uniform(0.5, 0.9, 40)
    res = _bounce({"e": e})
    path = tmp_path / "sweep.png"
    draw(res, str(path), ["e"] if grid else [], [] if grid else ["e"], title="bounce")
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_plot_is_never_written_over_an_existing_file_without_force(tmp_path):
    pytest.importorskip("matplotlib", reason="matplotlib is not installed (the `plot` extra)")
    from momentum_cli.sweep.execute import RunError, check_plot

    path = tmp_path / "old.png"
    path.write_bytes(b"keep")
    with pytest.raises(RunError, match="exists; add --force"):
        check_plot(str(path), [str(BOUNCE)], False)
    check_plot(str(path), [str(BOUNCE)], True)
    with pytest.raises(RunError, match="unknown file type"):
        check_plot(str(tmp_path / "x.txt"), [str(BOUNCE)], False)
    assert path.read_bytes() == b"keep"


def test_a_misspelt_parameter_is_a_usage_error():
    from momentum_cli.sweep.execute import RunError, run

    with pytest.raises(RunError, match="no `let ee`.*did you mean 'e'"):
        run(str(BOUNCE), BOUNCE.read_text(encoding="utf-8"), {"ee": np.array([0.5])},
            simulate=True)


def test_a_missing_dask_is_a_one_line_usage_error(monkeypatch):
    import sys

    from momentum_cli.sweep.execute import RunError, check_dask

    monkeypatch.setitem(sys.modules, "distributed", None)
    with pytest.raises(RunError, match=r"pip install 'momentum-cli\[dask\]'"):
        check_dask("local")
    check_dask(None)


def test_cli_simulate_sweep_with_plot(tmp_path):
    """`momentum sweep --simulate --plot`: the summary, the CSV, the PNG; the plot is not
    written over an existing file without --force (exit 2, one line, file untouched)."""
    pytest.importorskip("matplotlib", reason="matplotlib is not installed (the `plot` extra)")
    from typer.testing import CliRunner

    from momentum_cli.cli import app

    png, csv = tmp_path / "bounce.png", tmp_path / "bounce.csv"
    args = ["sweep", str(BOUNCE), "--simulate", "--vary", "e=0.5..0.9:3", "--csv", str(csv),
            "--plot", str(png)]
    res = CliRunner().invoke(app, args)
    assert res.exit_code == 0, res.output
    assert "3 solved one by one (one simulation per variant)" in res.output
    assert png.read_bytes()[:4] == b"\x89PNG"
    rows = csv.read_text(encoding="utf-8").splitlines()
    assert rows[0].startswith("e,t_end (s),impacts,energy_lost (J),ball.x (m),ball.y (m)")
    ys = [float(r.split(",")[5]) for r in rows[1:]]
    assert np.allclose(ys, R + np.array([0.25, 0.49, 0.81]) * (1.5 - R), rtol=1e-9)
    csv.unlink()
    res = CliRunner().invoke(app, args)
    assert res.exit_code == 2
    assert "--plot" in res.output and "exists; add --force" in res.output
    assert not csv.exists()  # refused before any work


def test_cli_dask_without_dask_is_one_line(monkeypatch):
    import sys

    from typer.testing import CliRunner

    from momentum_cli.cli import app

    monkeypatch.setitem(sys.modules, "distributed", None)
    res = CliRunner().invoke(app, ["sweep", str(BOUNCE), "--vary", "e=0.5..0.9:3", "--dask",
                                   "local"])
    assert res.exit_code == 2
    assert res.output.strip().splitlines() == [
        "momentum sweep: error: --dask needs dask.distributed: pip install "
        "'momentum-cli[dask]'"]


def test_plot_keeps_variants_solved_on_their_own_and_counts_failures(tmp_path, monkeypatch):
    """Only "error: ..." variants are left out of the picture (and counted)."""
    pytest.importorskip("matplotlib", reason="matplotlib is not installed (the `plot` extra)")
    from momentum_cli.sweep import plot

    drawn = {}
    monkeypatch.setattr(plot, "_lines", lambda ax, params, grid, y, ok, units:
                        drawn.setdefault("ok", list(ok)))
    res = _bounce({"e": np.array([0.5, 0.6, 0.7])})
    res.status = np.array(["ok", "the structure changes", "error: no solution"], dtype=object)
    plot.draw(res, str(tmp_path / "p.png"), ["e"], [], answers=["ball.y"])
    assert drawn["ok"] == [True, True, False]


@pytest.mark.parametrize("name, message", [
    ("e[floor]", "an impact's coefficient, which the simulation does not use"),
    ("ball.vy@2", "given in state 2, and the simulation starts from state 1"),
])
def test_a_parameter_the_simulation_does_not_use_is_refused(name, message):
    from momentum_cli.sweep.batch import SweepError

    with pytest.raises(SweepError, match=message):
        _bounce({name: np.array([0.5])})


def test_a_file_without_a_simulation_is_refused():
    from momentum_cli.sweep.batch import SweepError

    text = (EXAMPLES / "ball_bounce_rebound.mom").read_text(encoding="utf-8")
    with pytest.raises(SweepError, match="has no `simulate from S:` block"):
        simulate_batch(text, "ball_bounce_rebound.mom", {"h": np.array([1.0])})
