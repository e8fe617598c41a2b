"""Sweeps on Dask: a LocalCluster of two worker processes gives byte-identical results to
the local run, for `solve` sweeps and for sweeps of `simulate` scenes (issue 13).

Skipped when dask.distributed is not installed (the `dask` extra; the `test` extra has it).
"""
from __future__ import annotations

import sys

import numpy as np
import pytest

from conftest import EXAMPLES

distributed = pytest.importorskip("distributed", reason="dask.distributed is not installed: "
                                  "pip install 'momentum-cli[dask]' to run the Dask tests")

import sweep_standin  # noqa: E402
from momentum_cli.sweep import dask_run  # noqa: E402
from momentum_cli.sweep.sim_batch import simulate_batch  # noqa: E402

BOUNCE = EXAMPLES / "sweep" / "bounce_height.mom"


@pytest.fixture(scope="module")
def client():
    """Two worker processes, one thread each, for the whole module (start-up ~2 s)."""
    import cloudpickle

    cloudpickle.register_pickle_by_value(sweep_standin)  # the workers cannot import tests/
    c = dask_run.client_for("local", workers=2)
    yield c
    cluster = c.cluster
    c.close()
    cluster.close()


def _write_csv(result) -> str:
    try:
        from momentum_cli.sweep.output import write_csv
    except ImportError:
        return sweep_standin.csv_text(result)
    import io

    buf = io.StringIO()
    write_csv(result, buf)
    return buf.getvalue()


def test_chunks_cover_the_variants_in_order():
    assert dask_run.chunks(5, 2) == [(0, 2), (2, 4), (4, 5)]
    assert dask_run.chunks(4, 2) == [(0, 2), (2, 4)]
    assert dask_run.chunks(1, 2000) == [(0, 1)]


def test_simulate_sweep_on_two_workers_equals_the_local_run(client):
    text = BOUNCE.read_text(encoding="utf-8")
    cols = {"e": np.linspace(0.5, 0.9, 7), "h": np.linspace(1.0, 2.0, 7)}
    local = simulate_batch(text, str(BOUNCE), cols)
    remote = dask_run.run("simulate", text, str(BOUNCE), cols, "local", chunk=2,
                          client=client)
    assert len(client.scheduler_info()["workers"]) == 2
    assert _write_csv(remote) == _write_csv(local)
    assert list(remote.status) == ["ok"] * 7
    # the bounce height against its closed form r + e^2 (h - r)
    r = 0.033
    want = r + cols["e"] ** 2 * (cols["h"] - r)
    assert np.allclose(remote.answers["ball.y"], want, rtol=1e-9)


def test_solve_sweep_on_two_workers_equals_the_local_run(client):
    text = BOUNCE.read_text(encoding="utf-8")
    cols = {"e": np.array([0.5, 0.6, 0.7, 0.8, 0.9])}
    local = sweep_standin.solve_text_batch(text, str(BOUNCE), cols)
    remote = dask_run.run("solve", text, str(BOUNCE), cols, "local", chunk=2, client=client,
                          solver=sweep_standin.solve_text_batch)
    assert _write_csv(remote) == _write_csv(local)
    r, h, g = 0.033, 1.5, 9.81
    assert np.allclose(remote.answers["bounce"], r + cols["e"] ** 2 * (h - r), rtol=1e-9)
    assert np.allclose(remote.answers["ball.vy@3"], cols["e"] * np.sqrt(2 * g * (h - r)),
                       rtol=1e-9)


def test_a_failed_chunk_keeps_its_place_and_reason(client):
    """A variant that does not run (a negative drop height puts the ball below the
    floor) keeps its row, NaN outputs and its reason; the others are unchanged."""
    text = BOUNCE.read_text(encoding="utf-8")
    cols = {"e": np.array([0.6, 0.7, 0.8, 0.9]), "h": np.array([1.0, 1.2, -1.0, -1.0])}
    local = simulate_batch(text, str(BOUNCE), cols)
    remote = dask_run.run("simulate", text, str(BOUNCE), cols, "local", chunk=2, client=client)
    assert _write_csv(remote) == _write_csv(local)
    assert list(remote.status[:2]) == ["ok", "ok"]
    assert all(s != "ok" for s in remote.status[2:])
    assert np.isnan(remote.answers["ball.y"][2:]).all()


def test_missing_dask_is_one_line(monkeypatch):
    monkeypatch.setitem(sys.modules, "distributed", None)
    with pytest.raises(dask_run.DaskError, match=r"pip install 'momentum-cli\[dask\]'"):
        dask_run.client_for("local")


def test_an_unreachable_scheduler_is_one_line():
    with pytest.raises(dask_run.DaskError, match="cannot reach the scheduler"):
        dask_run.client_for("tcp://127.0.0.1:9", timeout=1)
