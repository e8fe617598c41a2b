"""Running one problem file through the pipeline, as a value the CLI can render.

`solve_source` and `check_source` never raise for a bad problem file: they return a
`FileResult` with diagnostics. Only a bug in momentum escapes as an exception.
"""
from __future__ import annotations

from dataclasses import field

from .diagnostics import Diagnostic, ExitCode, ProblemError
from .records import record
from .source import Source


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


def read_source(path: str, stdin_text: str | None = None) -> Source:
    """Read a problem file (`-` is standard input). Raises OSError or UnicodeDecodeError."""
    if path == "-":
        return Source("<stdin>", stdin_text if stdin_text is not None else "")
    with open(path, "rb") as fh:
        data = fh.read(2_000_001)
    if b"\x00" in data:
        return Source(path, "\x00")
    return Source(path, data.decode("utf-8"))


def solve_source(source: Source, solve_all: bool = False, sig: int = 6) -> FileResult:
    from .report.model import build_report
    from .scene import build
    from .solve import solve_scene
    from .syntax import parse

    try:
        scene = build(parse(source))
        sol = solve_scene(scene, solve_all)
        rep = build_report(source.name, sol, sig)
        return FileResult(source.name, "solved", source, rep, list(sol.diagnostics))
    except ProblemError as exc:
        return FileResult(source.name, "error", source, None, list(exc.diagnostics))
    except RecursionError:
        return FileResult(source.name, "error", source, None,
                          [Diagnostic("error", "too-deep", "expression nested too deeply")])


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
        diags.append(Diagnostic(sev, "under-determined", msg))
    counts = dict(unknowns=len(system.unknowns), equations=len(system.equations),
                  blocks=len(st.blocks), redundant=len(st.redundant) + len(st.constant_eqs),
                  undetermined=len(st.under), undetermined_equations=len(st.under_eqs))
    status = "error" if any(d.severity == "error" for d in diags) else "checked"
    return FileResult(source.name, status, source, None, diags, counts)
