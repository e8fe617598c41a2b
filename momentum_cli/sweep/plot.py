"""`momentum sweep --plot FILE`: the answers against a varied parameter, or histograms.

Stage: report (matplotlib, the `plot` extra, imported on use). In: a sweep's result
(answers, units, status, params in SI) and which parameters were a grid and which were
drawn. Out: a figure file. A grid parameter is the x axis (one line per value of a
second grid parameter, when there are few); drawn parameters give one histogram per
answer with its mean and 5th/95th percentiles. Variants that did not solve are left
out (status "error: ...") and counted in the title.
"""
from __future__ import annotations

import math

import numpy as np

MAX_PANELS = 6  # answers drawn; more would be unreadable in one figure
MAX_LINES = 8  # values of a second grid parameter drawn as separate lines


def _label(name: str, unit: str) -> str:
    return f"{name} ({unit})" if unit else name


def draw(result, path: str, grid: list[str], sampled: list[str], param_units: dict | None = None,
         answers: list[str] | None = None, title: str | None = None) -> None:
    """Draw `result` to `path` (its type from the suffix). `grid` and `sampled` name the
    parameters by how they were varied; `answers` picks the outputs (default: all, up to
    MAX_PANELS)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    param_units = param_units or {}
    # solved: "ok" (in the batch) or solved on its own for a stated reason; not "error: ..."
    ok = np.array([not str(s).startswith("error") for s in result.status], dtype=bool)
    names = list(answers) if answers else _varying(result, ok)
    names = names[:MAX_PANELS]
    failed = int((~ok).sum())
    cols = min(2, max(1, len(names)))
    rows = max(1, math.ceil(len(names) / cols))
    fig, axes = plt.subplots(rows, cols, figsize=(5.5 * cols, 3.8 * rows), squeeze=False)
    for ax, name in zip(axes.flat, names):
        y = np.asarray(result.answers[name], dtype=float)
        ylab = _label(name, result.units.get(name, ""))
        if grid and not sampled:
            _lines(ax, result.params, grid, y, ok, param_units)
            ax.set_ylabel(ylab)
        else:
            _histogram(ax, y[ok & np.isfinite(y)])
            ax.set_xlabel(ylab)
            ax.set_ylabel("variants")
        ax.grid(True, alpha=0.3)
    for ax in list(axes.flat)[len(names):]:
        ax.set_visible(False)
    n = len(result.status)
    head = title or "sweep"
    how = (f"{n} variants" if not sampled else
           f"{n} variants, {', '.join(sampled)} drawn")
    if failed:
        how += f"; {failed} not solved (left out)"
    fig.suptitle(f"{head}\n{how}", fontsize="medium")
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def _varying(result, ok) -> list[str]:
    """The answers that change between the solved variants (a constant says nothing
    here); all of them when none does."""
    out = []
    for name, v in result.answers.items():
        y = np.asarray(v, dtype=float)[ok]
        y = y[np.isfinite(y)]
        if len(y) and np.ptp(y) > 1e-12 * max(1.0, float(np.max(np.abs(y)))):
            out.append(name)
    return out or list(result.answers)


def _lines(ax, params: dict, grid: list[str], y, ok, units: dict) -> None:
    """y against the first grid parameter; one line per value of the second when few,
    else points (the other parameters' values mixed)."""
    x = np.asarray(params[grid[0]], dtype=float)
    ax.set_xlabel(_label(grid[0], units.get(grid[0], "")))
    if len(grid) >= 2:
        z = np.asarray(params[grid[1]], dtype=float)
        values = np.unique(z)
        if len(values) <= MAX_LINES and len(grid) == 2:
            for v in values:
                sel = ok & (z == v)
                ax.plot(x[sel], y[sel], "o-", ms=3,
                        label=f"{grid[1]} = {v:.4g} {units.get(grid[1], '')}".rstrip())
            ax.legend(fontsize="small")
            return
        ax.plot(x[ok], y[ok], ".", ms=3)
        return
    ax.plot(x[ok], y[ok], "o-" if ok.sum() <= 60 else "-", ms=3)


def _histogram(ax, y) -> None:
    if len(y) == 0:
        ax.text(0.5, 0.5, "no variant solved", ha="center", transform=ax.transAxes)
        return
    bins = int(min(60, max(5, math.sqrt(len(y)))))
    ax.hist(y, bins=bins, color="tab:blue", alpha=0.75)
    mean = float(np.mean(y))
    p5, p95 = (float(v) for v in np.percentile(y, [5, 95]))
    ax.axvline(mean, color="k", lw=1, label=f"mean {mean:.4g}")
    ax.axvline(p5, color="tab:red", lw=1, ls="--", label=f"5 % {p5:.4g}")
    ax.axvline(p95, color="tab:red", lw=1, ls=":", label=f"95 % {p95:.4g}")
    ax.legend(fontsize="small")
