"""`solve`'s work without the command-line parser: the options' defaults, reading,
solving, printing, exit codes. In: the parsed options (from typer's `solve` in cli.py,
or from fastpath.py's small parser). Out: printed results and an `Exit(code)`.

Imports neither typer nor click, so that a one-shot `solve` starts quickly; cli.py
installs click's `Exit` and `BadParameter` here in place of the stand-ins below.
"""
from __future__ import annotations

import os
import sys
from enum import Enum

from .diagnostics import Diagnostic, ExitCode


class Exit(Exception):
    """Stand-in for typer.Exit (replaced by it when cli.py is loaded)."""

    def __init__(self, code: int = 0):
        super().__init__(code)
        self.exit_code = code


class BadParameter(Exception):
    """Stand-in for typer.BadParameter (replaced by it when cli.py is loaded)."""


class Precision(str, Enum):
    float = "float"
    refine = "refine"
    exact = "exact"


class Format(str, Enum):
    auto = "auto"
    rich = "rich"
    plain = "plain"
    json = "json"


class SolveFormat(str, Enum):
    """`solve`'s outputs: the terminal and data formats, and the documents."""
    auto = "auto"
    rich = "rich"
    plain = "plain"
    json = "json"
    markdown = "markdown"
    latex = "latex"
    html = "html"


class Color(str, Enum):
    auto = "auto"
    always = "always"
    never = "never"


class Steps(str, Enum):
    brief = "brief"
    full = "full"


class Units(str, Enum):
    si = "si"
    us = "us"
    file = "file"

# `solve`'s option defaults: typer's `solve` (cli.py) and the fast path both take them
# from here (tests/test_fastpath.py checks the typer command against this table).
SOLVE_DEFAULTS = dict(fmt=SolveFormat.auto, json_flag=False, plain=False, output=None,
                      force=False, quiet=False, solve_all=False, digits=6,
                      precision=Precision.float, traceback_flag=False, sets=None,
                      jsonl=False, strict=False, color=Color.auto, steps=None,
                      units=Units.file, no_pager=False, sensitivity=False)


def _pick_format(fmt: Format, json_flag: bool, plain: bool) -> str:
    asked = [n for n, on in (("--json", json_flag), ("--plain", plain),
                             (f"--format {fmt.value}", fmt != Format.auto)) if on]
    if len(asked) > 1:
        raise BadParameter(f"{' and '.join(asked)} ask for different outputs; give one")
    if json_flag:
        return "json"
    if plain:
        return "plain"
    if fmt != Format.auto:
        return fmt.value
    return "rich" if sys.stdout.isatty() and os.environ.get("TERM") != "dumb" else "plain"


