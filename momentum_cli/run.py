"""Running one problem file through the pipeline, as a value the CLI can render.

`solve_source`, `check_source` and `simulate_source` never raise for a bad problem
file: they return a `FileResult` with diagnostics. Only a bug in momentum escapes as an
exception.
"""
from __future__ import annotations

import os
import sys

from .diagnostics import Diagnostic, ExitCode, ProblemError
from .records import field, record
from .source import Source, Span
from .syntax import MAX_BYTES

# Bytes read from a file: one more than MAX_BYTES characters can take (4 bytes each),
# so that `parse` sees any file over the limit as too large, never cut short.
READ_LIMIT = 4 * MAX_BYTES + 1
# read first: read(READ_LIMIT) allocates (and frees) an 80 MB buffer for every file,
# ~35 us each, while a batch's parent reads its files before any worker starts
FIRST_READ = 1 << 16


@record
class FileResult:
    name: str
    status: str  # solved | checked | error | unreadable
    source: Source | None = None
    report: object = None
    diagnostics: list[Diagnostic] = field(default_factory=list)
    counts: dict | None = None
    expects: list = field(default_factory=list)  # expectations.ExpectCheck: its `expect` lines

    @property
    def exit_code(self) -> ExitCode:
        if self.status == "unreadable":
            return ExitCode.USAGE
        if self.status == "error":
            return ExitCode.PROBLEM
        return ExitCode.OK


class SourceTextError(ProblemError):
    """A file that was read but is not UTF-8 text; `source` holds it with U+FFFD for
    the undecodable bytes, so that the diagnostic can show the line."""

    def __init__(self, source: Source, message: str, span: Span):
        super().__init__(message, span, code="encoding",
                         notes=["a problem file is UTF-8 text; re-save it as UTF-8"])
        self.source = source


def read_source(path: str, stdin_data: bytes | str | None = None) -> Source:
    """Read a problem file (`-` is standard input, given as `stdin_data`).

    Raises OSError if the file cannot be read, SourceTextError if it is not UTF-8.
    """
    if path == "-":
        return decode_source("<stdin>", stdin_data if stdin_data is not None else b"")
    return decode_source(path, _read_bytes(path))


_OPEN_FLAGS = os.O_RDONLY | getattr(os, "O_CLOEXEC", 0) | getattr(os, "O_BINARY", 0)


def _read_bytes(path: str) -> bytes:
    """Up to READ_LIMIT bytes of a file, through the raw descriptor: half the cost of a
    buffered file object (a batch's parent reads every file before any worker starts).
    A problem file's usual size comes in one read (no 80 MB buffer made), its end
    in a second; a pipe that gives its text in pieces is read to its end."""
    fd = os.open(path, _OPEN_FLAGS)
    try:
        data = os.read(fd, FIRST_READ)
        if not data:
            return data
        more = os.read(fd, FIRST_READ)
        if not more:
            return data
        parts, total = [data, more], len(data) + len(more)
        while total < READ_LIMIT:
            piece = os.read(fd, min(READ_LIMIT - total, 1 << 20))
            if not piece:
                break
            parts.append(piece)
            total += len(piece)
        return b"".join(parts)[:READ_LIMIT]
    finally:
        os.close(fd)


def decode_source(name: str, data: bytes | str) -> Source:
    """Problem text from a file's bytes: UTF-8, a leading byte order mark dropped.

    Text with NUL bytes (a binary file) or over the size limit is kept, with U+FFFD
    for undecodable bytes, for `parse` to refuse with its own message.
    """
    if isinstance(data, str):
        return Source(name, data.removeprefix("\ufeff"))
    data = data.removeprefix(b"\xef\xbb\xbf")
    if b"\x00" in data or len(data) >= READ_LIMIT:
        return Source(name, data.decode("utf-8", errors="replace"))
    try:
        return Source(name, data.decode("utf-8"))
    except UnicodeDecodeError as exc:
        good = data[: exc.start].decode("utf-8", errors="replace")
        line = good.count("\n") + 1
        span = Span(line, len(good) - good.rfind("\n"))
        raise SourceTextError(Source(name, data.decode("utf-8", errors="replace")),
                              f"not UTF-8 text: byte 0x{data[exc.start]:02x} cannot be decoded",
                              span) from None


