"""Where a sweep runs: here or on Dask, a `solve` or a `simulate` per variant; its plot.

Stage: run. In: the problem file's path and text, the design's columns (SI, drawn once
here), `--simulate`, `--dask ADDRESS` and the simulation's options. Out: one result with
answers, units, status and params in variant order, whichever way it ran; and the
`--plot` checks and drawing. The `sweep` command calls these; no physics here.
"""
from __future__ import annotations


class RunError(Exception):
    """A usage error found while setting up the run; the message is one line."""


def check_dask(address: str | None) -> None:
    """Before any work: `--dask` needs dask.distributed installed."""
    if address is None:
        return
    if address != "local" and "://" not in address and ":" not in address:
        raise RunError(f"--dask {address!r}: give a scheduler address such as "
                       "tcp://host:8786, or 'local' for a cluster on this machine")
    try:
        import distributed  # noqa: F401
    except ImportError:
        raise RunError("--dask needs dask.distributed: pip install 'momentum-cli[dask]'") \
            from None


def check_plot(path: str | None, inputs, force: bool) -> None:
    """Before any work: `--plot` needs matplotlib, a known image type and a path that
    loses no data (an existing file only with --force)."""
    if not path:
        return
    try:
        from matplotlib.backends.backend_agg import FigureCanvasAgg
    except ImportError:
        raise RunError("--plot needs matplotlib: pip install 'momentum-cli[plot]'") from None
    from ..outputs import OutputError, check_path

    try:
        check_path(path, inputs, force, "--plot", set(FigureCanvasAgg.get_supported_filetypes()))
    except OutputError as exc:
        raise RunError(str(exc)) from None


def run(path: str, text: str, columns: dict, dims: dict | None = None, simulate: bool = False,
        dask: str | None = None, sim_options: dict | None = None, progress=None,
        chunk: int | None = None, workers: int | None = None):
    """The sweep's result. Locally: `solve_batch` (or `simulate_batch`). On Dask: the same
    per chunk on the workers, joined in order (identical to the local result). A name the
    file cannot vary, or a file that does not parse, is a RunError before any work."""
    from .batch import SweepError

    sim_options = dict(sim_options or {})
    try:
        _check_names(path, text, columns)
        if dask is not None:
            from .dask_run import DaskError, run as on_dask

            try:
                return on_dask("simulate" if simulate else "solve", text, path, columns, dask,
                               sim_options if simulate else {"dims": dims}, chunk,
                               workers, progress)
            except DaskError as exc:
                raise RunError(str(exc)) from None
        if simulate:
            from .sim_batch import simulate_batch

            return simulate_batch(text, path, columns, progress=progress, **sim_options)
        from .batch import solve_batch

        return solve_batch(path, columns, dims, progress=progress)
    except SweepError as exc:
        raise RunError(str(exc)) from None


def _check_names(path: str, text: str, columns: dict) -> None:
    """Every parameter is a `let` or a given number of the file (`bind` says which)."""
    from .. import syntax as S
    from ..diagnostics import ProblemError
    from ..source import Source
    from .batch import SweepError
    from .params import ParamError, bind

    try:
        bind(S.parse(Source(path, text)), list(columns), path)
    except ParamError as exc:
        raise SweepError(str(exc)) from None
    except ProblemError as exc:
        d = exc.diagnostics[0]
        where = f":{d.span.line}:{d.span.column}" if d.span else ""
        raise SweepError(f"{path}{where}: error: {d.message}") from None


def draw(result, design, path: str, force: bool, title: str | None = None) -> None:
    """`--plot`: answers against the grid parameters, or histograms for drawn ones."""
    from ..outputs import OutputError, write_drawing
    from ..units import si_label
    from .plot import draw as draw_plot

    params = list(getattr(design, "params", []))
    grid = [p.name for p in params if p.kind == "grid"]
    sampled = [p.name for p in params if p.kind != "grid"]
    units = {p.name: si_label(tuple(p.dim)) for p in params}
    try:
        write_drawing(path, lambda tmp: draw_plot(result, tmp, grid, sampled, units,
                                                  title=title), force, "--plot")
    except OutputError as exc:
        raise RunError(str(exc)) from None
