"""Numeric rank: where the structure of the equations and their numbers disagree.

Stage: between analyse and solve. In: the compiled system, equation indices, the
values solved so far. Out: which rows are numerically dependent, which unknowns a
set of rows really determines, and which rows take part in a conflict (the support
of a left null vector). Rank decisions use `linalg.rank_reveal` (exact rationals
under `--precision exact`; in float, round-off of the terms is no entry).
"""
from __future__ import annotations

from .compile import System
from .expr import NonLinear, affine, diff, evaluate, variables
from .linalg import RankReveal, rank_reveal
from .records import record


def priority(system: System, ks) -> list[int]:
    """Equations in the order they are kept: derived ones first, then the principles the
    user states (so a stated one is the check when both say the same), each in the
    order compiled (the file's order, never the bodies' names)."""
    eqs = system.equations
    return sorted(ks, key=lambda k: (eqs[k].kind in ("stated", "user"), k))


def linear_rows(system: System, ks, cols: list[str], values, linearize: bool = False):
    """The rows of equations `ks` in the columns `cols` with `values` substituted:
    (rows, rhs, the equations kept). An equation that is not linear in `cols` (unless
    `linearize`: its Jacobian at `values`) or that needs an unknown not in `values` is
    left out."""
    col = {n: j for j, n in enumerate(cols)}
    cset = set(cols)
    rows, rhs, kept = [], [], []
    for k in ks:
        e = system.equations[k]
        try:
            coef, const = affine(e.residual, cset, values)
        except NonLinear:
            if not linearize:
                continue
            try:
                env = dict(values)
                coef = {n: evaluate(diff(e.residual, n), env)
                        for n in variables(e.residual) if n in cset}
                const = evaluate(e.residual, env)
            except (KeyError, ValueError, ZeroDivisionError, OverflowError):
                continue
        except (KeyError, ValueError, ZeroDivisionError, OverflowError):
            continue
        rows.append({col[n]: v for n, v in coef.items() if v != 0.0})
        rhs.append(-const)
        kept.append(k)
    return rows, rhs, kept


def dependent_rows(system: System, equations: list[int], unknowns: list[str], values,
                   exact: bool = True) -> tuple[set[int], set[int]]:
    """The equations of a singular block that depend on the others (kept in priority
    order): leaving them out (they become checks) makes the rest independent. Also the
    equations the dependencies involve (for naming them)."""
    rows, rhs, kept = linear_rows(system, priority(system, equations), unknowns, values)
    rr = rank_reveal(rows, rhs, len(unknowns), exact=exact)
    return {kept[i] for i, _, _ in rr.dependent}, _support(rr, kept)


def inconsistent_rows(system: System, equations: list[int], unknowns: list[str], values,
                      exact: bool = True) -> tuple[int, set[int]] | None:
    """A dependent row of a singular block whose right-hand side disagrees with the rows
    it depends on: (the row, every row of that dependency), else None. The left side
    of such rows is a combination of the others; their numbers are not, so no solution
    exists whatever the undetermined split (a row with a free impulse is never checked
    after solving, so this is the only place the conflict shows)."""
    from .expr import magnitude
    from .linalg import equilibrate

    rows, rhs, kept = linear_rows(system, priority(system, equations), unknowns, values)
    rr = rank_reveal(rows, rhs, len(unknowns), exact=exact)
    _, _, r, _ = equilibrate(rows, rhs, len(unknowns))
    env = dict(values)
    env.update((n, 0.0) for n in unknowns)
    for i, comb, rem in rr.dependent:
        if rem == 0.0:
            continue
        # the size of the known terms each row subtracts (m v2 - m v1 cancels in a heavy
        # body's row): the solved values carry round-off of that size, not of the rhs
        scale = 0.0
        for q, c in comb.items():
            try:
                scale += abs(c) * magnitude(system.equations[kept[q]].residual, env) / r[q]
            except (KeyError, ValueError, ZeroDivisionError, OverflowError):
                return None
        # the rows are formed in float from solved values (also in exact mode): judge the
        # remainder against their round-off, tighter when the values were exact
        if abs(rem) > (1e-12 if exact else 1e-8) * scale:
            return kept[i], {kept[q] for q in comb}
    return None


def _support(rr: RankReveal, kept: list[int]) -> set[int]:
    out: set[int] = set()
    for _, comb, _ in rr.dependent:
        out.update(kept[q] for q in comb)
    return out


@record
class Split:
    """What a structurally under-determined part determines numerically."""

    cols: list[str]
    basis: list[tuple[int, int]]  # (equation, pivot column)
    rows: dict[int, dict[int, float]]  # equation -> its row
    rhs: dict[int, float]
    determined: list[str]
    free: list[str]
    dependent: list[int]  # equations dependent on the basis
    support: set[int]  # the equations those dependencies involve


UNDER_LIMIT = 2000  # larger under-determined parts keep the structural answer


def split_under(system: System, under: set[str], ks, values, exact: bool) -> Split | None:
    """Rank-reveal the rows `ks` (linear in the unknowns of `under`, the rest known):
    the unknowns every solution agrees on are determined; the others are free."""
    rank = {n: i for i, n in enumerate(system.unknowns)}
    cols = sorted({v for k in ks for v in variables(system.equations[k].residual)
                   if v in under}, key=lambda n: rank.get(n, len(rank)))
    if not cols or len(cols) > UNDER_LIMIT:
        return None
    rows, rhs, kept = linear_rows(system, priority(system, ks), cols, values)
    if not rows:
        return None
    rr: RankReveal = rank_reveal(rows, rhs, len(cols), exact=exact)
    free = set(rr.free)
    pivots = {p for _, p in rr.basis}
    determined = [cols[j] for j in range(len(cols)) if j in pivots and j not in free]
    return Split(cols, [(kept[i], p) for i, p in rr.basis],
                 {kept[i]: rows[i] for i in range(len(kept))},
                 {kept[i]: rhs[i] for i in range(len(kept))}, determined,
                 [cols[j] for j in sorted(free)], [kept[i] for i, _, _ in rr.dependent],
                 _support(rr, kept))


def conflict_set(system: System, failing: int, supports: list[int], values) -> list[int]:
    """The equations of the smallest conflict that `failing` is part of: `supports` (the
    rows that determined its unknowns) are eliminated first, then `failing`; the rows
    its left null vector involves are the conflict. [] if it cannot be told."""
    cols: set[str] = set()
    for k in [failing, *supports]:
        cols |= {v for v in variables(system.equations[k].residual) if v in values}
    rank = {n: i for i, n in enumerate(system.unknowns)}
    order = sorted(cols, key=lambda n: rank.get(n, len(rank)))
    ks = priority(system, [k for k in supports if k != failing]) + [failing]
    rows, rhs, kept = linear_rows(system, ks, order, values, linearize=True)
    if not kept or kept[-1] != failing:
        return []
    if not order:
        return [failing]
    rr = rank_reveal(rows, rhs, len(order))
    for i, comb, _ in rr.dependent:
        if kept[i] == failing:
            return sorted(kept[q] for q in comb)
    return []
