"""`momentum sweep`: the command's work between the CLI's options and the outputs.

In: the file, the design options and the output choices. Out: the summary on
standard output (or JSON / JSON lines), the CSV file, and an exit code: 0 when every
variant solved, 1 when some did not (they are counted in the summary), 2 for usage
errors (a bad design, a name the file has no `let` or given number for).
"""
from __future__ import annotations

import sys

from ..diagnostics import ExitCode


class UsageError(ValueError):
    """One line for the command line (exit code 2)."""


def run(file: str, vary, sample, count, seed, csv_path, json_flag: bool, jsonl: bool,
        digits: int, progress_factory=None, simulate: bool = False, dask: str | None = None,
        plot: str | None = None, force: bool = False, sim_options: dict | None = None,
        chunk: int | None = None) -> int:
    from .batch import SweepError, solve_batch
    from .output import json_document, summary_text, write_csv, write_jsonl
    from .spec import SpecError, parse_design

    try:
        design = parse_design(vary, sample, count, seed)
    except SpecError as exc:
        raise UsageError(str(exc)) from None
    if csv_path:
        from ..outputs import OutputError, check_path

        try:  # before any work: a path that would lose data is refused
            check_path(csv_path, [file], force, "--csv")
        except OutputError as exc:
            raise UsageError(str(exc)) from None
    columns = design.columns()
    dims = {p.name: p.dim for p in design.params}
    progress = progress_factory(design.size) if progress_factory else None
    try:
        if simulate or dask or plot:  # execute.py: --simulate, --dask, --plot
            result = _run_elsewhere(file, columns, dims, simulate, dask, plot, force,
                                    sim_options, chunk, progress)
        else:
            result = solve_batch(file, columns, dims,
                                 progress=progress if progress is not None else None)
    except SweepError as exc:
        raise UsageError(str(exc)) from None
    finally:
        if progress is not None:
            progress.close()
    if plot:
        from .execute import RunError, draw

        try:
            draw(result, design, plot, force, title=file)
        except RunError as exc:
            raise UsageError(str(exc)) from None
    out = sys.stdout
    if csv_path:
        from ..outputs import OutputError, write_stream

        try:
            write_stream(csv_path, lambda fh: write_csv(result, fh), force, "--csv")
        except OutputError as exc:
            raise UsageError(str(exc)) from None
        except OSError as exc:
            raise UsageError(f"--csv {csv_path}: {exc.strerror or exc}") from None
        if csv_path == "-":  # the CSV is standard output: the summary goes to stderr
            out = sys.stderr
    if jsonl:
        write_jsonl(result, out)
    elif json_flag:
        import json

        out.write(json.dumps(json_document(result, file), indent=1) + "\n")
    else:
        out.write(summary_text(result, file, digits))
    from .output import failed

    return int(ExitCode.PROBLEM if failed(result).any() else ExitCode.OK)


def _run_elsewhere(file, columns, dims, simulate, dask, plot, force, sim_options, chunk,
                   progress):
    """A sweep of simulations, or one on Dask (execute.py); --plot checked first."""
    from ..run import SourceTextError, read_source
    from .execute import RunError, check_dask, check_plot, run

    try:
        check_plot(plot, [file], force)
        check_dask(dask)
        try:
            text = read_source(file).text
        except (OSError, SourceTextError) as exc:
            raise RunError(f"{file}: cannot read: {getattr(exc, 'strerror', None) or exc}") \
                from None
        return run(file, text, columns, dims, simulate, dask, sim_options, progress, chunk)
    except RunError as exc:
        raise UsageError(str(exc)) from None
