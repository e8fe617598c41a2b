"""The command-line interface (typer): solve / check. No physics here.

Parses flags, reads files, picks a renderer, and maps results to exit codes:
0 solved, 1 a problem in a file, 2 usage or unreadable file, 3 internal error (or
standard output not writable), 130 interrupted, 141 broken pipe, 128+N signal N. Heavy modules (rich, numpy) are imported only when needed.
`solve`'s work is in solve_cmd.py (shared with the typer-free fastpath.py); the guards
around a run are in guard.py.
"""
from __future__ import annotations

import math
import os
import sys
from enum import Enum
from typing import List, Optional

import typer

from . import solve_cmd
from .diagnostics import Diagnostic, ExitCode
from .guard import _on_signal, _usable_environment, guarded  # noqa: F401
from .solve_cmd import (SOLVE_DEFAULTS, Color, Format, Precision,  # noqa: F401 (shared)
                        SolveFormat, Steps, Units, _Captured, _colored, _console, _expand,
                        _internal, _is_utf8, _overrides_for, _pick_format, _print_diagnostics,
                        _read_all, _render, _safe_streams, _solve_files, _solve_loop, _strict,
                        _title_of, _use_color, _write_output, run_solve)

# solve_cmd's helpers raise click's exceptions when typer runs them
solve_cmd.Exit, solve_cmd.BadParameter = typer.Exit, typer.BadParameter
_D = SOLVE_DEFAULTS

app = typer.Typer(
    name="momentum",
    help="Solve planar rigid-body impulse, momentum and impact problems written in the "
         "momentum problem language, and show the solution step by step.\n\n"
         "Exit codes: 0 solved, 1 a problem in a file (syntax, units, under-determined, "
         "inconsistent), 2 usage error or unreadable file, 3 internal error or standard output "
         "not writable, 130 interrupted, 141 broken pipe, 128+N signal N.",
    no_args_is_help=True,
    pretty_exceptions_enable=False,
    rich_markup_mode=None,
    context_settings={"help_option_names": ["-h", "--help"]},
)


def _version_callback(value: bool) -> None:
    if value:
        from . import __version__

        typer.echo(f"momentum {__version__}")
        raise typer.Exit()


@app.callback()
def _root(
    version: Optional[bool] = typer.Option(None, "--version", "-V", is_eager=True,
                                           callback=_version_callback,
                                           help="Print the version and exit."),
) -> None:
    """momentum: impulse, momentum and impact problems, solved step by step."""


# ---- options several commands share (a fresh OptionInfo for each command) -------------
SET_HELP = "Override a `let` constant: NAME=VALUE with its unit, e.g. --set v0='5 m/s' " \
           "(repeatable)."


def _set_option():
    return typer.Option(None, "--set", metavar="NAME=VALUE", help=SET_HELP)


def _strict_option():
    return typer.Option(False, "--strict", help="Warnings (a stated principle that does not "
                        "hold, a contact that would pull, precision lost) are errors: exit "
                        "code 1.")


def _color_option():
    return typer.Option(Color.auto, "--color", help="Colour: auto (on a terminal, unless "
                        "NO_COLOR; FORCE_COLOR forces it), always or never.")


@app.command()
def solve(
    files: List[str] = typer.Argument(..., metavar="FILE",
                                      help="Problem files (.mom); '-' reads standard input."),
    fmt: SolveFormat = typer.Option(_D["fmt"], "--format", "-f",
                                    help="auto: rich on a terminal, plain when piped (with "
                                         "--output: from its suffix, .md .tex .html .json); "
                                         "markdown, latex and html write one document."),
    json_flag: bool = typer.Option(_D["json_flag"], "--json", help="Print one JSON document."),
    plain: bool = typer.Option(_D["plain"], "--plain", help="Deterministic plain text (the golden "
                                                      "format)."),
    output: Optional[str] = typer.Option(_D["output"], "--output", "-o", metavar="FILE",
                                         help="Write the output to FILE (whole, or not at "
                                              "all) instead of standard output."),
    force: bool = typer.Option(_D["force"], "--force", help="Let --output overwrite an existing "
                                                      "file."),
    quiet: bool = typer.Option(_D["quiet"], "--quiet", "-q", help="Print only `name = value unit`."),
    solve_all: bool = typer.Option(_D["solve_all"], "--all", help="Solve every determined block, not only "
                                                        "those the `find` lines need."),
    digits: int = typer.Option(_D["digits"], "--digits", "-p", min=1, max=17,
                               help="Significant figures in printed numbers."),
    precision: Precision = typer.Option(_D["precision"], "--precision",
                                        help="Linear blocks in float64, float64 refined with "
                                             "exact residuals, or exact rationals."),
    traceback_flag: bool = typer.Option(_D["traceback_flag"], "--traceback", help="Show Python tracebacks of "
                                                                   "internal errors."),
    sets: Optional[List[str]] = _set_option(),
    jsonl: bool = typer.Option(_D["jsonl"], "--jsonl", help="Print one JSON object per file (a "
                                                      "result of --json) as soon as it is "
                                                      "solved."),
    strict: bool = _strict_option(),
    color: Color = _color_option(),
    steps: Optional[Steps] = typer.Option(_D["steps"], "--steps", help="brief: the principles, the "
                                          "equations with numbers, the answers and key checks "
                                          "(the default on a terminal); full: everything "
                                          "(matrices, conditioning, every check; the default "
                                          "of --plain and pipes)."),
    units: Units = typer.Option(_D["units"], "--units", help="The units numbers are shown "
                                "in: file (the unit system the problem is written in, angles "
                                "in degrees where it typed degrees), si or us (slug, ft, lb); "
                                "`find ... in UNIT` still wins. JSON numbers stay SI."),
    no_pager: bool = typer.Option(_D["no_pager"], "--no-pager", help="Never page: by default a "
                                  "derivation longer than the terminal goes through $PAGER "
                                  "(less -FRX), never when the output is piped."),
    sensitivity: bool = typer.Option(_D["sensitivity"], "--sensitivity",
                                     help="Also print d answer / d given for every answer and "
                                          "every given number of the file, ranked by the "
                                          "relative form (d ln answer / d ln given)."),
) -> None:
    """Solve problem files and print the solution step by step.

    \b
    Examples:
      momentum solve examples/seed_rod_drop_smooth.mom
      momentum solve --json examples/*.mom
      cat problem.mom | momentum solve -q -
    """
    run_solve(files, fmt, json_flag, plain, output, force, quiet, solve_all, digits, precision,
              traceback_flag, sets, jsonl, strict, color, steps, units, no_pager, sensitivity)