class _NoCyclicGC:
    """Pause the cyclic garbage collector while one file is solved.

    The pipeline builds ~10^5 short-lived, acyclic objects for a large scene (reference
    counting frees them); the cyclic collector would rescan the growing heap again
    and again and make a 10x larger scene cost 16x. Measured: linear without it.
    """

    def __enter__(self):
        import gc

        self.was = gc.isenabled()
        gc.disable()

    def __exit__(self, *exc):
        import gc

        if self.was:
            gc.enable()
        return False


def _build_scene(source: Source, overrides=()):
    """Parse and build one file, with `--set` (name, value text) overrides of its `let`s."""
    from .scene import build
    from .syntax import parse

    doc = parse(source)
    if overrides:
        from .overrides import apply

        doc = apply(doc, overrides)
    return build(doc)


def solve_source(source: Source, solve_all: bool = False, sig: int = 6,
                 precision: str = "float", overrides=(), units: str = "file",
                 sensitivity: bool = False, lazy: bool = False) -> FileResult:
    """Solve one file; `overrides` are `--set` (name, value text) pairs for its `let`s.
    Its `expect` lines are checked (`FileResult.expects`), also when it does not solve.
    `sensitivity`: the report gets d answer / d given number (`--sensitivity`); `lazy`:
    its big lists made as they are read (model.Lazy: for a report rendered at once)."""
    from .report.model import build_report
    from .solve import solve_scene

    try:
        with _NoCyclicGC():
            scene = _build_scene(source, overrides)
            sol = solve_scene(scene, solve_all, precision=precision)
            _shed(sol, sensitivity)
            _instant_phases(sol)
            rep = build_report(source.name, sol, sig, units, lazy=lazy)
            if sensitivity:
                rep.sensitivities = _sensitivities(source, overrides, sol)
            checks = []
            if scene.expects:
                from .expectations import check_solution
                from .report.model import add_expectations

                checks = check_solution(scene.expects, sol)
                add_expectations(rep, checks, sig)
        return FileResult(source.name, "solved", source, rep, list(sol.diagnostics),
                          expects=checks)
    except ProblemError as exc:
        return _failed(source, list(exc.diagnostics))
    except RecursionError:  # `parse` bounds the depth; this is the last line of defence
        return _too_deep(source)


def _shed(sol, sensitivity: bool = False) -> None:
    """Free what only the solve reads (the structure's incidence sets and matching,
    one or two entries per equation) before the report is built: the report, the
    expectations and the sensitivities read the blocks and the redundant and
    undetermined equations, never these. Of the residual trees (one sum and one product
    an equation), only the impulse-momentum rows' are read again (the report's
    momentum-residual check, which then drops them); the others go (made again if
    something asks: the same tree, the same floats). The unknowns' sizes and error
    bounds (two entries an unknown, read by the answers, made already) go too, the sizes
    kept for `--sensitivity`, and a one-unknown block's 1x1 matrix and right side (the
    report shows a block's matrix from two unknowns on), and each answer's second form
    (`FindSpec.alt`, read once for the answers: T_lost as the sum of the contacts'
    losses): the report reuses their memory."""
    st = sol.structure
    st.incidence, st.match_eq, st.match_var, st.block_of_var = [], {}, {}, {}
    sol.errors = None
    if not sensitivity:
        sol.size = None
    for b in sol.blocks:
        if len(b.unknowns) == 1:
            b.matrix = b.rhs = None
    for f in sol.system.finds:
        f.alt = None
    if not sensitivity:  # the sensitivities read every residual
        for e in sol.system.equations:
            if not e.momentum_row:
                e._residual = None


def _sensitivities(source: Source, overrides, sol) -> dict:
    """The report's sensitivities section of a solved file (parsed again: the given
    numbers are the document's literals)."""
    from .report.sensitivity import section
    from .sensitivity import sensitivities
    from .syntax import parse

    doc = parse(source)
    if overrides:
        from .overrides import apply

        doc = apply(doc, overrides)
    return section(sensitivities(doc, sol))


def _failed(source: Source, diagnostics) -> FileResult:
    """A file that did not solve, with its `expect` lines checked against its errors."""
    from .expectations import check_error, scan_expects

    specs = scan_expects(source.text)
    return FileResult(source.name, "error", source, None, diagnostics,
                      expects=check_error(specs, diagnostics) if specs else [])


