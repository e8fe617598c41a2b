"""Running one problem file through the pipeline, as a value the CLI can render.

`solve_source` and `check_source` never raise for a bad problem file: they return a
`FileResult` with diagnostics. Only a bug in momentum escapes as an exception.
"""
from __future__ import annotations

import sys
from dataclasses import field

from .diagnostics import Diagnostic, ExitCode, ProblemError
from .records import record
from .source import Source, Span
from .syntax import MAX_BYTES

# Bytes read from a file: one more than MAX_BYTES characters can take (4 bytes each),
# so that `parse` sees any file over the limit as too large, never cut short.
READ_LIMIT = 4 * MAX_BYTES + 1


@record
class FileResult:
    name: str
    status: str  # solved | checked | error | unreadable
    source: Source | None = None
    report: object = None
    diagnostics: list[Diagnostic] = field(default_factory=list)
    counts: dict | None = None

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
    with open(path, "rb") as fh:
        data = fh.read(READ_LIMIT)
    return decode_source(path, data)


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


def solve_source(source: Source, solve_all: bool = False, sig: int = 6,
                 precision: str = "float") -> FileResult:
    from .report.model import build_report
    from .scene import build
    from .solve import solve_scene
    from .syntax import parse

    try:
        with _NoCyclicGC():
            scene = build(parse(source))
            sol = solve_scene(scene, solve_all, precision=precision)
            _finite_answers(sol)
            _instant_phases(sol)
            rep = build_report(source.name, sol, sig)
        return FileResult(source.name, "solved", source, rep, list(sol.diagnostics))
    except ProblemError as exc:
        return FileResult(source.name, "error", source, None, list(exc.diagnostics))
    except RecursionError:  # `parse` bounds the depth; this is the last line of defence
        return _too_deep(source)


def _finite_answers(sol) -> None:
    """The last guard before anything is printed: an answer that is not a finite number
    (an overflow, a 0/0 the earlier checks missed) is an error at its `find` item, never
    a printed nan, inf or null."""
    import math

    spans = {f.name: f.span for f in sol.system.finds}
    bad = [Diagnostic("error", "not-finite", f"{name} is not a finite number (got {si!r}): "
                      "the data overflow or lose all precision in float64", spans.get(name),
                      ("check the magnitudes and units of the data it depends on",))
           for name, v, _u, si in sol.answers
           if not (math.isfinite(v) and math.isfinite(si))]
    if bad:
        raise ProblemError.many(bad)


def _instant_phases(sol) -> None:
    """A phase whose duration comes out exactly 0 (its end condition already holds at
    its start) is legal but odd: a warning at the phase says so."""
    import re

    sc = sol.system.scene
    phases = list(sc.transitions) + list(sc.burns) + list(sc.gains)
    named = dict(sol.values)
    named.update((name, si) for name, _v, _u, si in sol.answers)
    for name, v in sorted(named.items()):
        m = re.fullmatch(r"t@(\S+)->(\S+)", name)
        if m and v == 0:
            span = next((p.span for p in phases if (p.before, p.after) == m.groups()), None)
            sol.diagnostics.append(Diagnostic(
                "warning", "instant-phase", f"{name} = 0 s: the phase's end condition already "
                "holds at its start, so it takes no time and changes nothing", span))


def _too_deep(source: Source) -> FileResult:
    return FileResult(source.name, "error", source, None,
                      [Diagnostic("error", "too-deep", "expression too long or nested too deeply",
                                  None, ("split it into parts with `let`",))])


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


def _solve_job(job):
    """Worker: solve one (source, options) job; a bug becomes an internal FileResult."""
    source, solve_all, sig, precision = job
    try:
        return solve_source(source, solve_all, sig, precision)
    except Exception as exc:  # a bug in momentum: keep going, report it in order
        return FileResult(source.name, "internal", None, None, [Diagnostic(
            "error", "internal", f"internal error: {type(exc).__name__}: {exc} (this is a bug "
            "in momentum; rerun with --traceback and report it)")])


def solve_many(sources, solve_all: bool, sig: int, precision: str):
    """Solve sources in order, in parallel worker processes when there are many.

    Yields FileResults in the input order. Each file is independent, so with many
    files a fork-based pool on every core cuts the per-file cost; the parser is
    built first, so each worker inherits it.
    """
    import os

    sources = list(sources)
    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else \
        (os.cpu_count() or 1)
    if len(sources) < PARALLEL_MIN or cores < 2:
        for s in sources:
            yield _solve_job((s, solve_all, sig, precision))
        return
    import multiprocessing as mp
    from concurrent.futures import ProcessPoolExecutor
    from concurrent.futures.process import BrokenProcessPool

    from .syntax import parser

    parser()  # build (or load) once; forked workers share it
    try:
        ctx = mp.get_context("fork")
    except ValueError:
        ctx = None
    jobs = [(s, solve_all, sig, precision) for s in sources]
    done = 0
    if ctx is not None:
        pool = None
        try:
            pool = ProcessPoolExecutor(cores, mp_context=ctx, initializer=_worker_init,
                                       initargs=(os.getpid(),))
            for res in pool.map(_solve_job, jobs, chunksize=8):
                done += 1
                yield res
        except (BrokenProcessPool, OSError, RuntimeError):
            pass  # no worker processes here: finish in this one
        except BaseException:  # interrupted, or the reader went away: end the workers now
            _end_workers(mp)
            raise
        finally:
            if pool is not None:
                pool.shutdown(wait=done == len(jobs), cancel_futures=True)
                if done < len(jobs):
                    _end_workers(mp)
    for job in jobs[done:]:
        yield _solve_job(job)


def _end_workers(mp) -> None:
    """Kill the worker processes now (the run is ending: interrupted, or its output
    gone); the pool's manager thread, which sees them die, is kept from printing."""
    import threading

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