@app.command()
def check(
    files: List[str] = typer.Argument(..., metavar="FILE",
                                      help="Problem files (.mom); '-' reads standard input."),
    json_flag: bool = typer.Option(False, "--json", help="Print one JSON document."),
    strict: bool = _strict_option(),
    color: Color = _color_option(),
) -> None:
    """Parse, build and analyse problem files without solving them.

    Prints the counts of unknowns and equations and the under- or over-determined parts,
    and every error of every file.

    \b
    Examples:
      momentum check examples/*.mom
      momentum check --json problem.mom
    """
    from .run import check_source

    _safe_streams()
    out, err = sys.stdout, sys.stderr
    worst = ExitCode.OK
    results = []
    tint = _use_color(color, err, json_flag)
    for name, source, res in _read_all(files):
        if res is None:
            try:
                res = check_source(source)
            except Exception as exc:
                res = _internal(name, exc, False)
        res = _strict(res, strict)
        code = ExitCode.INTERNAL if res.status == "internal" else res.exit_code
        worst = max(worst, code)
        if json_flag:
            from .report.json_out import result_dict

            d = result_dict(name, res.status if res.status != "internal" else "error",
                            None, res.diagnostics, res.counts)
            d["title"] = _title_of(res)
            results.append(d)
            continue
        _print_diagnostics(res, err, tint)
        if res.counts is not None:
            c = res.counts
            out.write(f"{name}: {'ok' if res.status == 'checked' else 'error'}: "
                      f"{c['unknowns']} unknowns, {c['equations']} equations, {c['blocks']} "
                      f"blocks; {c['redundant']} redundant (checked after solving); "
                      f"{c['undetermined']} not determined\n")
    if json_flag:
        from . import __version__
        from .report.json_out import document

        out.write(document(results, __version__, not _is_utf8(out)))
    raise typer.Exit(int(worst))


