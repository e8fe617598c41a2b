"""Sweeps: one problem solved for many values of its numbers, compiled once.

spec.py (the design: --vary grids, --sample draws) -> params.py (which numbers a file
lets vary) -> trace.py (build and compile once with traced numbers) -> kernel.py and
blocks.py (numpy kernels; linear, quadratic and Newton blocks for all variants) ->
batch.py (`solve_batch`, per-variant checks and the scalar fallback) -> output.py
(summary, CSV, JSON) -> command.py (`momentum sweep`). Beside them: sim_batch.py
(`--simulate`: one simulation per variant), dask_run.py (`--dask`: chunks on a
cluster), execute.py (which of these runs), plot.py (`--plot`), bench.py
(`momentum bench sweep`).
"""
