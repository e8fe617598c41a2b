"""Sweeps of `simulate` scenes: one simulation per variant, its scalar outputs as arrays.

Stage: run (parse once, then build and simulate per variant). In: the problem text and
columns {parameter: SI values}: `let` names, or a state's given number `BODY.QTY@STATE`
(made a `let` by the sweep's `bind`). Out: a `BatchResult`, as `solve_batch` gives, so
that the same summary/CSV/JSON/plot writers and the Dask runner take both. A variant
that fails keeps NaN outputs and "error: ..." as its status.
"""
from __future__ import annotations

import math

import numpy as np

# The outputs of one run, in this order (the final state's per body; see `outputs`).
BODY_OUTPUTS = (("x", "m"), ("y", "m"), ("angle", "rad"), ("vx", "m/s"), ("vy", "m/s"),
                ("omega", "rad/s"))


def outputs(report: dict) -> list[tuple[str, float, str]]:
    """The scalar outputs of one simulation report (as its summary and JSON give them):
    the stop time, the number of impacts, the energy the impacts took, and the final
    state of every body (angle and omega for rigid bodies only). With `until apex` the
    final y is the height of the top of the flight, e.g. a bounce height."""
    out = [("t_end", float(report["t_end"]), "s"), ("impacts", float(report["impacts"]), ""),
           ("energy_lost", float(sum(e["energy_lost"] or 0.0 for e in report["events"])), "J")]
    for f in report["final"]:
        for q, unit in BODY_OUTPUTS:
            if f[q] is not None:
                out.append((f"{f['body']}.{q}", float(f[q]), unit))
    return out


def simulate_batch(text: str, name: str, columns: dict, rtol: float = 1e-9,
                   dt: float | None = None, closed_forms: bool = True,
                   max_events: int = 10000, max_time: float | None = None,
                   progress=None):
    """Simulate every variant of one problem text; `columns` hold SI values per
    parameter. A name the file cannot vary raises `batch.SweepError` (one line)."""
    from .. import syntax as S
    from ..diagnostics import ProblemError
    from ..scene import build
    from ..sim.integrate import simulate
    from ..sim.output import build as build_report
    from ..source import Source
    from .batch import BatchResult, SweepError
    from .params import ParamError, bind

    cols = {k: np.asarray(v, dtype=float) for k, v in columns.items()}
    n = len(next(iter(cols.values()))) if cols else 1
    try:
        parsed = S.parse(Source(name, text))
        _check_simulated(parsed, list(cols), name)
        doc = bind(parsed, list(cols), name)
        lets = {s.name: s for s in doc.statements if isinstance(s, S.Let)}
        dims = build(doc).constants  # each parameter's dimension, from the file as written
    except ParamError as exc:
        raise SweepError(str(exc)) from None
    except ProblemError as exc:
        d = exc.diagnostics[0]
        where = f":{d.span.line}:{d.span.column}" if d.span else ""
        raise SweepError(f"{name}{where}: error: {d.message}") from None
    units = {k: _si_unit(dims[k].dim) for k in cols}
    values: dict[str, list] = {}
    found_units: dict[str, str] = {}
    status = []
    for i in range(n):
        variant = _with_values(doc, lets, {k: float(c[i]) for k, c in cols.items()}, units)
        try:
            res = simulate(build(variant), rtol=rtol, dt=dt, closed_forms=closed_forms,
                           max_events=max_events, max_time=max_time)
            row = outputs(build_report(name, res))
            status.append("ok")
        except ProblemError as exc:
            d = exc.diagnostics[0]
            where = f" (line {d.span.line})" if d.span is not None else ""
            status.append(f"error: {d.message}{where}")
            row = []
        except RecursionError:
            status.append("error: expression too long or nested too deeply")
            row = []
        for key, v, unit in row:
            if key not in values:
                values[key] = [math.nan] * i
                found_units[key] = unit
            values[key].append(v)
        for key, vs in values.items():
            if len(vs) < i + 1:
                vs.append(math.nan)
        if progress is not None:
            progress(i + 1)
    st = np.array(status, dtype=object)
    ok = np.array([s == "ok" for s in status], dtype=bool)
    return BatchResult(answers={k: np.array(v, dtype=float) for k, v in values.items()},
                       units=found_units, status=st, params=cols,
                       display={k: (u, 1.0) for k, u in found_units.items()},
                       param_units=units, regimes=None, batched=False,
                       note="one simulation per variant", ok=ok, failed=~ok)


def _check_simulated(doc, names: list, name: str) -> None:
    """Every parameter must enter the simulation: a `let`, or a given number of the
    state it starts from. An impact's `e[C]`/`mu[C]` or another state's given number
    would change the `solve` part only, and the runs would all be alike."""
    import re

    from .. import syntax as S
    from .batch import SweepError

    sims = [s for s in doc.statements if isinstance(s, S.SimulateDecl)]
    if not sims:
        raise SweepError(f"--simulate: {name} has no `simulate from S:` block")
    start = sims[0].start
    for p in names:
        if re.match(r"^(e|mu)\[", p):
            raise SweepError(f"--simulate: {p} is an impact's coefficient, which the "
                             "simulation does not use; write its contact's coefficient as a "
                             "`let` (restitution e) and vary that")
        m = re.match(r"^[A-Za-z_]\w*\.[A-Za-z_]+@(\w+)$", p)
        if m and m.group(1) != start:
            raise SweepError(f"--simulate: {p} is given in state {m.group(1)}, and the "
                             f"simulation starts from state {start}: vary a number of state "
                             f"{start} or a `let`")


def _si_unit(dim) -> str:
    from ..units import si_label

    return si_label(dim)


def _with_values(doc, lets: dict, values: dict, units: dict):
    """The document with each named `let` set to a number in SI (its spans kept)."""
    from .. import syntax as S

    if not values:
        return doc
    out = []
    for s in doc.statements:
        if isinstance(s, S.Let) and s.name in values:
            span = s.value.span
            v = values[s.name]
            node = S.Num(span, abs(v), units[s.name] or None, span if units[s.name] else None)
            if v < 0 or (v == 0 and math.copysign(1.0, v) < 0):
                node = S.Neg(span, node)
            s = S.Let(s.span, s.name, node)
        out.append(s)
    return S.Document(doc.source, tuple(out))
