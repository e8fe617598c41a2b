"""The command-line interface (typer): solve / check. No physics here.

Parses flags, reads files, picks a renderer, and maps results to exit codes:
0 solved, 1 a problem in a file, 2 usage or unreadable file, 3 internal error,
130 interrupted. Heavy modules (rich, numpy) are imported only when needed.
"""
from __future__ import annotations

import os
import sys
from enum import Enum
from typing import List, Optional

import typer

from .diagnostics import Diagnostic, ExitCode

app = typer.Typer(
    name="momentum",
    help="Solve planar rigid-body impulse, momentum and impact problems written in the "
         "momentum problem language, and show the solution step by step.\n\n"
         "Exit codes: 0 solved, 1 a problem in a file (syntax, units, under-determined, "
         "inconsistent), 2 usage error or unreadable file, 3 internal error, 130 interrupted.",
    no_args_is_help=True,
    pretty_exceptions_enable=False,
    rich_markup_mode=None,
    context_settings={"help_option_names": ["-h", "--help"]},
)


class Precision(str, Enum):
    float = "float"
    refine = "refine"
    exact = "exact"


class Format(str, Enum):
    auto = "auto"
    rich = "rich"
    plain = "plain"
    json = "json"


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


def _pick_format(fmt: Format, json_flag: bool, plain: bool) -> str:
    if json_flag:
        return "json"
    if plain:
        return "plain"
    if fmt != Format.auto:
        return fmt.value
    return "rich" if sys.stdout.isatty() and os.environ.get("TERM") != "dumb" else "plain"


def _read_all(files: List[str]):
    """Yield (name, Source, None), or (name, None, FileResult) for a file that cannot be
    used, for each path; `-` (named `<stdin>`) is read once."""
    from .run import FileResult, SourceTextError, read_source

    if files.count("-") > 1:
        raise typer.BadParameter("'-' (standard input) may be given only once")
    stdin_data = None
    if "-" in files:
        if sys.stdin is None or sys.stdin.isatty():
            raise typer.BadParameter("'-' reads a problem from standard input, but standard "
                                     "input is a terminal")
        # bytes, decoded like a file's (not with the locale's encoding)
        buffer = getattr(sys.stdin, "buffer", None)
        stdin_data = buffer.read() if buffer is not None else sys.stdin.read()
    for path in files:
        name = "<stdin>" if path == "-" else path
        problem = None
        try:
            source = read_source(path, stdin_data)
        except SourceTextError as exc:
            yield name, None, FileResult(name, "error", exc.source, None, exc.diagnostics)
            continue
        except IsADirectoryError:
            problem = "is a directory, not a file"
        except FileNotFoundError:
            problem = "no such file"
        except PermissionError:
            problem = "permission denied"
        except OSError as exc:
            problem = exc.strerror or str(exc)
        if problem is not None:
            yield name, None, FileResult(name, "unreadable", None, None,
                                         [Diagnostic("error", "unreadable", problem)])
        else:
            yield name, source, None


def _safe_streams() -> None:
    """Text from a problem file that stdout's encoding lacks (a title with '—' under an
    ASCII locale) prints as a \\u escape instead of failing."""
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.reconfigure(errors="backslashreplace")
        except (AttributeError, ValueError, OSError):
            pass


def _is_utf8(stream) -> bool:
    return (getattr(stream, "encoding", None) or "").lower().replace("-", "").replace(
        "_", "") in ("utf8", "utf8sig")


def _print_diagnostics(res, err) -> None:
    for d in res.diagnostics:
        if res.source is None:
            err.write(f"{res.name}: {d.severity}: {d.message}\n")
        else:
            err.write(d.format(res.source) + "\n")


def _internal(name: str, exc: BaseException, traceback_flag: bool):
    from .run import FileResult

    if traceback_flag:
        raise exc
    return FileResult(name, "internal", None, None, [Diagnostic(
        "error", "internal", f"internal error: {type(exc).__name__}: {exc} (this is a bug in "
        "momentum; rerun with --traceback and report it)")])


def _render(report, mode: str, console, index: int, digits: int, simulation: bool):
    """Print one file's report as rich tables or plain text; returns the rich console
    (made once, on first use)."""
    if mode == "rich":
        if console is None:
            from rich.console import Console

            console = Console()
        if simulation:
            from .sim.output import render_rich as render
        else:
            from .report.rich_out import render
        render(report, console, digits)
        return console
    if simulation:
        from .sim.output import render_plain as render
    else:
        from .report.text import render
    if index:
        sys.stdout.write("\n")
    sys.stdout.write(render(report, digits))
    return console