@app.command()
def simulate(
    files: List[str] = typer.Argument(..., metavar="FILE",
                                      help="Problem files with a `simulate from S:` block; '-' "
                                           "reads standard input."),
    fmt: Format = typer.Option(Format.auto, "--format", "-f",
                               help="auto: rich on a terminal, plain when piped."),
    json_flag: bool = typer.Option(False, "--json", help="Print one JSON document."),
    plain: bool = typer.Option(False, "--plain", help="Deterministic plain text (the golden "
                                                      "format)."),
    rtol: float = typer.Option(1e-9, "--rtol", min=1e-14, max=0.1,
                               help="Relative tolerance of the adaptive integrator (DOP853)."),
    dt: Optional[float] = typer.Option(None, "--dt", min=1e-12,
                                       help="Fixed time step in seconds instead of --rtol "
                                            "(events are still located on the dense output)."),
    integrate: bool = typer.Option(False, "--integrate",
                                   help="Integrate every phase numerically, also where a closed "
                                        "form exists (to compare the two)."),
    csv: Optional[str] = typer.Option(None, "--csv", metavar="FILE",
                                      help="Write the time series (every step and event)."),
    plot: Optional[str] = typer.Option(None, "--plot", metavar="FILE.png",
                                       help="Draw positions, velocities and energy against "
                                            "time (needs the `plot` extra: matplotlib)."),
    force: bool = typer.Option(False, "--force", help="Let --csv and --plot overwrite an "
                                                      "existing file."),
    max_events: int = typer.Option(10000, "--max-events", min=1,
                                   help="Stop with an error after this many events (impacts, "
                                        "phase changes)."),
    max_time: Optional[float] = typer.Option(None, "--max-time", metavar="SECONDS",
                                             help="Stop with an error after this much "
                                                  "computing time per file."),
    timings: bool = typer.Option(False, "--timings", help="Put wall-clock times in the JSON "
                                                          "(left out so that runs compare equal)."),
    digits: int = typer.Option(6, "--digits", "-p", min=1, max=17,
                               help="Significant figures in printed numbers."),
    traceback_flag: bool = typer.Option(False, "--traceback", help="Show Python tracebacks of "
                                                                   "internal errors."),
    sets: Optional[List[str]] = _set_option(),
    strict: bool = _strict_option(),
    color: Color = _color_option(),
) -> None:
    """Simulate the motion of a scene over time, with only the effects it declares.

    Impacts are resolved by the same impulse solver as `solve`; between them the motion
    is advanced in closed form where the accelerations are constant or a body swings on
    a pin under gravity alone (elliptic functions), else integrated
    by scipy's solve_ivp (DOP853) with its events located on the dense output.

    \b
    Examples:
      momentum simulate examples/seed_pendulum_wall.mom
      momentum simulate --csv swing.csv --rtol 1e-12 examples/seed_pendulum_wall.mom
      momentum simulate --json examples/simulate/*.mom
    """
    from .outputs import OutputError, check_path, write_drawing, write_text
    from .run import simulate_source

    for opt, v in (("--rtol", rtol), ("--dt", dt), ("--max-time", max_time)):
        if v is not None and not (math.isfinite(v) and v > 0):
            raise typer.BadParameter(f"{opt} takes a finite positive number; got {v}")
    if (csv or plot) and len(files) > 1:
        raise typer.BadParameter("--csv and --plot take one problem file")
    if csv and plot and csv == plot and csv != "-":
        raise typer.BadParameter("--csv and --plot name the same file")
    if csv == "-" and plot == "-":
        raise typer.BadParameter("--csv and --plot cannot both write to standard output")
    if plot:
        try:
            import matplotlib  # noqa: F401
        except ImportError:
            raise typer.BadParameter("--plot needs matplotlib: pip install "
                                     "'momentum-cli[plot]'") from None
    mode = _pick_format(fmt, json_flag, plain)
    if "-" in (csv, plot) and mode == "json":
        raise typer.BadParameter("--json and --csv/--plot '-' both write to standard output")
    try:  # before the run: a path that would lose data, or cannot be written, is refused
        if csv:
            check_path(csv, files, force, "--csv")
        if plot:
            from matplotlib.backends.backend_agg import FigureCanvasAgg

            check_path(plot, files, force, "--plot",
                       set(FigureCanvasAgg.get_supported_filetypes()))
    except OutputError as exc:
        sys.stderr.write(f"momentum: error: {exc}\n")
        raise typer.Exit(int(ExitCode.USAGE)) from None
    _safe_streams()
    out, err = sys.stdout, sys.stderr
    worst = ExitCode.OK
    results = []
    console = _console(mode, color)
    tint = _use_color(color, err, plain or json_flag)
    to_stdout = "-" in (csv, plot)
    items = list(_read_all(files))
    overrides = _overrides_for(sets, [s for _, s, _ in items])
    for i, (name, source, res) in enumerate(items):
        sim = None
        if res is None:
            progress = _ProgressBar(err) if err.isatty() and mode != "json" else None
            try:
                res, sim = simulate_source(source, rtol, dt, progress, not integrate,
                                           overrides, max_events=max_events,
                                           max_time=max_time)
            except (KeyboardInterrupt, typer.Exit):
                raise
            except Exception as exc:
                res = _internal(name, exc, traceback_flag)
            finally:
                if progress is not None:
                    progress.close()
        res = _strict(res, strict)
        code = ExitCode.INTERNAL if res.status == "internal" else res.exit_code
        worst = max(worst, code)
        try:
            if sim is not None and csv:
                from .sim.output import csv_text

                write_text(csv, csv_text(sim), force, "--csv")
            if sim is not None and plot:
                from .sim.output import plot as draw

                write_drawing(plot, lambda path: draw(sim, path), force, "--plot")
        except OutputError as exc:
            err.write(f"momentum: error: {exc}\n")
            worst = max(worst, ExitCode.USAGE)
        if mode == "json":
            from .report.sim_json import json_result

            d = json_result(res.report, name, res.status if res.status != "internal"
                            else "error", res.diagnostics)
            if not timings:
                d.pop("seconds", None)
            if d.get("title") is None and _title_of(res) is not None:
                d["title"] = _title_of(res)
            results.append(d)
            continue
        _print_diagnostics(res, err, tint)
        if res.report is None or to_stdout:
            continue
        console = _render(res.report, mode, console, i, digits, simulation=True)
    if mode == "json":
        from . import __version__
        from .report.json_out import document

        out.write(document(results, __version__, not _is_utf8(out), key="simulations"))
    out.flush()
    raise typer.Exit(int(worst))


