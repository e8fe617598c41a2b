"""Which roots of a nonlinear block are physical (part of `solve`).

In: one root Newton found for a block, the structure (its redundant equations) and a
way to solve the blocks after it. Out: the reasons the root is not physical: a
redundant equation it breaks (once the blocks that equation needs are solved on a
copy), a contact that pulls, a found restitution outside [0, 1], bodies that would
separate before an impact or still approach after it. Also a hint that separates the
roots left, for the "more than one solution" error.
"""
from __future__ import annotations

import math

from .bounds import term_size
from .diagnostics import ProblemError
from .elements.kinds import Component
from .expr import evaluate, variables
from .numbers import fmt_num

LOOSE = 1e-7  # a root holds its equations to ~1e-14 of their size; a spurious one by O(1)
TRIAL_LIMIT = 400  # unknowns solved on trial per root, at most
_depth = [0]  # trials do not nest: a root inside a trial is judged on what is solved


def problems(system, structure, block, names, x, values, solve_block,
             broken: list | None = None) -> list[str]:
    """Why root `x` of `block` is not physical ([] if nothing says it is not); the
    redundant equations it breaks are added to `broken` (their indices)."""
    env = dict(values)
    env.update(zip(names, x))
    solved = set(names)
    if _depth[0] == 0:
        solved |= _trial(system, structure, block, env, solve_block)
    out = []
    for k in structure.redundant:
        inc = structure.incidence[k]
        if not inc & solved or not all(v in env for v in inc):
            continue
        e = system.equations[k]
        try:
            r, size = evaluate(e.residual, env), term_size(e.residual, env)
        except (KeyError, ValueError, ZeroDivisionError, OverflowError):
            continue
        if not abs(r) <= LOOSE * size:
            where = f"line {e.span.line}" if e.span else "the scene"
            out.append(f"it breaks {e.principle} ({where}) by {fmt_num(r, 3)}")
            if broken is not None:
                broken.append(k)
    for t in system.transitions:
        if t.kind != "impact":
            continue
        for label, vn1, vn2 in t.contacts:
            for when, vn, bad in (("before", vn1, 1.0), ("after", vn2, -1.0)):
                vs = variables(vn)
                if not vs & solved or not all(v in env for v in vs):
                    continue
                try:
                    v, size = evaluate(vn, env), term_size(vn, env)
                except (KeyError, ValueError, ZeroDivisionError, OverflowError):
                    continue
                if bad * v > LOOSE * max(size, 1e-300):
                    out.append(f"at {label} the bodies would separate before the impact "
                               f"(normal velocity {fmt_num(v, 4)})" if when == "before" else
                               f"at {label} the bodies would still approach after the impact "
                               f"(normal velocity {fmt_num(v, 4)}): they would pass through "
                               "each other")
    impulses = [abs(env[n]) for n in solved if _is_normal_impulse(n)]
    big = max(impulses, default=0.0)
    for n in sorted(solved):
        u = system.unknowns.get(n)
        if u is None or n not in env:
            continue
        v = env[n]
        if _is_normal_impulse(n) and v < -LOOSE * big:
            out.append(f"{n} = {fmt_num(v, 4)} < 0: the contact would pull")
        if u.kind == "restitution" and not -LOOSE <= v <= 1 + LOOSE:
            out.append(f"{n} = {fmt_num(v, 4)} is outside [0, 1]")
    return out


def _is_normal_impulse(name) -> bool:
    """A contact's normal impulse `J_n[A]@2->3` (its key says so; no name is parsed)."""
    return getattr(name, "comp", None) is Component.JN


def _trial(system, structure, block, env, solve_block) -> set[str]:
    """Solve, on `env`, the later blocks that the redundant equations and the contact
    checks need; the names solved."""
    want: set[str] = set()
    for k in structure.redundant:
        want |= structure.incidence[k]
    for t in system.transitions:
        for _, vn1, vn2 in t.contacts:
            variables(vn1, want)
            variables(vn2, want)
    want |= {n for n, u in system.unknowns.items()
             if u.kind == "restitution" or _is_normal_impulse(n)}
    later = [b for b in structure.needed_blocks(sorted(want & set(structure.block_of_var)))
             if b > block.index]
    if sum(len(structure.blocks[b].unknowns) for b in later) > TRIAL_LIMIT:
        return set()
    done: set[str] = set()
    _depth[0] += 1
    try:
        for b in later:
            blk = structure.blocks[b]
            try:
                solve_block(blk, env)
            except (ProblemError, KeyError, ArithmeticError, ValueError):
                continue
            done |= set(blk.unknowns)
    finally:
        _depth[0] -= 1
    return done


def separating_hint(system, names, roots) -> str | None:
    """A hint `body.qty < v` (or `>`) in some state that keeps one root and not the
    others: the unknown whose roots are furthest apart, cut between them at a round value."""
    best = None
    for j, n in enumerate(names):
        u = system.unknowns[n]
        if u.kind != "state" or not u.body or not u.state:
            continue
        vals = sorted(x[j] for x in roots)
        gaps = [b - a for a, b in zip(vals, vals[1:])]
        scale = max(abs(v) for v in vals) or 1.0
        gap = min(gaps, default=0.0) / scale
        if gap > 1e-6 and (best is None or gap > best[0]):
            best = (gap, j, n, vals)
    if best is None:
        return None
    _, j, n, vals = best
    u = system.unknowns[n]
    lo, hi = vals[0], vals[1]  # cut between the two smallest: `<` keeps the lowest root
    cut = _round_between(lo, hi)
    c = fmt_num(cut, 3) + (f" {u.unit}" if cut != 0 and u.unit else "")
    kept_lo = next(x for x in roots if x[j] == lo)
    kept_hi = [x for x in roots if x[j] > cut]
    text = (f"`{u.body}.{u.qty} < {c}` in state {u.state} keeps "
            f"{n} = {fmt_num(kept_lo[j], 4)}")
    if len(kept_hi) == 1:
        text += f"; `{u.body}.{u.qty} > {c}` keeps {n} = {fmt_num(kept_hi[0][j], 4)}"
    return text


def _round_between(lo: float, hi: float) -> float:
    """A short number strictly between lo and hi (0 if they differ in sign)."""
    if lo < 0 < hi:
        return 0.0
    mid = (lo + hi) / 2
    for sig in range(1, 8):
        c = float(fmt_num(mid, sig))
        if lo < c < hi:
            return c
    return mid if math.isfinite(mid) else lo
