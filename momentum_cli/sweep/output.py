"""A sweep's results as text, CSV, JSON and JSON lines.

In: a `BatchResult`. Out: the summary table (each answer's mean, standard deviation,
percentiles 5/50/95, min and max in the `find`'s unit; how many variants were solved
on their own and why; the friction regimes that held), and one row per variant:
parameters in SI, answers in the `find`'s unit, the status. Floats are written as
`repr` writes them (shortest exact round trip), so two runs give identical bytes.
"""
from __future__ import annotations

import json
import math
from collections import Counter

import numpy as np

from ..numbers import fmt_num


def header(result) -> list[str]:
    cols = [f"{p} ({u})" if u else p for p, u in result.param_units.items()]
    for a in result.answers:
        unit = result.display[a][0]
        cols.append(f"{a} ({unit})" if unit else a)
    return cols + ["status"]


def _display(result) -> list[np.ndarray]:
    return [result.answers[a] / result.display[a][1] for a in result.answers]


def _f(x: float) -> str:
    return repr(float(x)) if math.isfinite(x) else ""


def rows(result, lo: int = 0, hi: int | None = None):
    """Each variant's cells as text (parameters SI, answers in the find's unit)."""
    params = list(result.params.values())
    answers = _display(result)
    n = len(result.status)
    hi = n if hi is None else hi
    pl = [c[lo:hi].tolist() for c in params]
    al = [c[lo:hi].tolist() for c in answers]
    st = result.status[lo:hi].tolist()
    for j in range(hi - lo):
        yield [_f(c[j]) for c in pl] + [_f(c[j]) for c in al] + [st[j]]


def _texts(col: np.ndarray) -> list[str]:
    """A column's cells: `repr` of each float (shortest exact), '' for nan or inf."""
    out = list(map(repr, col.tolist()))
    bad = ~np.isfinite(col)
    if bad.any():
        for i in np.nonzero(bad)[0].tolist():
            out[i] = ""
    return out


def _quoted(s: str) -> str:
    """A cell as the csv module writes it (quoted only if it must be)."""
    if any(c in s for c in ',"\r\n'):
        return '"' + s.replace('"', '""') + '"'
    return s


def write_csv(result, path_or_stream) -> None:
    """One row per variant; the header says each column's unit (parameters in SI).
    Written column-wise (repr of whole columns), the same bytes as `csv.writer`."""
    import csv
    import io

    def emit(fh):
        head = io.StringIO()
        csv.writer(head, lineterminator="\n").writerow(header(result))
        fh.write(head.getvalue())
        cols = list(result.params.values()) + _display(result)
        n = len(result.status)
        for lo in range(0, n, 65536):
            hi = min(n, lo + 65536)
            texts = [_texts(c[lo:hi]) for c in cols]
            st = ["ok"] * (hi - lo)
            for j in np.nonzero(~_ok(result)[lo:hi])[0].tolist():
                st[j] = _quoted(result.status[lo + j])
            texts.append(st)
            fh.write("\n".join(map(",".join, zip(*texts))) + "\n")

    if isinstance(path_or_stream, str):
        with open(path_or_stream, "w", encoding="utf-8", newline="") as fh:
            emit(fh)
    else:
        emit(path_or_stream)


def write_jsonl(result, stream) -> None:
    """One JSON object per variant: parameters (SI), answers (find's unit), status."""
    keys = header(result)
    for cells in rows(result):
        obj = {}
        for k, c in zip(keys[:-1], cells[:-1]):
            obj[k] = float(c) if c != "" else None
        obj["status"] = cells[-1]
        stream.write(json.dumps(obj) + "\n")


def stats(result) -> list[dict]:
    """Each answer's summary over the variants that solved (find's unit)."""
    out = []
    for a, vals in zip(result.answers, _display(result)):
        v = vals[np.isfinite(vals)]
        row = {"name": a, "unit": result.display[a][0], "count": int(v.size)}
        if v.size:
            p5, p50, p95 = np.percentile(v, [5, 50, 95])
            row.update(mean=float(v.mean()), sd=float(v.std(ddof=1)) if v.size > 1 else 0.0,
                       p5=float(p5), p50=float(p50), p95=float(p95), min=float(v.min()),
                       max=float(v.max()))
        out.append(row)
    return out


