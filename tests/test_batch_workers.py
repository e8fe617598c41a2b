"""A batch's worker processes (run_pool.Worker): forked with the batch, fed chunks of
file indices down their own pipes, results back in order. A worker that dies leaves
the rest of the batch to the parent (every file still solved, as alone); a bug in a
worker is raised in the parent, never hidden; the workers are reaped at the end.
"""
from __future__ import annotations

import multiprocessing as mp
import os
import threading
from pathlib import Path

import pytest

from momentum_cli import run, run_pool
from momentum_cli.run import PARALLEL_MIN, read_source, solve_many, solve_source

ROOT = Path(__file__).resolve().parent.parent
EXAMPLES = sorted((ROOT / "examples").glob("*.mom"))

fork = pytest.mark.skipif("fork" not in mp.get_all_start_methods(),
                          reason="workers are forked")


def _square(i):
    return i * i


def _dies_at_5(i):
    if i == 5:
        os._exit(3)  # as a worker killed (by the OOM killer, say) half-way
    return i * i


def _raises_at_3(i):
    if i == 3:
        raise ValueError("a bug in the solve")
    return i * i


def _workers(solve, n=2):
    ctx = mp.get_context("fork")
    return [run_pool.Worker(ctx, solve) for _ in range(n)]


def _close(workers):
    for wk in workers:
        wk.proc.kill()
        wk.close(ask=False)


@fork
def test_routed_yields_every_result_in_order():
    texts = [f"let a = {k}\n" if k % 3 else f"let b = {k}\n" for k in range(70)]
    workers = _workers(_square)
    try:
        assert list(run_pool.routed(texts, workers)) == [k * k for k in range(70)]
    finally:
        for wk in workers:
            wk.close(ask=True)
    assert not any(wk.proc.is_alive() for wk in workers)
    assert all(wk.proc.exitcode == 0 for wk in workers)  # asked to end, and reaped


@fork
def test_a_worker_that_dies_is_reported_not_waited_for():
    texts = ["let a = 1\n"] * 20  # one family: one worker, index 5 in its first chunk
    workers = _workers(_dies_at_5, 1)
    got = []
    try:
        with pytest.raises(run_pool.WorkerDied):
            for r in run_pool.routed(texts, workers):
                got.append(r)
    finally:
        _close(workers)
    assert got == [k * k for k in range(len(got))] and len(got) < 5


@fork
def test_a_worker_already_dead_when_sent_its_files_is_reported_too():
    """The other side of the race above: the parent sends to a worker that has died
    (a broken pipe, not an end of file): the same WorkerDied, not an OSError."""
    workers = _workers(_square, 1)
    workers[0].proc.kill()
    workers[0].proc.join()
    try:
        with pytest.raises(run_pool.WorkerDied):
            list(run_pool.routed(["let a = 1\n"] * 200, workers))
    finally:
        _close(workers)


@fork
def test_a_bug_in_a_worker_is_raised_in_the_parent():
    workers = _workers(_raises_at_3)
    try:
        with pytest.raises(ValueError, match="a bug in the solve"):
            list(run_pool.routed(["let a = 1\n"] * 10, workers))
    finally:
        _close(workers)


@fork
@pytest.mark.skipif(len(os.sched_getaffinity(0)) < 2 if hasattr(os, "sched_getaffinity")
                    else (os.cpu_count() or 1) < 2, reason="workers need two cores")
def test_a_batch_whose_worker_dies_is_finished_by_the_parent(monkeypatch):
    """Every file is still solved, and each result is the file's alone (its source
    given back by the parent, since a worker ships a result without it)."""
    parent = os.getpid()
    real = run._batch_index

    def dies_once(i):
        if os.getpid() != parent and i == 9:
            os._exit(3)
        return real(i)

    monkeypatch.setattr(run, "_batch_index", dies_once)
    monkeypatch.setattr(run, "WORKERS_KILLED", False)
    monkeypatch.setattr(threading, "excepthook", threading.excepthook)
    sources = [read_source(str(p)) for p in (EXAMPLES * 2)[:PARALLEL_MIN + 4]]
    batch = list(solve_many(sources, False, 6, "float"))
    assert run.WORKERS_KILLED  # the survivor was ended too
    assert len(batch) == len(sources)
    for s, b in zip(sources, batch):
        a = solve_source(s, False, 6, "float")
        assert b.source is s or (b.source is None and b.status == "internal"), s.name
        assert (b.name, b.status, b.diagnostics) == (a.name, a.status, a.diagnostics), s.name


@fork
def test_a_worker_that_ends_prints_nothing_the_parent_had_not_flushed():
    """Text waiting in the parent's stdout buffer at the fork is printed once, also
    when the workers are asked to end (the batch read to its end), not killed."""
    import subprocess
    import sys

    code = (
        "import sys\n"
        "from momentum_cli.run import solve_many, PARALLEL_MIN\n"
        "from momentum_cli.source import Source\n"
        f"text = open({str(EXAMPLES[0])!r}, encoding='utf-8').read()\n"
        "sys.stdout.write('before the batch\\n')\n"
        "n = sum(1 for r in solve_many([Source(f'{k}.mom', text) for k in "
        "range(PARALLEL_MIN + 2)], False, 6, 'float'))\n"
        "sys.stdout.write(f'{n} results\\n')\n")
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                       timeout=300)
    assert p.returncode == 0, p.stderr
    from momentum_cli.run import PARALLEL_MIN
    assert p.stdout == f"before the batch\n{PARALLEL_MIN + 2} results\n"