def _instant_phases(sol) -> None:
    """A phase whose duration comes out exactly 0 (its end condition already holds at
    its start) is legal but odd: a warning at the phase says so (the durations picked
    before sorting: a big scene's values are ~3 a body)."""

    sc = sol.system.scene
    phases = list(sc.transitions) + list(sc.burns) + list(sc.gains)
    for name, v in sorted((n, v) for n, v in sol.values.items()
                          if getattr(n, "kind", None) == "duration" and v == 0):
        span = next((p.span for p in phases
                     if f"{p.before}->{p.after}" == name.transition), None)
        sol.diagnostics.append(Diagnostic(
            "warning", "instant-phase", f"{name} = 0 s: the phase's end condition already "
            "holds at its start, so it takes no time and changes nothing", span))


def _too_deep(source: Source) -> FileResult:
    return _failed(source, [Diagnostic("error", "too-deep", "expression too long or nested "
                                       "too deeply", None, ("split it into parts with `let`",))])


def simulate_source(source: Source, rtol: float = 1e-9, dt: float | None = None,
                    progress=None, closed_forms: bool = True, overrides=(), **limits):
    """One file through `simulate`: (FileResult with `report` = the simulation's report
    dict, SimResult or None); never raises for a bad file. `overrides`: `--set`
    (name, value text) pairs for the file's `let`s; `limits`: `max_events`, `max_time`."""
    from .sim.integrate import simulate
    from .sim.output import build as build_report

    try:
        with _NoCyclicGC():
            scene = _build_scene(source, overrides)
            res = simulate(scene, rtol=rtol, dt=dt, progress=progress, closed_forms=closed_forms,
                           **limits)
            rep = build_report(source.name, res)
        return FileResult(source.name, "solved", source, rep, []), res
    except ProblemError as exc:
        return FileResult(source.name, "error", source, None, list(exc.diagnostics)), None
    except RecursionError:
        return _too_deep(source), None


def check_source(source: Source) -> FileResult:
    """Parse, build, compile and analyse without solving."""
    from .analyse import analyse
    from .compile import compile_scene
    from .scene import build
    from .syntax import parse

    try:
        scene = build(parse(source))
        system = compile_scene(scene)
        st = analyse(system)
    except ProblemError as exc:
        return FileResult(source.name, "error", source, None, list(exc.diagnostics))
    except RecursionError:
        return _too_deep(source)
    diags = list(system.notes.items)
    if st.under:
        names = sorted(st.under)
        shown = ", ".join(names[:8]) + (f" and {len(names) - 8} more" if len(names) > 8 else "")
        needed = set()
        from .expr import variables

        for f in system.finds:
            variables(f.expr, needed)
        missing = st.undetermined_for(sorted(needed))
        sev = "error" if missing else "note"
        msg = (f"under-determined: {', '.join(missing)} not determined" if missing else
               f"not determined (and not asked for): {shown}")
        where = next((f.span for f in system.finds if missing and
                      variables(f.expr, set()) & set(missing)), None)
        diags.append(Diagnostic(sev, "under-determined", msg, where))
    counts = dict(unknowns=len(system.unknowns), equations=len(system.equations),
                  blocks=len(st.blocks), redundant=len(st.redundant) + len(st.constant_eqs),
                  undetermined=len(st.under), undetermined_equations=len(st.under_eqs))
    status = "error" if any(d.severity == "error" for d in diags) else "checked"
    return FileResult(source.name, status, source, None, diags, counts)


PARALLEL_MIN = 48  # files in one call from which a second process pays for itself


@record
class Rendered:
    """A solved file's report as text (`solve_many`'s `render`, run where it was solved),
    with the report's checks (--strict reads them). A worker ships this instead of the
    report: a fifth of the bytes, and the parent neither rebuilds nor renders it.
    `fields`: for --json, the report's part of the result as JSON text
    (json_out.encoded_fields) instead of `text`. `parts`: the text as pieces to join
    with newlines (text.render_parts), written one by one, never joined whole."""
    text: str
    checks: list
    fields: dict | None = None
    parts: list | None = None


JOIN_LIMIT = 1 << 20  # characters: a report's pieces joined where it is solved