class _ProgressBar:
    """A rich progress bar on stderr for runs longer than half a second."""

    def __init__(self, stream):
        import time

        self.stream, self.began, self.bar, self.task = stream, time.perf_counter(), None, None
        self.end = None

    def __call__(self, t: float, t_end: float = float("inf")) -> None:
        """Called now and then with the simulated time and the stop time (inf: unknown)."""
        import math
        import time

        if self.bar is None:
            if time.perf_counter() - self.began < 0.5:
                return
            from rich.console import Console
            from rich.progress import Progress

            self.bar = Progress(console=Console(file=self.stream), transient=True)
            self.bar.start()
            self.task = self.bar.add_task("simulating",
                                          total=t_end if math.isfinite(t_end) else None)
        self.bar.update(self.task, completed=t, description=f"simulating: t = {t:.4g} s")

    def close(self) -> None:
        if self.bar is not None:
            self.bar.stop()


bench_app = typer.Typer(help="Benchmarks: what accuracy costs in time.", no_args_is_help=True,
                        rich_markup_mode=None)
app.add_typer(bench_app, name="bench")


@bench_app.command("accuracy")
def bench_accuracy(
    files: List[str] = typer.Argument(None, metavar="[FILE...]",
                                      help="Problem files to include (default: the seed and "
                                           "hard examples when run from the repository)."),
    sizes: str = typer.Option("10,100,1000,10000", "--sizes",
                              help="Ball-chain lengths, comma separated."),
    repeat: int = typer.Option(3, "--repeat", min=1, help="Runs per measurement (best kept)."),
    json_flag: bool = typer.Option(False, "--json", help="Print JSON."),
) -> None:
    """Time every precision mode and measure its error against the exact answer.

    \b
    Examples:
      momentum bench accuracy
      momentum bench accuracy --sizes 10,100 --json examples/seed_*.mom
    """
    import json

    from .bench import accuracy, default_files, default_problems

    try:
        ns = [int(s) for s in sizes.split(",") if s.strip()]
    except ValueError:
        raise typer.BadParameter("--sizes takes whole numbers separated by commas") from None
    if not files:
        files = default_files()
    for f in files:
        if not os.path.isfile(f):
            raise typer.BadParameter(f"no such file: {f}")
    err = sys.stderr
    rows = accuracy(default_problems(files, ns), repeat,
                    progress=lambda name, p: err.write(f"  {name}: {p}\n") if
                    err.isatty() else None)
    if json_flag:
        from .report.json_out import clean

        doc = [dict(problem=r.problem, unknowns=r.unknowns, precision=r.precision,
                    seconds=r.seconds, relative_error=r.rel_error, error_bound=r.error_bound,
                    note=r.note) for r in rows]
        sys.stdout.write(json.dumps({"schema_version": "1", "accuracy": clean(doc)},
                                    indent=2, allow_nan=False) + "\n")
        return
    from .numbers import fmt_num
    from .report.text import table

    out = []
    for r in rows:
        err_s = "failed: " + r.note if r.rel_error is None else fmt_num(r.rel_error, 2)
        out.append([r.problem, str(r.unknowns), r.precision,
                    "-" if r.rel_error is None else f"{r.seconds * 1e3:.3g}",
                    err_s, "-" if r.error_bound is None else fmt_num(r.error_bound, 2)])
    sys.stdout.write("\n".join(table(["problem", "unknowns", "precision", "time (ms)",
                                       "error vs exact", "estimated bound"], out)) + "\n")


@bench_app.command("simulate")
def bench_simulate(
    root: str = typer.Option(".", "--root", help="The repository root (where examples/ is)."),
    repeat: int = typer.Option(3, "--repeat", min=1, help="Runs per measurement (median kept)."),
    plot: Optional[str] = typer.Option(None, "--plot", metavar="FILE.png",
                                       help="Draw error against time (needs matplotlib)."),
    json_flag: bool = typer.Option(False, "--json", help="Print JSON."),
    markdown: bool = typer.Option(False, "--markdown",
                                  help="Print Markdown tables with the library versions."),
) -> None:
    """Error against `solve` and wall time of the seed scenes at each tolerance.

    Every seed example with a `simulate` block is simulated at rtol 1e-3 ... 1e-12 and at
    fixed steps of 10 and 1 ms; one quantity is compared with what `solve` gives.

    \b
    Examples:
      momentum bench simulate
      momentum bench simulate --repeat 5 --plot simulate.png
      momentum bench simulate --markdown
    """
    import json

    from .sim.bench import HEADERS, cases, run, table

    found = cases(root)
    if not found:
        raise typer.BadParameter(f"no seed examples under {root}/examples (use --root)")
    if plot:
        try:
            import matplotlib  # noqa: F401
        except ImportError:
            raise typer.BadParameter("--plot needs matplotlib: pip install "
                                     "'momentum-cli[plot]'") from None
    err = sys.stderr
    rows = run(found, repeat, progress=lambda c, s: err.write(f"  {c}: {s}\n")
               if err.isatty() else None)
    if plot:
        from .sim.bench import plot as draw

        draw(rows, plot)
    if json_flag:
        from .report.json_out import clean

        doc = [dict(scene=r.case, setting=r.setting, value=r.value, error=r.error, unit=r.unit,
                    seconds=r.seconds, steps=r.steps, evaluations=r.evaluations) for r in rows]
        sys.stdout.write(json.dumps({"schema_version": "1", "simulate": clean(doc)}, indent=2,
                                    allow_nan=False) + "\n")
        return
    if markdown:
        from .bench import versions
        from .sim.bench import markdown as md

        command = "momentum bench simulate" + (f" --repeat {repeat}" if repeat != 3 else "")
        sys.stdout.write(md(rows) + f"\nProduced by `{command} --markdown`: median of "
                         f"{repeat} run(s) per row, from the parsed file to the result "
                         f"(start-up excluded); {versions()}.\n")
        return
    from .report.text import table as text_table

    sys.stdout.write("\n".join(text_table(HEADERS, table(rows))) + "\n")