@app.command()
def solve(
    files: List[str] = typer.Argument(..., metavar="FILE",
                                      help="Problem files (.mom); '-' reads standard input."),
    fmt: Format = typer.Option(Format.auto, "--format", "-f",
                               help="auto: rich on a terminal, plain when piped."),
    json_flag: bool = typer.Option(False, "--json", help="Print one JSON document."),
    plain: bool = typer.Option(False, "--plain", help="Deterministic plain text (the golden "
                                                      "format)."),
    quiet: bool = typer.Option(False, "--quiet", "-q", help="Print only `name = value unit`."),
    solve_all: bool = typer.Option(False, "--all", help="Solve every determined block, not only "
                                                        "those the `find` lines need."),
    digits: int = typer.Option(6, "--digits", "-p", min=1, max=17,
                               help="Significant figures in printed numbers."),
    precision: Precision = typer.Option(Precision.float, "--precision",
                                        help="Linear blocks in float64, float64 refined with "
                                             "exact residuals, or exact rationals."),
    traceback_flag: bool = typer.Option(False, "--traceback", help="Show Python tracebacks of "
                                                                   "internal errors."),
) -> None:
    """Solve problem files and print the solution step by step.

    \b
    Examples:
      momentum solve examples/seed_rod_drop_smooth.mom
      momentum solve --json examples/*.mom
      cat problem.mom | momentum solve -q -
    """
    from .run import solve_many

    mode = _pick_format(fmt, json_flag, plain)
    _safe_streams()
    out = sys.stdout
    results = []
    many = len(files) > 1
    items = list(_read_all(files))
    solved = (r for r in ())
    if not traceback_flag:  # many files: solved in parallel, reported in order
        solved = solve_many([s for _, s, r in items if r is None], solve_all, digits,
                            precision.value)
    try:
        worst = _solve_loop(items, solved, mode, quiet, many, digits, solve_all, precision,
                            traceback_flag, results)
    finally:
        solved.close()  # ends any worker processes still running
    if mode == "json":
        from . import __version__
        from .report.json_out import document

        out.write(document(results, __version__, not _is_utf8(out)))
    out.flush()
    raise typer.Exit(int(worst))


def _solve_loop(items, solved, mode, quiet, many, digits, solve_all, precision,
                traceback_flag, results) -> ExitCode:
    """Print (or collect, for JSON) each file's result in order; the worst exit code."""
    from .run import solve_source

    out, err = sys.stdout, sys.stderr
    console = None
    worst = ExitCode.OK
    for i, (name, source, res) in enumerate(items):
        if res is None and not traceback_flag:
            res = next(solved)
        elif res is None:
            try:
                res = solve_source(source, solve_all, digits, precision.value)
            except (KeyboardInterrupt, typer.Exit):
                raise
            except Exception as exc:  # --traceback: show the bug
                res = _internal(name, exc, traceback_flag)
        code = ExitCode.INTERNAL if res.status == "internal" else res.exit_code
        worst = max(worst, code)
        if mode == "json":
            from .report.json_out import result_dict

            results.append(result_dict(name, res.status if res.status != "internal" else "error",
                                       res.report, res.diagnostics))
            continue
        _print_diagnostics(res, err)
        if res.report is None:
            continue
        if quiet:
            from .report.text import render_quiet

            if many:
                out.write(f"==> {name} <==\n")
            out.write(render_quiet(res.report, digits))
        else:
            console = _render(res.report, mode, console, i, digits, simulation=False)
    return worst