def _ok(result) -> np.ndarray:
    return result.ok if getattr(result, "ok", None) is not None else result.status == "ok"


def status_counts(result) -> list[tuple[str, int]]:
    ok = _ok(result)
    c = Counter(result.status[~ok].tolist())
    if ok.any():
        c["ok"] = int(ok.sum())
    return sorted(c.items(), key=lambda kv: (-kv[1], kv[0]))


def failed(result) -> np.ndarray:
    """Which variants did not solve."""
    if getattr(result, "failed", None) is not None:
        return result.failed
    other = np.nonzero(~_ok(result))[0]
    out = np.zeros(len(result.status), bool)
    out[other] = [s.startswith("error") for s in result.status[other].tolist()]
    return out


def regime_counts(result) -> list[tuple[str, int]]:
    """How many variants (that solved) ended in each set of friction regimes."""
    if result.regimes is None:
        return []
    solved = ~failed(result)
    first = result.regimes[0] if len(result.regimes) else ""
    same = result.regimes == first
    c = Counter(result.regimes[solved & ~same].tolist())
    c[first] += int((solved & same).sum())
    return sorted(((r, n) for r, n in c.items() if r and n), key=lambda kv: (-kv[1], kv[0]))


def summary_text(result, file: str, digits: int = 6) -> str:
    n = len(result.status)
    lines = [f"== {file}: {n} variant{'s' if n != 1 else ''}"]
    params = ", ".join(f"{p}" + (f" ({u})" if u else "") for p, u in result.param_units.items())
    lines.append(f"   parameters (SI): {params}")
    lines.append("")
    head = ["answer", "unit", "mean", "sd", "p5", "p50", "p95", "min", "max"]
    table = [head]
    for s in stats(result):
        cells = [s["name"], s["unit"] or "-"]
        cells += [fmt_num(s[k], digits) if "mean" in s else "-"
                  for k in ("mean", "sd", "p5", "p50", "p95", "min", "max")]
        table.append(cells)
    lines += _align(table)
    lines.append("")
    lines.append("Variants")
    for st, c in status_counts(result):
        if st == "ok":
            how = "solved in one batch" if result.batched else \
                f"solved one by one ({result.note})"
            lines.append(f"  {c} {how}")
        elif st.startswith("error"):
            lines.append(f"  {c} did not solve: {st[len('error: '):]}")
        else:
            lines.append(f"  {c} solved on their own: {st}")
    regimes = regime_counts(result)
    if len(regimes) > 1 or (regimes and regimes[0][0]):
        lines.append("")
        lines.append("Friction regimes")
        for r, c in regimes:
            lines.append(f"  {c} variant{'s' if c != 1 else ''}: {r}")
    return "\n".join(lines) + "\n"


def _align(table: list[list[str]]) -> list[str]:
    widths = [max(len(r[i]) for r in table) for i in range(len(table[0]))]
    out = []
    for k, r in enumerate(table):
        out.append("  " + "  ".join(c.ljust(w) for c, w in zip(r, widths)).rstrip())
        if k == 0:
            out.append("  " + "  ".join("-" * w for w in widths))
    return out


def json_document(result, file: str) -> dict:
    return {
        "file": file,
        "variants": len(result.status),
        "batched": result.batched,
        "parameters": [{"name": p, "unit": u} for p, u in result.param_units.items()],
        "answers": [{"name": a, "unit": result.display[a][0]} for a in result.answers],
        "summary": stats(result),
        "status": [{"status": s, "count": c} for s, c in status_counts(result)],
        "regimes": [{"regimes": r, "count": c} for r, c in regime_counts(result)],
        "rows": [dict(zip(header(result), [float(c) if c != "" else None
                                           for c in cells[:-1]] + [cells[-1]]))
                 for cells in rows(result)],
    }