@bench_app.command("sweep")
def bench_sweep(
    files: List[str] = typer.Argument(None, metavar="[FILE...]",
                                      help="Problem files (default: the seed and sweep "
                                           "examples when run from the repository)."),
    count: int = typer.Option(10000, "--count", "-n", min=1,
                              help="Variants of each file for the batched sweep and numpy."),
    loop: int = typer.Option(100, "--loop", min=1,
                             help="Variants timed in the scalar-solve loop."),
    processes: int = typer.Option(5, "--processes", min=0,
                                  help="Variants timed as one process each (0: skip)."),
    seed: int = typer.Option(1, "--seed", help="Seed of the drawn values."),
    json_flag: bool = typer.Option(False, "--json", help="Print JSON."),
    markdown: bool = typer.Option(False, "--markdown",
                                  help="Print a Markdown table with the library versions."),
) -> None:
    """Variants per second: the batched sweep, numpy's batched solve, a scalar loop, and
    one process per variant.

    Every number a file gives (its `let`s, its states' given scalars, its impacts'
    `e[C]` and `mu[C]`) is drawn uniform within +-5 % of its value. numpy's limit is
    np.linalg.solve on the file's linear blocks stacked COUNT times (built first, only the
    solve timed).

    \b
    Examples:
      momentum bench sweep
      momentum bench sweep --count 100000 --markdown
    """
    import json

    from .sweep.bench import HEADERS, as_json, default_files, markdown as md, run, table

    given = list(files or [])
    if not files:
        files = default_files()
    if not files:
        raise typer.BadParameter("no problem files given, and no examples/seed_*.mom here")
    for f in files:
        if not os.path.isfile(f):
            raise typer.BadParameter(f"no such file: {f}")
    err = sys.stderr
    rows = run(files, count, loop, processes, seed,
               progress=lambda f, s: err.write(f"  {f}: {s}\n") if err.isatty() else None)
    if json_flag:
        from .bench import versions
        from .report.json_out import clean

        sys.stdout.write(json.dumps({"schema_version": "1", "versions": versions(),
                                     "sweep": clean(as_json(rows))}, indent=2,
                                    allow_nan=False) + "\n")
        return
    if markdown:
        from .bench import versions

        command = "momentum bench sweep" + "".join(
            f" {opt} {v}" for opt, v, d in (("--count", count, 10000), ("--loop", loop, 100),
                                            ("--processes", processes, 5), ("--seed", seed, 1))
            if v != d) + "".join(f" {f}" for f in given)
        load = f"; load average {os.getloadavg()[0]:.1f}" if hasattr(os, "getloadavg") else ""
        sys.stdout.write(md(rows) + f"\nProduced by `{command} --markdown`: {count:,} variants "
                         f"per file for the batched sweep and numpy, {loop} in the scalar "
                         f"loop, {processes} as processes{load}; {versions()}.\n")
        return
    from .report.text import table as text_table

    sys.stdout.write("\n".join(text_table(HEADERS, table(rows))) + "\n")


# ---- problem sets: test, expect, variants, grade; --set -------------------------------------

class _FileProgress:
    """A transient rich progress bar on stderr, shown once a run passes half a second."""

    def __init__(self, total: int, what: str):
        import time

        self.total, self.what, self.began, self.bar = total, what, time.perf_counter(), None

    def __call__(self, done: int) -> None:
        import time

        if self.bar is None:
            if time.perf_counter() - self.began < 0.5:
                return
            from rich.console import Console
            from rich.progress import Progress

            self.bar = Progress(console=Console(file=sys.stderr), transient=True)
            self.bar.start()
            self.task = self.bar.add_task(self.what, total=self.total)
        self.bar.update(self.task, completed=done)

    def close(self) -> None:
        if self.bar is not None:
            self.bar.stop()


