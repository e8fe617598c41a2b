"""One problem file through `simulate`, as a value the CLI renders; never raises for a
bad file (only a bug in momentum escapes as an exception)."""
from __future__ import annotations

from ..diagnostics import ProblemError
from ..run import FileResult, _NoCyclicGC, _too_deep
from ..source import Source


def simulate_source(source: Source, rtol: float = 1e-9, dt: float | None = None,
                    progress=None, closed_forms: bool = True, **limits):
    """(FileResult with `report` = the simulation's report dict, SimResult or None)."""
    from ..scene import build
    from ..syntax import parse
    from .integrate import simulate
    from .output import build as build_report

    try:
        with _NoCyclicGC():
            scene = build(parse(source))
            res = simulate(scene, rtol=rtol, dt=dt, progress=progress, closed_forms=closed_forms,
                           **limits)
            rep = build_report(source.name, res)
        return FileResult(source.name, "solved", source, rep, []), res
    except ProblemError as exc:
        return FileResult(source.name, "error", source, None, list(exc.diagnostics)), None
    except RecursionError:
        return _too_deep(source), None