def _joined_if_small(parts: list):
    """text.render_parts' pieces as one text when they are small (the common file):
    one string to pickle and one write in the parent instead of ~50 of each; a big
    report stays in pieces (never held twice)."""
    if sum(map(len, parts)) + len(parts) > JOIN_LIMIT:  # summed in C: ~50 pieces a file
        return parts
    return "\n".join(parts)


def _solve_job(job, keep_report: bool = False):
    """Worker: solve one (source, options) job; a bug becomes an internal FileResult.
    With a `render` (the job's last item), a report is shipped as `Rendered` text;
    `keep_report`: it comes back lazy and unrendered instead (`solve_many`'s stream)."""
    source, solve_all, sig, precision, overrides, units, sensitivity, render = job
    try:
        with _NoCyclicGC():  # the report's text too: collected once it is all freed
            res = solve_source(source, solve_all, sig, precision, overrides, units,
                               sensitivity, lazy=render is not None)
            if render is not None and res.report is not None and not keep_report:
                made = render(res.report)
                checks = list(res.report.checks)
                if isinstance(made, list):
                    made = _joined_if_small(made)
                res.report = Rendered(made, checks) if isinstance(made, str) else \
                    Rendered("", checks, None, made) if isinstance(made, list) else \
                    Rendered("", checks, made)
                from .report.model import forget_diagram_index

                forget_diagram_index()  # the report is freed now, its diagrams with it
        return res
    except Exception as exc:  # a bug in momentum: keep going, report it in order
        return internal_result(source.name, exc)


def internal_result(name: str, exc: Exception) -> FileResult:
    """The result of a file whose solve or rendering met a bug in momentum (or a broken
    installation): one internal error, said the same wherever it happened."""
    if isinstance(exc, ModuleNotFoundError):  # the installation, not momentum, is broken
        return FileResult(name, "internal", None, None, [Diagnostic(
            "error", "internal", f"momentum's dependency {exc.name!r} is not installed in "
            f"this Python ({sys.executable}): reinstall momentum-cli with pip")])
    return FileResult(name, "internal", None, None, [Diagnostic(
        "error", "internal", f"internal error: {type(exc).__name__}: {exc} (this is a bug "
        "in momentum; rerun with --traceback and report it)")])


def solve_many(sources, solve_all: bool, sig: int, precision: str, overrides=(),
               units: str = "file", sensitivity: bool = False, render=None,
               stream: bool = False):
    """Solve sources in order, in parallel worker processes when there are many.

    Yields FileResults in the input order. Each file is independent, so with many
    files a fork-based worker per core cuts the per-file cost (run_pool routes the
    files: a family of variants to one worker, flows that may need scipy to one);
    the parser's tables are loaded first, so each worker inherits them. Files of a batch are often
    variants of one problem: each distinct statement is parsed once (statement_memo).
    `render` (report -> str, picklable): each report comes back as `Rendered` text,
    made by the worker. `stream` (with a `render`): a single file's report comes back
    lazy and unrendered, for the caller to write as it is made (text.iter_parts: the
    text is never held whole beside the solution), with the cyclic collector paused
    until the caller asks for the next result (it would walk the whole solution).
    """
    sources = list(sources)
    if len(sources) < 2:
        for s in sources:
            job = (s, solve_all, sig, precision, overrides, units, sensitivity, render)
            if stream and render is not None:
                with _NoCyclicGC():
                    yield _solve_job(job, keep_report=True)
            else:
                yield _solve_job(job)
        return
    from . import statement_memo

    try:
        yield from _solve_all(sources, solve_all, sig, precision, overrides, units,
                              sensitivity, render)
    finally:
        statement_memo.clear()


def _batch_job(job):
    """`_solve_job` for a file of a batch: its statements through statement_memo's
    table, which stays (in this process, or in the worker) for the next file."""
    from .statement_memo import hooked

    with hooked():
        return _solve_job(job)