@app.command()
def test(
    paths: List[str] = typer.Argument(None, metavar="[PATH...]",
                                      help="Problem files or folders (searched for *.mom "
                                           "recursively); default: the current folder."),
    pattern: Optional[str] = typer.Option(None, "-k", metavar="PATTERN",
                                          help="Only files whose path contains PATTERN (or "
                                               "matches it, with * ? [ ])."),
    junit: Optional[str] = typer.Option(None, "--junit-xml", metavar="FILE",
                                        help="Also write JUnit XML for CI systems."),
    json_flag: bool = typer.Option(False, "--json", help="Print one JSON document."),
    jsonl: bool = typer.Option(False, "--jsonl", help="Print one JSON object per file as "
                                                      "soon as it is done, then a summary."),
    simulate: bool = typer.Option(False, "--simulate",
                                  help="Also run `simulate` on simulate scenes (a `simulate` "
                                       "block and no `find`): they pass if they simulate."),
    sets: Optional[List[str]] = _set_option(),
    quiet: bool = typer.Option(False, "--quiet", "-q", help="Only failures and the summary."),
) -> None:
    """Run problem files as tests of their `expect` lines.

    One line per file, `file:line: expected ... got ...` for each expectation not met,
    and a last line `N passed, M failed`. A file without `expect` lines passes if it
    solves; a file that fails with an error no `expect error CODE` line names fails.
    Exit code: 0 all passed, 1 a failure or error, 2 usage.

    \b
    Examples:
      momentum test examples/
      momentum test -k rod --junit-xml report.xml problems/
      momentum test --jsonl problems/ | jq .
    """
    import json
    import time

    from .problemset import (
        CollectError,
        Outcome,
        collect,
        is_simulation,
        judge,
        outcome_dict,
        outcome_line,
        simulate_outcome,
        summary,
        summary_line,
    )
    from .run import solve_many

    if json_flag and jsonl:
        raise typer.BadParameter("--json and --jsonl: choose one")
    try:
        files = collect(paths, pattern)
    except CollectError as exc:
        raise typer.BadParameter(str(exc)) from None
    if not files:
        raise typer.BadParameter("no problem files (*.mom) found" +
                                 (f" matching -k {pattern}" if pattern else ""))
    _safe_streams()
    out = sys.stdout
    items = list(_read_all(files))
    overrides = _overrides_for(sets, [s for _, s, _ in items])
    sim = {name for name, s, r in items if s is not None and simulate and is_simulation(s.text)}
    solved = solve_many([s for n, s, r in items if r is None and n not in sim], False, 6,
                        "float", overrides)
    progress = _FileProgress(len(items), "testing") if sys.stderr.isatty() and not \
        (json_flag or jsonl) and len(items) > 1 else None
    outcomes: list[Outcome] = []
    began = time.perf_counter()
    try:
        for i, (name, source, res) in enumerate(items):
            start = time.perf_counter()
            if name in sim:
                try:
                    o = simulate_outcome(source, start)
                except Exception as exc:  # a bug in momentum: reported, the run goes on
                    o = judge(_internal(name, exc, False))
            else:
                if res is None:
                    res = next(solved)
                o = judge(res, time.perf_counter() - start)
            outcomes.append(o)
            if progress is not None:
                progress(i + 1)
            if jsonl:
                out.write(json.dumps(outcome_dict(o), allow_nan=False) + "\n")
                out.flush()
            elif not json_flag and not (quiet and o.outcome in ("passed", "skipped")):
                if progress is not None and progress.bar is not None:
                    progress.bar.console.print(outcome_line(o), markup=False, highlight=False)
                else:
                    out.write(outcome_line(o) + "\n")
    finally:
        if progress is not None:
            progress.close()
    counts = summary(outcomes)
    seconds = time.perf_counter() - began
    if junit:
        from .problemset import junit_xml

        try:
            with open(junit, "w", encoding="utf-8") as fh:
                fh.write(junit_xml(outcomes, counts))
        except OSError as exc:
            raise typer.BadParameter(f"--junit-xml {junit}: {exc.strerror or exc}") from None
    if json_flag:
        from . import __version__
        from .report.json_out import SCHEMA_VERSION, clean

        doc = {"schema_version": SCHEMA_VERSION, "momentum_version": __version__,
               "files": clean([outcome_dict(o) for o in outcomes]), "summary": counts}
        out.write(json.dumps(doc, allow_nan=False, indent=2, ensure_ascii=not _is_utf8(out))
                  + "\n")
    elif jsonl:
        out.write(json.dumps(dict(type="summary", **counts)) + "\n")
    else:
        out.write(summary_line(counts) + (f" in {seconds:.2f} s" if sys.stdout.isatty() else "")
                  + "\n")
    out.flush()
    if any(o.status == "internal" for o in outcomes):
        raise typer.Exit(int(ExitCode.INTERNAL))
    raise typer.Exit(int(ExitCode.PROBLEM if counts["failed"] or counts["error"] else
                         ExitCode.OK))


