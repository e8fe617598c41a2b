"""A stand-in for `sweep.batch.solve_batch` (tests only): a loop of scalar solves with
each variant's `let` values given as `--set` overrides in SI. Slow but independent of the
batched solver, so it also serves as the reference the batched results are held to."""
from __future__ import annotations

import math

import numpy as np

from momentum_cli.records import record


@record
class StandInBatch:
    answers: dict
    units: dict
    status: np.ndarray
    params: dict


def solve_text_batch(text: str, name: str, columns: dict) -> StandInBatch:
    from momentum_cli.run import solve_source
    from momentum_cli.scene import build
    from momentum_cli.source import Source
    from momentum_cli.syntax import parse
    from momentum_cli.units import si_label

    cols = {k: np.asarray(v, dtype=float) for k, v in columns.items()}
    n = len(next(iter(cols.values())))
    dims = build(parse(Source(name, text))).constants
    units = {k: si_label(dims[k].dim) for k in cols}
    answers, out_units, status = {}, {}, []
    for i in range(n):
        sets = [(k, f"{float(c[i])!r} {units[k]}".strip()) for k, c in cols.items()]
        res = solve_source(Source(name, text), overrides=sets)
        if res.report is None:
            d = next(d for d in res.diagnostics if d.severity == "error")
            status.append(f"{d.code}: {d.message}")
            continue
        status.append("ok")
        for a in res.report.answers:
            col = answers.setdefault(a["name"], [math.nan] * n)
            col[i] = a["si_value"]
            out_units.setdefault(a["name"], a["unit"])
    return StandInBatch({k: np.array(v) for k, v in answers.items()}, out_units,
                        np.array(status, dtype=object), cols)


def csv_text(result) -> str:
    """A deterministic CSV (17 significant digits) for comparing results byte for byte."""
    names = list(result.params) + list(result.answers)
    lines = [",".join(["variant", "status"] + names)]
    for i, st in enumerate(result.status):
        vals = [result.params[k][i] for k in result.params] + \
               [result.answers[k][i] for k in result.answers]
        lines.append(",".join([str(i), str(st)] + [repr(float(v)) for v in vals]))
    return "\n".join(lines) + "\n"
