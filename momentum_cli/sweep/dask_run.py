"""Sweeps on a Dask cluster: the variants in deterministic chunks, solved on the workers.

Stage: run. In: the problem text (never a path: a worker may not see the file), columns
{let name: SI values} drawn once here, and a scheduler address (`tcp://host:8786`) or
`local` (a LocalCluster on this machine). Out: the chunks' results joined in variant
order, the same as one local batch. `dask.distributed` is imported only here, on use.
"""
from __future__ import annotations

import math
import os

import numpy as np

# variants per task: a task should last seconds, well beyond its scheduling and the
# tracing each batched chunk repeats (~0.5 s); a simulation costs ~10 ms, a batched
# solve ~0.05 ms per variant
CHUNK = {"solve": 50_000, "simulate": 500}


class DaskError(Exception):
    """Dask missing, or a cluster that cannot be reached; the message is one line."""


def chunks(n: int, size: int) -> list[tuple[int, int]]:
    """[start, stop) ranges of at most `size` variants, in order (a function of n only)."""
    if size < 1:
        raise ValueError("a chunk holds at least one variant")
    return [(a, min(a + size, n)) for a in range(0, n, size)] or [(0, 0)]


def client_for(address: str, workers: int | None = None, timeout: float = 10.0):
    """A dask.distributed Client: `local` starts a LocalCluster of worker processes (one
    thread each); anything else is a scheduler's address."""
    try:
        from distributed import Client, LocalCluster
    except ImportError:
        raise DaskError("--dask needs dask.distributed: pip install 'momentum-cli[dask]'") \
            from None
    if address == "local":
        if workers is None:
            workers = max(1, min(len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity")
                                 else (os.cpu_count() or 1), 8))
        cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                               dashboard_address=None)
        return Client(cluster)
    try:
        return Client(address, timeout=f"{timeout}s")
    except (OSError, TimeoutError, ValueError) as exc:
        raise DaskError(f"--dask {address}: cannot reach the scheduler: "
                        f"{str(exc).splitlines()[0] if str(exc) else type(exc).__name__}") \
            from None


def run(kind: str, text: str, name: str, columns: dict, address: str, options: dict | None = None,
        chunk: int | None = None, workers: int | None = None, progress=None, client=None,
        solver=None):
    """The sweep of one problem on a cluster. `kind`: "solve" (each chunk through
    `solve_batch`, `options` its `dims`) or "simulate" (through `simulate_batch`, with
    `options`); `solver` (text, name, columns) -> result replaces the solve of a chunk.
    The result is the chunks' results joined in order."""
    from .. import __version__

    cols = {k: np.asarray(v, dtype=float) for k, v in columns.items()}
    n = len(next(iter(cols.values()))) if cols else 1
    chunk = chunk or CHUNK[kind]
    own = client is None
    if own:
        client = client_for(address, workers)
    try:
        parts = chunks(n, chunk) if cols else [(0, 1)]
        options = dict(options or {})
        if kind == "solve" and solver is None and cols:
            options["base"] = base_for(name, cols, options.get("dims"))
        futures = [client.submit(_task, kind, text, name, {k: c[a:b] for k, c in cols.items()},
                                 options, solver, pure=False)
                   for a, b in parts]
        if progress is not None:
            from distributed import as_completed

            size = {f.key: b - a for f, (a, b) in zip(futures, parts)}
            done = 0
            for fut in as_completed(futures):
                done += size[fut.key]
                progress(done)
        results = client.gather(futures)
    finally:
        if own:
            cluster = getattr(client, "cluster", None)
            client.close()
            if cluster is not None:
                cluster.close()
    for version, _ in results:
        if version != __version__:
            raise DaskError(f"--dask {address}: a worker runs momentum {version}, this is "
                            f"{__version__}: install the same version on every worker")
    return concat([r for _, r in results])


def base_for(path: str, cols: dict, dims=None) -> dict:
    """The variant the whole design is traced at (`choose_base`, here, where the file
    is): every chunk is solved with it as its base, so that each variant is decided as
    in the local run and its bits are the same."""
    from .batch import choose_base

    return choose_base(path, cols, dims)


def _task(kind: str, text: str, name: str, columns: dict, options: dict, solver=None):
    """On a worker: one chunk; returns (momentum's version there, the chunk's result)."""
    from .. import __version__

    if solver is not None:
        return __version__, solver(text, name, columns)
    if kind == "simulate":
        from .sim_batch import simulate_batch

        return __version__, simulate_batch(text, name, columns, **options)
    return __version__, _solve_text(text, name, columns, options.get("dims"),
                                    options.get("base"))


def _solve_text(text: str, name: str, columns: dict, dims=None, base=None):
    """`solve_batch` on a copy of the problem text written on the worker (same file name,
    so that messages name the file as the local run does)."""
    import tempfile

    from .batch import solve_batch

    with tempfile.TemporaryDirectory(prefix="momentum-dask-") as tmp:
        path = os.path.join(tmp, os.path.basename(name) or "problem.mom")
        with open(path, "w", encoding="utf-8", newline="") as fh:
            fh.write(text)
        res = solve_batch(path, columns, dims, base=base)
    status = getattr(res, "status", None)
    if status is not None and path != name:
        res.status = np.array([s.replace(path, name) if isinstance(s, str) else s
                               for s in status], dtype=object if status.dtype == object else None)
    return res


def concat(results: list):
    """One result from chunk results in order: per-variant arrays joined (an output a
    chunk lacks, e.g. one whose variants all failed, is NaN there), the rest from the
    first chunk."""
    first = results[0]
    if len(results) == 1:
        return first
    sizes = [len(r.status) for r in results]
    fields = _fields(first)
    out = {}
    for f in fields:
        vals = [getattr(r, f) for r in results]
        if isinstance(vals[0], dict) and f not in ("units", "display", "param_units") and all(
                isinstance(v, dict) for v in vals) and _per_variant(vals, sizes):
            keys = list(dict.fromkeys(k for v in vals for k in v))
            out[f] = {k: np.concatenate([np.asarray(v[k]) if k in v else
                                         np.full(m, math.nan) for v, m in zip(vals, sizes)])
                      for k in keys}
        elif f in ("units", "display", "param_units") and isinstance(vals[0], dict):
            merged = {}
            for v in vals:
                for k, u in v.items():
                    merged.setdefault(k, u)
            out[f] = merged
        elif isinstance(vals[0], np.ndarray) and all(
                isinstance(v, np.ndarray) and v.ndim >= 1 and len(v) == m
                for v, m in zip(vals, sizes)):
            out[f] = np.concatenate(vals)
        else:
            out[f] = vals[0]
    return type(first)(**out)


def _per_variant(vals: list, sizes: list) -> bool:
    return all(all(np.ndim(a) >= 1 and len(a) == m for a in v.values())
               for v, m in zip(vals, sizes))


def _fields(obj) -> tuple:
    import dataclasses

    if dataclasses.is_dataclass(obj):
        return tuple(f.name for f in dataclasses.fields(obj))
    return tuple(getattr(type(obj), "_fields"))