@app.command()
def check(
    files: List[str] = typer.Argument(..., metavar="FILE",
                                      help="Problem files (.mom); '-' reads standard input."),
    json_flag: bool = typer.Option(False, "--json", help="Print one JSON document."),
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
    for name, source, res in _read_all(files):
        if res is None:
            try:
                res = check_source(source)
            except Exception as exc:
                res = _internal(name, exc, False)
        code = ExitCode.INTERNAL if res.status == "internal" else res.exit_code
        worst = max(worst, code)
        if json_flag:
            from .report.json_out import result_dict

            results.append(result_dict(name, res.status if res.status != "internal" else "error",
                                       None, res.diagnostics, res.counts))
            continue
        _print_diagnostics(res, err)
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
    digits: int = typer.Option(6, "--digits", "-p", min=1, max=17,
                               help="Significant figures in printed numbers."),
    traceback_flag: bool = typer.Option(False, "--traceback", help="Show Python tracebacks of "
                                                                   "internal errors."),
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
    from .sim.run_file import simulate_source

    if (csv or plot) and len(files) > 1:
        raise typer.BadParameter("--csv and --plot take one problem file")
    if plot:
        try:
            import matplotlib  # noqa: F401
        except ImportError:
            raise typer.BadParameter("--plot needs matplotlib: pip install "
                                     "'momentum-cli[plot]'") from None
    mode = _pick_format(fmt, json_flag, plain)
    _safe_streams()
    out, err = sys.stdout, sys.stderr
    worst = ExitCode.OK
    results = []
    console = None
    for i, (name, source, res) in enumerate(_read_all(files)):
        sim = None
        if res is None:
            progress = _ProgressBar(err) if err.isatty() and mode != "json" else None
            try:
                res, sim = simulate_source(source, rtol, dt, progress, not integrate)
            except (KeyboardInterrupt, typer.Exit):
                raise
            except Exception as exc:
                res = _internal(name, exc, traceback_flag)
            finally:
                if progress is not None:
                    progress.close()
        code = ExitCode.INTERNAL if res.status == "internal" else res.exit_code
        worst = max(worst, code)
        if sim is not None and csv:
            from .sim.output import csv_text

            with open(csv, "w", encoding="utf-8") as fh:
                fh.write(csv_text(sim))
        if sim is not None and plot:
            from .sim.output import plot as draw

            draw(sim, plot)
        if mode == "json":
            from .sim.output import json_result

            results.append(json_result(res.report, name, res.status if res.status != "internal"
                                       else "error", res.diagnostics))
            continue
        _print_diagnostics(res, err)
        if res.report is None:
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
) -> None:
    """Error against `solve` and wall time of the seed scenes at each tolerance.

    Every seed example with a `simulate` block is simulated at rtol 1e-3 ... 1e-12 and at
    fixed steps of 10 and 1 ms; one quantity is compared with what `solve` gives.

    \b
    Examples:
      momentum bench simulate
      momentum bench simulate --repeat 5 --plot simulate.png
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
    from .report.text import table as text_table

    sys.stdout.write("\n".join(text_table(HEADERS, table(rows))) + "\n")


def _on_signal(signum, _frame) -> None:
    """SIGTERM or SIGHUP: end the worker processes and this one now, with 128 + signal
    (a pool waiting for its workers would not stop promptly)."""
    mp = sys.modules.get("multiprocessing")
    if mp is not None:
        for child in mp.active_children():
            try:
                child.kill()
            except OSError:
                pass
    os._exit(128 + signum)


def _usable_environment() -> None:
    """Terminal sizes that are not positive whole numbers (`COLUMNS=0`) are ignored, so
    that rich does not draw into zero columns; signals end the run promptly."""
    import signal

    for var in ("COLUMNS", "LINES"):
        v = os.environ.get(var)
        if v is not None and not (v.strip().isdigit() and int(v) > 0):
            del os.environ[var]
    for name in ("SIGTERM", "SIGHUP"):
        if hasattr(signal, name):
            try:
                signal.signal(getattr(signal, name), _on_signal)
            except (ValueError, OSError):
                pass


def main() -> None:
    """Entry point of the `momentum` command: exit codes for output that cannot be
    written (a broken pipe ends quietly with 141, like other tools; a full disk or a
    closed standard output is one line and 3), interrupts and signals."""
    from .outputs import (GuardedStream, OutputFailed, OutputGone, silence_stdout,
                          stdout_is_closed)

    if stdout_is_closed():
        sys.stderr.write("momentum: error: standard output is closed\n")
        sys.exit(int(ExitCode.INTERNAL))
    _usable_environment()
    sys.stdout = GuardedStream(sys.stdout)
    try:
        try:
            # a fixed name: usage lines and shell completion (`_MOMENTUM_COMPLETE`) say
            # `momentum` also under `python -m momentum_cli`
            app(prog_name="momentum")
        finally:
            sys.stdout.flush()
    except KeyboardInterrupt:
        sys.exit(int(ExitCode.INTERRUPTED))
    except OutputGone:
        silence_stdout()
        sys.exit(141)
    except OutputFailed as exc:
        silence_stdout()
        sys.stderr.write(f"momentum: error: cannot write to standard output: {exc.reason}\n")
        sys.exit(int(ExitCode.INTERNAL))
