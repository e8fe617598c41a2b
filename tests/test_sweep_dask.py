"""Sweeps on Dask: a LocalCluster of two worker processes gives byte-identical CSV to
the local run, for `solve` sweeps and for sweeps of `simulate` scenes (issue 13).

Skipped when dask.distributed is not installed (the `dask` extra; the `test` extra has it).
"""
from __future__ import annotations

import io
import sys

import numpy as np
import pytest

from conftest import EXAMPLES

distributed = pytest.importorskip("distributed", reason="dask.distributed is not installed: "
                                  "pip install 'momentum-cli[dask]' to run the Dask tests")

from momentum_cli.sweep import dask_run  # noqa: E402
from momentum_cli.sweep.batch import solve_batch  # noqa: E402
from momentum_cli.sweep.output import write_csv  # noqa: E402
from momentum_cli.sweep.sim_batch import simulate_batch  # noqa: E402
from momentum_cli.sweep.spec import parse_design  # noqa: E402

BOUNCE = EXAMPLES / "sweep" / "bounce_height.mom"
R, G = 0.033, 9.81


@pytest.fixture(scope="module")
def client():
    """Two worker processes, one thread each, for the whole module (start-up ~2 s)."""
    c = dask_run.client_for("local", workers=2)
    yield c
    cluster = c.cluster
    c.close()
    cluster.close()


def _csv(result) -> str:
    buf = io.StringIO()
    write_csv(result, buf)
    return buf.getvalue()


def test_chunks_cover_the_variants_in_order():
    assert dask_run.chunks(5, 2) == [(0, 2), (2, 4), (4, 5)]
    assert dask_run.chunks(4, 2) == [(0, 2), (2, 4)]
    assert dask_run.chunks(1, 2000) == [(0, 1)]


def test_solve_sweep_on_two_workers_is_byte_identical(client):
    """e from 0 to 1: at e = 0 and e = 1 the structure changes (the rebound speed is 0,
    no energy is lost) and those variants are solved on their own. A chunk holding only
    them must still be traced at the whole run's base (choose_base), or its statuses
    would differ."""
    design = parse_design(["e=0..1:5"], [], None, None)
    cols, dims = design.columns(), {p.name: p.dim for p in design.params}
    local = solve_batch(str(BOUNCE), cols, dims)
    remote = dask_run.run("solve", BOUNCE.read_text(encoding="utf-8"), str(BOUNCE), cols,
                          "local", {"dims": dims}, chunk=2, client=client)
    assert len(client.scheduler_info()["workers"]) == 2
    assert _csv(remote) == _csv(local)
    assert [s == "ok" for s in remote.status] == [False, True, True, True, False]
    e, h = cols["e"], 1.5
    assert np.allclose(remote.answers["bounce"], R + e ** 2 * (h - R), rtol=1e-9, atol=1e-12)


def test_monte_carlo_of_a_seed_on_two_workers_is_byte_identical(client):
    path = EXAMPLES / "seed_rod_drop_smooth.mom"
    design = parse_design([], ["e[A]~uniform(0.5, 1)", "rod.y@1~normal(1 m, 0.1 m)"], 30, 1)
    cols, dims = design.columns(), {p.name: p.dim for p in design.params}
    local = solve_batch(str(path), cols, dims)
    remote = dask_run.run("solve", path.read_text(encoding="utf-8"), str(path), cols, "local",
                          {"dims": dims}, chunk=15, client=client)
    assert _csv(remote) == _csv(local)


def test_simulate_sweep_on_two_workers_is_byte_identical(client):
    text = BOUNCE.read_text(encoding="utf-8")
    cols = {"e": np.linspace(0.5, 0.9, 7), "h": np.linspace(1.0, 2.0, 7)}
    local = simulate_batch(text, str(BOUNCE), cols)
    remote = dask_run.run("simulate", text, str(BOUNCE), cols, "local", chunk=2,
                          client=client)
    assert _csv(remote) == _csv(local)
    assert list(remote.status) == ["ok"] * 7
    want = R + cols["e"] ** 2 * (cols["h"] - R)  # the top of the rebound
    assert np.allclose(remote.answers["ball.y"], want, rtol=1e-9)


def test_a_failed_variant_keeps_its_place_and_reason(client):
    """A variant that does not run (a negative drop height makes the file's expected
    rebound speed the root of a negative number) keeps its row, NaN outputs and its
    reason; the others are unchanged."""
    text = BOUNCE.read_text(encoding="utf-8")
    cols = {"e": np.array([0.6, 0.7, 0.8, 0.9]), "h": np.array([1.0, 1.2, -1.0, -1.0])}
    local = simulate_batch(text, str(BOUNCE), cols)
    remote = dask_run.run("simulate", text, str(BOUNCE), cols, "local", chunk=2, client=client)
    assert _csv(remote) == _csv(local)
    assert list(remote.status[:2]) == ["ok", "ok"]
    assert all(s.startswith("error: ") for s in remote.status[2:])
    assert np.isnan(remote.answers["ball.y"][2:]).all()


def test_missing_dask_is_one_line(monkeypatch):
    monkeypatch.setitem(sys.modules, "distributed", None)
    with pytest.raises(dask_run.DaskError, match=r"pip install 'momentum-cli\[dask\]'"):
        dask_run.client_for("local")


def test_an_unreachable_scheduler_is_one_line():
    with pytest.raises(dask_run.DaskError, match="cannot reach the scheduler"):
        dask_run.client_for("tcp://127.0.0.1:9", timeout=1)
