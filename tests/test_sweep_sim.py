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
    assert res.status[1] != "ok" and "line" in res.status[1]
    assert math.isnan(res.answers["ball.y"][1])
    assert np.allclose(res.answers["ball.y"][[0, 2]],
                       R + 0.49 * (np.array([1.0, 2.0]) - R), rtol=1e-9)


def test_a_name_without_a_let_is_refused():
    with pytest.raises(ValueError, match="no `let m`"):
        _bounce({"m": np.array([1.0])})


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


def test_simulate_sweeps_vary_lets_only():
    from momentum_cli.sweep.execute import RunError, run

    with pytest.raises(RunError, match="has no `let ee`; did you mean 'e'"):
        run(str(BOUNCE), BOUNCE.read_text(encoding="utf-8"), {"ee": np.array([0.5])},
            simulate=True)


def test_a_missing_dask_is_a_one_line_usage_error(monkeypatch):
    import sys

    from momentum_cli.sweep.execute import RunError, check_dask

    monkeypatch.setitem(sys.modules, "distributed", None)
    with pytest.raises(RunError, match=r"pip install 'momentum-cli\[dask\]'"):
        check_dask("local")
    check_dask(None)