def _read_all(files: list[str]):
    """Yield (name, Source, None), or (name, None, FileResult) for a file that cannot be
    used, for each path; `-` (named `<stdin>`) is read once."""
    from .run import FileResult, SourceTextError, read_source

    files = _expand(files)
    if files.count("-") > 1:
        raise BadParameter("'-' (standard input) may be given only once")
    stdin_data = None
    if "-" in files:
        if sys.stdin is None or sys.stdin.isatty():
            raise BadParameter("'-' reads a problem from standard input, but standard "
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


def _expand(files: list[str]) -> list[str]:
    """A directory argument means the `*.mom` files under it (recursively, sorted)."""
    out: list[str] = []
    for f in files:
        if f != "-" and os.path.isdir(f):
            from pathlib import Path  # here: a one-shot solve of a file never needs it

            found = sorted(str(p) for p in Path(f).rglob("*.mom") if p.is_file())
            if not found:
                raise BadParameter(f"{f} is a directory with no .mom files in it")
            out.extend(found)
        else:
            out.append(f)
    return out


def _use_color(color: Color, stream, deterministic: bool = False) -> bool:
    """--color, else NO_COLOR (off), else FORCE_COLOR (on), else whether `stream` is a
    terminal (and not TERM=dumb). `deterministic` (--plain, --json asked for): only
    --color always colours."""
    if color == Color.always:
        return True
    if deterministic or color == Color.never or os.environ.get("NO_COLOR"):
        return False
    if os.environ.get("FORCE_COLOR") not in (None, "", "0"):
        return True
    try:
        return stream.isatty() and os.environ.get("TERM") != "dumb"
    except (AttributeError, ValueError):
        return False


_SEVERITY_COLOR = {"error": "1;31", "warning": "1;35", "note": "1;36"}


def _colored(line: str, severity: str, on: bool) -> str:
    """`file:line:col: error: ...` with the location bold and the severity coloured."""
    if not on:
        return line
    head, sep, rest = line.partition(f" {severity}: ")
    if not sep:
        return line
    return (f"\x1b[1m{head}\x1b[0m \x1b[{_SEVERITY_COLOR.get(severity, '1')}m{severity}:"
            f"\x1b[0m {rest}")


def _strict(res, strict: bool):
    """With --strict, a result's warnings (diagnostics and warning checks) become errors:
    its exit code is 1 and each warning is shown as an error."""
    if not strict or res.status not in ("solved", "checked"):
        return res
    checks = []
    rep = res.report
    if rep is not None:
        raw = rep["checks"] if isinstance(rep, dict) else getattr(rep, "checks", [])
        checks = [c for c in raw if (c["status"] if isinstance(c, dict) else c.status)
                  == "warning"]
    warned = [d for d in res.diagnostics if d.severity == "warning"]
    if not warned and not checks:
        return res
    diags = [Diagnostic("error", d.code, d.message + " (--strict)", d.span, d.notes, d.caret)
             if d.severity == "warning" else d for d in res.diagnostics]
    for c in checks:
        name, detail = (c["name"], c["detail"]) if isinstance(c, dict) else (c.name, c.detail)
        diags.append(Diagnostic("error", "strict", f"check {name}: {detail} (--strict: a "
                                "warning is an error)"))
    res.diagnostics = diags
    res.status = "error"
    return res


def _title_of(res):
    """The file's `problem` title, also for a file with errors (from its text)."""
    import re

    if res.source is None:
        return None
    m = re.search(r'^[ \t]*problem[ \t]+"([^"\n]*)"', res.source.text, re.M)
    return m.group(1) if m else None


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


def _print_diagnostics(res, err, color: bool = False) -> None:
    for d in res.diagnostics:
        if res.source is None:
            text = f"{res.name}: {d.severity}: {d.message}"
        else:
            text = d.format(res.source)
        first, nl, rest = text.partition("\n")
        err.write(_colored(first, d.severity, color) + nl + rest + "\n")


def _internal(name: str, exc: BaseException, traceback_flag: bool):
    from .run import FileResult

    if traceback_flag:
        raise exc
    return FileResult(name, "internal", None, None, [Diagnostic(
        "error", "internal", f"internal error: {type(exc).__name__}: {exc} (this is a bug in "
        "momentum; rerun with --traceback and report it)")])


def _console(mode: str, color: Color):
    """The rich console for the rich format (None for the others), coloured as asked."""
    if mode != "rich":
        return None
    from .report.console import make_console

    return make_console(color.value)


def _render(report, mode: str, console, index: int, digits: int, simulation: bool,
            detail: str = "full", failed: list | None = None):
    """Print one file's report as rich tables or plain text; returns the rich console
    (made once, on first use). `detail`: brief or full (solve's --steps). The full plain
    text is written as it is made; `failed` (a list): an exception raised while making
    it is put there (the text made before it is written) instead of raised."""
    if mode == "rich":
        if console is None:
            console = _console(mode, Color.auto)
        if simulation:
            from .report.sim_rich import render
            render(report, console, digits)
        else:
            from .report.rich_out import render
            render(report, console, digits, detail=detail)
        return console
    if index:
        sys.stdout.write("\n")
    if simulation:
        from .report.sim_text import render
        sys.stdout.write(render(report, digits))
    else:
        from .report import text

        if detail != "full":
            _write_text(sys.stdout, text.render(report, digits, detail=detail))
            return console
        if failed is not None and \
                (report.counts or {}).get("equations", 0) >= FORK_MIN_EQUATIONS:
            from . import forked_text

            if forked_text.write(sys.stdout, report, digits, failed, _write_text):
                return console
        parts = text.iter_parts(report, digits)
        _write_text(sys.stdout, parts if failed is None else text.until_failure(parts, failed))
    return console


WRITE_CHUNK = 1 << 20  # characters
# a plain report from which its text is made by two processes (forked_text): below it the
# text costs less than ~30 ms, not worth a fork
FORK_MIN_EQUATIONS = 2000


def _write_text(out, text) -> None:
    """Write `text` in pieces of about WRITE_CHUNK characters: a text stream encodes what
    it is given at once, so a 100 MB report written whole costs another 100 MB of bytes. A
    list (or an iterator: text.iter_parts) is text.render_parts' pieces, written with
    newlines between, never joined whole: runs of small pieces are joined up to
    WRITE_CHUNK characters and written at once (a big report has 10^5 pieces: a write
    each cost more than the joins)."""
    if isinstance(text, str):
        _write_long(out, text)
        return
    run: list = []  # the pieces not written yet
    size = 0  # their characters, a newline each included
    started = False  # a piece was written: the next one follows a newline
    for part in text:
        if isinstance(part, str):
            run.append(part)
            size += len(part) + 1
            if size < WRITE_CHUNK:
                continue
            part = None
        if run:
            if started:
                out.write("\n")
            _write_long(out, "\n".join(run))
            run, size, started = [], 0, True
        if part is not None:  # a list in the list: its pieces, newlines between
            if started:
                out.write("\n")
            _write_text(out, part)
            started = True
    if run:
        if started:
            out.write("\n")
        _write_long(out, "\n".join(run))


def _write_long(out, text: str) -> None:
    """`text` in writes of at most WRITE_CHUNK characters."""
    if len(text) <= WRITE_CHUNK:
        out.write(text)
        return
    for i in range(0, len(text), WRITE_CHUNK):
        out.write(text[i:i + WRITE_CHUNK])


def run_solve(files, fmt=SolveFormat.auto, json_flag=False, plain=False, output=None,
              force=False, quiet=False, solve_all=False, digits=6, precision=Precision.float,
              traceback_flag=False, sets=None, jsonl=False, strict=False, color=Color.auto,
              steps=None, units=Units.file, no_pager=False, sensitivity=False) -> None:
    """The `solve` command once its options are parsed; ends with `Exit(code)`."""
    from .pager import paged

    from .report.formats import output_format

    if fmt == SolveFormat.auto and output and not (json_flag or plain or jsonl):
        fmt = SolveFormat(output_format(output))
    mode = "json" if jsonl else _pick_format(fmt, json_flag, plain)
    sensitivity = sensitivity and (mode == "json" or not quiet)  # -q prints answers only
    _safe_streams()
    detail = (steps or (Steps.brief if mode == "rich" else Steps.full)).value
    view = dict(units=units.value, detail=detail, sensitivity=sensitivity)
    screen = None
    if output is not None:
        from .outputs import OutputError, check_path

        try:  # before any work: a path that would lose data is refused
            check_path(output, files, force, "--output")
        except OutputError as exc:
            sys.stderr.write(f"momentum: error: {exc}\n")
            raise Exit(int(ExitCode.USAGE)) from None
        screen, sys.stdout = sys.stdout, _Captured()
    try:
        with paged(enabled=output is None and not no_pager and mode in ("rich", "plain")
                   and not quiet, color=color != Color.never):
            _solve_files(files, mode, quiet, digits, solve_all, precision, traceback_flag, sets,
                         jsonl, strict, color, plain or json_flag, view)
    except Exit as done:
        if output is None:
            raise
        worst = max(int(done.exit_code), int(_write_output(output, screen, force)))
        raise Exit(worst) from None


def _solve_files(files, mode, quiet, digits, solve_all, precision, traceback_flag, sets,
                 jsonl, strict, color, deterministic, view) -> None:
    """`solve`'s work: read, solve in order (in parallel for many), print, exit code."""
    from .run import solve_many

    sensitivity = view["sensitivity"]
    # one plain full report: written as it is made from the lazy report (never whole)
    stream = mode == "plain" and not quiet and view["detail"] == "full"
    out = sys.stdout
    results: list = []
    if mode == "json" and not jsonl:  # streamed: one result held at a time
        from . import __version__
        from .report.json_out import DocumentStream

        results = DocumentStream(out, __version__, not _is_utf8(out))
    many = len(files) > 1
    items = list(_read_all(files))
    overrides = _overrides_for(sets, [s for _, s, _ in items])
    solved = (r for r in ())
    if not traceback_flag:  # many files: solved in parallel, reported in order
        solved = solve_many([s for _, s, r in items if r is None], solve_all, digits,
                            precision.value, overrides, view["units"], sensitivity,
                            _text_renderer(mode, quiet, digits, view["detail"], jsonl,
                                           not _is_utf8(out), many), stream=stream)
    try:
        worst = _solve_loop(items, solved, mode, quiet, many, digits, solve_all, precision,
                            traceback_flag, results, strict, color, deterministic,
                            overrides, jsonl, view, sensitivity)
    finally:
        solved.close()  # ends any worker processes still running
    if mode == "json" and not jsonl:
        results.close()
    elif mode in ("markdown", "latex", "html") and results:
        from .report.formats import render_document

        out.write(render_document(mode, results, digits, view["detail"]))
    out.flush()
    raise Exit(int(worst))


class _Captured:
    """Standard output collected for --output (UTF-8: written to a file as such)."""

    encoding = "utf-8"

    def __init__(self):
        import io

        self._buf = io.StringIO()
        self.write, self.getvalue = self._buf.write, self._buf.getvalue

    def flush(self):
        pass

    def isatty(self):
        return False


def _write_output(path: str, screen, force: bool) -> ExitCode:
    """The collected output to `path` (whole or not at all); stdout is put back."""
    from .outputs import OutputError, write_text

    text, sys.stdout = sys.stdout.getvalue(), screen
    if not text:
        return ExitCode.OK  # nothing solved: no file (the errors said why)
    try:
        write_text(path, text, force, "--output")
    except OutputError as exc:
        sys.stderr.write(f"momentum: error: {exc}\n")
        return ExitCode.USAGE
    return ExitCode.OK


def _solve_loop(items, solved, mode, quiet, many, digits, solve_all, precision,
                traceback_flag, results, strict, color, deterministic, overrides=(),
                jsonl=False, view=None, sensitivity=False) -> ExitCode:
    """Print (or collect, for JSON) each file's result in order; the worst exit code."""
    from .run import Rendered, _NoCyclicGC, solve_source

    out, err = sys.stdout, sys.stderr
    console = _console(mode, color)
    tint = _use_color(color, err, deterministic)
    worst = ExitCode.OK
    for i, (name, source, res) in enumerate(items):
        if res is None and not traceback_flag:
            res = next(solved)
        elif res is None:
            try:
                res = solve_source(source, solve_all, digits, precision.value, overrides,
                                   units=(view or {}).get("units", "file"),
                                   sensitivity=sensitivity)
            except (KeyboardInterrupt, Exit):
                raise
            except Exception as exc:  # --traceback: show the bug
                res = _internal(name, exc, traceback_flag)
        res = _strict(res, strict)
        code = ExitCode.INTERNAL if res.status == "internal" else res.exit_code
        worst = max(worst, code)
        if mode == "json":
            with _NoCyclicGC():  # a big result's dicts and text: no collector passes
                _json_result(name, res, out, results, jsonl)
            continue
        _print_diagnostics(res, err, tint)
        for c in res.expects if res.report is None else ():  # `expect` lines of a failed file
            err.write(f"{name}:{c.spec.span.line}: note: " + (
                f"this error was expected (expect {c.spec.quantity})" if c.met and c.spec.error
                else c.message) + "\n")
        if res.report is None:
            continue
        if mode in ("markdown", "latex", "html") and not quiet:
            results.append(res.report)  # one document for all files, written at the end
        elif quiet:
            from .report.text import render_quiet

            if many:
                out.write(f"==> {name} <==\n")
            out.write(res.report.text if isinstance(res.report, Rendered) else
                      render_quiet(res.report, digits))
        elif isinstance(res.report, Rendered):  # plain text, made by the worker
            text = res.report.text if res.report.parts is None else res.report.parts
            if i and isinstance(text, str) and len(text) < WRITE_CHUNK:
                text = "\n" + text  # the common file: one write
            elif i:
                out.write("\n")
            _write_text(out, text)
        else:
            failed = None if traceback_flag else []  # --traceback: a bug is raised
            with _NoCyclicGC():
                console = _render(res.report, mode, console, i, digits, simulation=False,
                                  detail=(view or {}).get("detail", "full"), failed=failed)
            if failed:  # after the text made before it: the error a worker would give
                from .run import internal_result

                _print_diagnostics(internal_result(name, failed[0]), err, tint)
                worst = max(worst, ExitCode.INTERNAL)
            _keep_if_big(res)
    return worst


KEEP_MIN_EQUATIONS = 2000  # a solution from which freeing it costs more than ~10 ms


def _keep_if_big(res) -> None:
    """A big solution (and its report) is kept to the end of a one-shot process, which
    then leaves without freeing it (guard.keep_until_exit: ~0.25 s for 10^4 impacts);
    elsewhere (tests, a batch's parent) it is freed as usual."""
    counts = getattr(res.report, "counts", None) or {}
    if counts.get("equations", 0) >= KEEP_MIN_EQUATIONS:
        from .guard import keep_until_exit

        keep_until_exit(res)
    from .report.model import forget_diagram_index

    forget_diagram_index()  # its diagrams are not held by the index beyond the report


def _json_result(name, res, out, results, jsonl: bool) -> None:
    """One file's JSON result: a line of --jsonl, or the next entry of the document."""
    from .report.json_out import result_dict

    d = result_dict(name, res.status if res.status != "internal" else "error",
                    res.report, res.diagnostics)
    if d.get("title") is None:
        d["title"] = _title_of(res)
    if res.expects and res.report is None:
        from .report.model import expectation_dict

        d["expectations"] = [expectation_dict(c) for c in res.expects]
    if jsonl:
        import json

        from .report.json_out import clean

        out.write(json.dumps(clean(d), allow_nan=False,
                             ensure_ascii=not _is_utf8(out)) + "\n")
        out.flush()
    else:
        results.append(d)


def _text_renderer(mode: str, quiet: bool, digits: int, detail: str, jsonl: bool = False,
                   ascii_only: bool = False, many: bool = True):
    """What turns a report into its printed text where the file is solved (a worker
    ships that text, not the report), for the outputs that are such a text: -q's
    answers, plain's report, the JSON document's report fields (`ascii_only` as the
    document; one file's, if big, made by two processes: forked_text); None for the
    others (rich, documents, --jsonl)."""
    from functools import partial

    if mode == "json" and not jsonl and not many:
        return partial(_json_fields, ascii_only=ascii_only, min_equations=FORK_MIN_EQUATIONS)
    if mode == "json" and not jsonl:
        from .report import json_out

        return partial(json_out.encoded_fields, ascii_only=ascii_only)
    if mode == "json" or not (quiet or mode == "plain"):
        return None
    from .report import text

    if quiet:
        return partial(text.render_quiet, sig=digits)
    if detail == "full":  # in pieces, joined by solve_many once the report is freed
        return partial(text.render_parts, sig=digits)
    return partial(text.render, sig=digits, detail=detail)


def _json_fields(rep, ascii_only: bool, min_equations: int) -> dict:
    """One file's JSON report fields (json_out.encoded_fields); a big report's made by
    two processes (forked_text)."""
    if (rep.counts or {}).get("equations", 0) < min_equations:
        from .report import json_out

        return json_out.encoded_fields(rep, ascii_only)
    from . import forked_text

    return forked_text.encoded_fields(rep, ascii_only, min_equations)


def _overrides_for(sets: list[str] | None, sources) -> tuple:
    """The `--set` pairs, checked: each parses as a value and names a `let` of every
    file given (else a usage error, exit 2, with "did you mean")."""
    if not sets:
        return ()
    from .overrides import OverrideError, check_names, split

    try:
        pairs = tuple(split(s) for s in sets)
        for src in sources:
            if src is not None:
                check_names(pairs, src.text, src.name)
    except OverrideError as exc:
        raise BadParameter(str(exc)) from None
    return pairs