def _solve_all(sources, solve_all, sig, precision, overrides, units, sensitivity, render):
    """`solve_many` for two or more files."""
    import os

    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else \
        (os.cpu_count() or 1)
    if len(sources) < PARALLEL_MIN or cores < 2:
        for s in sources:
            yield _batch_job((s, solve_all, sig, precision, overrides, units, sensitivity,
                              render))
        return
    import multiprocessing as mp

    from .syntax import _fast_parser

    _fast_parser()  # syntax_run's tables, loaded once for the workers (lark only if needed)
    try:
        ctx = mp.get_context("fork")
    except ValueError:
        ctx = None
    global _BATCH
    jobs = [(s, solve_all, sig, precision, overrides, units, sensitivity, render)
            for s in sources]
    done = 0
    if ctx is not None:
        from .run_pool import Worker, routed

        workers = []
        _before_fork()
        _BATCH = jobs  # the workers, forked after this, inherit the jobs: never pickled
        try:
            for _ in range(cores):
                workers.append(Worker(ctx, _batch_index, _worker_init, (os.getpid(),)))
            for res, shipped_bare in routed([s.text for s in sources], workers):
                if shipped_bare:
                    res.source = sources[done]
                done += 1
                yield res
        except (OSError, RuntimeError):
            pass  # no worker processes here, or one died: finish in this one
        except BaseException:  # interrupted, or the reader went away: end the workers now
            _end_workers(mp)
            raise
        finally:
            if workers and done < len(jobs):
                _end_workers(mp)
            for wk in workers:
                wk.close(ask=not WORKERS_KILLED)
            _BATCH = None
            import gc

            gc.unfreeze()
    for job in jobs[done:]:
        yield _batch_job(job)


_BATCH = None  # a pool's jobs, set in the parent before its workers are forked


def _batch_index(i: int):
    """Worker: `_batch_job` for job `i` of `_BATCH` (inherited from the parent at the
    fork), and whether the result comes without its source: the parent holds that
    Source already, so it is not pickled back (an internal error's result has none)."""
    job = _BATCH[i]
    res = _batch_job(job)
    if res.source is job[0]:
        res.source = None
        return res, True
    return res, False


def _before_fork() -> None:
    """Import what every worker needs and freeze the heap, once, before forking: the
    workers share these pages instead of each importing the pipeline again, and their
    cyclic collector never rescans the parser's and modules' ~10^5 long-lived objects
    (the collections of a batch cost ~5 % of its time otherwise)."""
    import gc

    from . import expectations, scene, solve  # noqa: F401
    from .report import model, text  # noqa: F401
    # what the seeds' files import along the way (each worker imported them again)
    from . import (contact_laws, flows, integration, lowered, massratio,  # noqa: F401
                   numeric_rank, regime_search, roots)
    from .laws import impulse_path  # noqa: F401
    from .report import diagram  # noqa: F401

    if sys.platform.startswith("linux"):
        try:
            import ctypes  # noqa: F401  (_worker_init's prctl)
        except ImportError:
            pass
    gc.freeze()


WORKERS_KILLED = False  # set once a pool's workers were killed: see guard.guarded


def _end_workers(mp) -> None:
    """Kill the worker processes now (the run is ending: interrupted, or its output
    gone, or its last result read); a thread that sees them die is kept from printing.

    A worker killed while writing a result leaves half a message in its pipe, never to
    be read: the run records the kill, and guard.guarded ends the process with os._exit
    (nothing is left to wait for, and no interpreter teardown to pay)."""
    global WORKERS_KILLED
    import threading

    WORKERS_KILLED = True
    threading.excepthook = lambda _args: None
    for child in mp.active_children():
        try:
            child.kill()
        except OSError:
            pass


def _worker_init(parent: int) -> None:
    """A worker ends with its parent however the parent dies: on Linux the kernel sends
    it SIGKILL (prctl PR_SET_PDEATHSIG); elsewhere, and as a second guard, a thread
    polls for a new parent. Ctrl-C is the parent's to handle."""
    import os
    import signal
    import threading
    import time

    signal.signal(signal.SIGINT, signal.SIG_IGN)
    for name in ("SIGTERM", "SIGHUP"):
        if hasattr(signal, name):
            signal.signal(getattr(signal, name), signal.SIG_DFL)
    if sys.platform.startswith("linux"):
        try:
            import ctypes

            libc = ctypes.CDLL(None, use_errno=True)
            libc.prctl(1, signal.SIGKILL, 0, 0, 0)  # PR_SET_PDEATHSIG
        except (OSError, AttributeError):
            pass
    if os.getppid() != parent:  # the parent died before prctl took effect
        os._exit(1)

    def watch():
        while True:
            time.sleep(0.5)
            if os.getppid() != parent:
                os._exit(1)

    threading.Thread(target=watch, daemon=True).start()