@app.command()
def expect(
    files: List[str] = typer.Argument(..., metavar="FILE", help="Problem files (.mom)."),
    write: bool = typer.Option(False, "--write", "-w",
                               help="Insert or refresh the `expect` lines in each file, in "
                                    "place (atomically), and show the diff."),
    digits: int = typer.Option(4, "--digits", "-p", min=1, max=15,
                               help="Significant figures of the expected values (the "
                                    "tolerance is half a unit in the last one)."),
    sets: Optional[List[str]] = _set_option(),
) -> None:
    """Print `expect` lines for the current answers; with --write, put them in the file.

    Without --write nothing is written. With it, only `expect` lines change (refreshed
    in place, an explicit `± TOL` or `within P %` kept; new lines after the last
    `expect` or `find` line); the file is replaced through a temporary file.

    \b
    Examples:
      momentum expect examples/seed_rod_drop_smooth.mom
      momentum expect --write problems/*.mom
    """
    from .run import solve_source
    from .snapshots import WriteError, answer_lines, diff, refreshed, write_atomic

    _safe_streams()
    out, err = sys.stdout, sys.stderr
    items = list(_read_all(files))
    overrides = _overrides_for(sets, [s for _, s, _ in items])
    worst = ExitCode.OK
    for name, source, res in items:
        if res is None:
            try:
                res = solve_source(source, False, 6, "float", overrides)
            except Exception as exc:
                res = _internal(name, exc, False)
        if res.status in ("unreadable", "internal"):
            _print_diagnostics(res, err)
            worst = max(worst, ExitCode.USAGE if res.status == "unreadable" else
                        ExitCode.INTERNAL)
            continue
        if not write:
            if len(items) > 1:
                out.write(f"==> {name} <==\n")
            out.writelines(f"expect {body}\n" for body in answer_lines(res, digits).values())
            continue
        new = refreshed(source.text, res, digits)
        if new == source.text:
            out.write(f"{name}: expect lines up to date\n")
            continue
        try:
            with open(name, "rb") as fh:
                raw = fh.read()
            old = raw.decode("utf-8")
            if old.startswith("\ufeff"):
                new = "\ufeff" + new
            write_atomic(name, new)
        except (WriteError, OSError, UnicodeDecodeError) as exc:
            err.write(f"{name}: error: {exc}\n" if not isinstance(exc, WriteError) else
                      f"{exc}\n")
            worst = max(worst, ExitCode.USAGE)
            continue
        out.write(diff(name, old, new))
    out.flush()
    raise typer.Exit(int(worst))


@app.command()
def variants(
    key: str = typer.Argument(..., metavar="KEY.mom", help="The problem file to vary."),
    vary: List[str] = typer.Option(..., "--vary", metavar="NAME=LO..HI",
                                   help="A `let` to draw uniformly from LO..HI, in the let's "
                                        "own unit or one given: v0=4..6 or 'v0=4..6 m/s'."),
    count: int = typer.Option(..., "--count", "-n", min=1, max=100000,
                              help="How many variants."),
    seed: int = typer.Option(..., "--seed", help="The random seed: the same seed gives the "
                                                  "same files on every machine."),
    out_dir: str = typer.Option(..., "--out", metavar="DIR", help="Folder for the variants."),
    digits: int = typer.Option(3, "--digits", "-p", min=1, max=12,
                               help="Significant figures of the drawn values."),
    expect_digits: int = typer.Option(4, "--expect-digits", min=1, max=15,
                                      help="Significant figures of the `expect` lines."),
) -> None:
    """Write COUNT variants of a problem with `let` values drawn, each with its `expect`
    lines, and an index CSV (variant, values, answers).

    \b
    Examples:
      momentum variants key.mom --vary v0=4..6 --vary m=1..3 --count 40 --seed 7 --out hw3
    """
    from .variants import VariantError, make_variants

    try:
        rows, failed = make_variants(key, vary, count, seed, out_dir, digits, expect_digits)
    except VariantError as exc:
        raise typer.BadParameter(str(exc)) from None
    for line in failed:
        sys.stderr.write(line + "\n")
    sys.stdout.write(f"{len(rows)} variants of {key} in {out_dir} (index: "
                     f"{out_dir.rstrip('/')}/index.csv)\n")
    raise typer.Exit(int(ExitCode.PROBLEM if failed else ExitCode.OK))


@app.command()
def sweep(
    file: str = typer.Argument(..., metavar="FILE", help="The problem file (.mom)."),
    vary: Optional[List[str]] = typer.Option(None, "--vary", metavar="NAME=LO..HI:N",
                                             help="A grid of N values from LO to HI "
                                                  "(several make a product): e=0..1:101, "
                                                  "'h=0.5..2:16 m'."),
    sample: Optional[List[str]] = typer.Option(None, "--sample", metavar="NAME~DIST(...)",
                                               help="Draws: uniform(lo, hi), normal(mean, "
                                                    "sd), lognormal(mean, sd), "
                                                    "triangular(lo, mode, hi), with units: "
                                                    "'m~normal(2 kg, 0.05 kg)'."),
    count: Optional[int] = typer.Option(None, "--count", "-n", help="How many draws."),
    seed: Optional[int] = typer.Option(None, "--seed", help="The random seed (numpy PCG64; "
                                                            "default 0)."),
    csv_path: Optional[str] = typer.Option(None, "--csv", metavar="FILE",
                                           help="One row per variant: parameters (SI), "
                                                "answers (the find's unit), status."),
    json_flag: bool = typer.Option(False, "--json", help="Print one JSON document."),
    jsonl: bool = typer.Option(False, "--jsonl", help="Print one JSON object per variant."),
    digits: int = typer.Option(6, "--digits", "-p", min=1, max=17,
                               help="Significant figures in the summary."),
    simulate: bool = typer.Option(False, "--simulate",
                                  help="Run the file's `simulate` block for each variant and "
                                       "sweep its outputs (stop time, impacts, energy lost, "
                                       "each body's final state)."),
    rtol: float = typer.Option(1e-9, "--rtol", min=1e-14, max=0.1,
                               help="With --simulate: the integrator's relative tolerance."),
    dask: Optional[str] = typer.Option(None, "--dask", metavar="ADDRESS",
                                       help="Run the variants in chunks on a Dask cluster: "
                                            "tcp://host:8786, or 'local' for a LocalCluster "
                                            "here (needs the `dask` extra)."),
    chunk: Optional[int] = typer.Option(None, "--chunk", min=1,
                                        help="With --dask: variants per task (default 50000; "
                                             "500 with --simulate)."),
    plot: Optional[str] = typer.Option(None, "--plot", metavar="FILE.png",
                                       help="Draw each answer against the --vary parameter, or "
                                            "its histogram for --sample (needs the `plot` "
                                            "extra: matplotlib)."),
    force: bool = typer.Option(False, "--force", help="Let --csv and --plot overwrite an existing file."),
) -> None:
    """Solve a problem for many values of its `let` constants (or given numbers:
    `rod.y@1`, `e[A]`), compiled once and solved as arrays; summarise every answer.

    \b
    Examples:
      momentum sweep examples/seed_oblique_particles.mom --vary e=0..1:101 --csv e.csv
      momentum sweep examples/seed_rod_drop_smooth.mom --sample 'e[A]~uniform(0.5, 0.7)' \\
          --sample 'rod.y@1~normal(1 m, 0.05 m)' --count 100000 --seed 1
      momentum sweep examples/sweep/bounce_height.mom --simulate \\
          --sample 'e~uniform(0.6, 0.8)' --count 1000 --plot bounce.png
      momentum sweep examples/seed_rod_drop_smooth.mom --vary e[A]=0..1:1001 --dask local
    """
    from .sweep.command import UsageError, run

    if json_flag and jsonl:
        raise typer.BadParameter("--json and --jsonl ask for different outputs; give one")
    _safe_streams()
    bar = (lambda total: _FileProgress(total, "variants")) \
        if sys.stderr.isatty() and not (json_flag or jsonl) else None
    try:
        code = run(file, vary or [], sample or [], count, seed, csv_path, json_flag, jsonl,
                   digits, bar, simulate, dask, plot, force, {"rtol": rtol}, chunk)
    except UsageError as exc:
        sys.stderr.write(f"momentum sweep: error: {exc}\n")
        raise typer.Exit(int(ExitCode.USAGE)) from None
    sys.stdout.flush()
    raise typer.Exit(code)


@app.command()
def grade(
    key: List[str] = typer.Argument(..., metavar="KEY_PATH",
                                    help="The key: problem files or folders (*.mom)."),
    answers: str = typer.Option(..., "--answers", metavar="CSV",
                                help="student, problem, quantity, value, unit (unit "
                                     "optional: the key's)."),
    rel: Optional[float] = typer.Option(None, "--rel", metavar="PERCENT",
                                        help="Relative tolerance in percent for every "
                                             "quantity (default: each `expect` line's own; "
                                             "1 % for quantities without one)."),
    csv_out: Optional[str] = typer.Option(None, "--csv", metavar="FILE",
                                          help="Write one row per student and quantity."),
    json_flag: bool = typer.Option(False, "--json", help="Print one JSON document."),
    fmt: str = typer.Option("auto", "--format", "-f", help="auto | rich | plain."),
) -> None:
    """Grade students' answers against a key: right, rounding, sign error, unit slip,
    wrong or missing; a table per student and per problem, and class statistics.

    \b
    Examples:
      momentum grade examples/problem-set --answers examples/problem-set/answers.csv
      momentum grade hw3/ --answers submitted.csv --csv grades.csv
    """
    import json

    from .grading import GradeError, grade_all, to_csv, to_json
    from .problemset import CollectError, collect

    try:
        files = collect(key)
    except CollectError as exc:
        raise typer.BadParameter(str(exc)) from None
    if not files:
        raise typer.BadParameter("no key files (*.mom) found")
    _safe_streams()
    try:
        result = grade_all(files, answers, rel)
    except GradeError as exc:
        raise typer.BadParameter(str(exc)) from None
    for line in result.key_errors + result.warnings:
        sys.stderr.write(line + "\n")
    if csv_out:
        with open(csv_out, "w", encoding="utf-8", newline="") as fh:
            fh.write(to_csv(result))
    if json_flag:
        from . import __version__

        sys.stdout.write(json.dumps(dict(to_json(result), momentum_version=__version__),
                                    indent=2, allow_nan=False) + "\n")
    elif fmt == "rich" or (fmt == "auto" and sys.stdout.isatty()):
        from .report.grades import render_rich

        render_rich(result)
    else:
        from .report.grades import render_plain

        sys.stdout.write(render_plain(result))
    raise typer.Exit(int(ExitCode.PROBLEM if result.key_errors else ExitCode.OK))


def main() -> None:
    """The typer application inside the guards (the `momentum` command is __main__.main,
    which tries the fast path first)."""
    guarded(lambda: app(prog_name="momentum"))
