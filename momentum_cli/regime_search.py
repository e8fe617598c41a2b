"""Solve: the Coulomb regimes of impact contacts, when trying stick first does not settle.

In: a solution, and a function that solves the scene in given regimes. Out: the one
combination of stick / slide+ / slide- per impact friction contact that satisfies
Coulomb's law at every contact, or an error naming the contacts (none, or several).
"""
from __future__ import annotations

from itertools import product

from .diagnostics import ProblemError
from .elements.kinds import Regime

MAX_SITES = 6  # 3^6 = 729 solves; beyond that the search is refused, not attempted
CHOICES = (Regime.STICK, Regime.SLIDE_POS, Regime.SLIDE_NEG)


def impact_sites(system) -> list:
    """The impact friction contacts whose regime is chosen (stick, or slide either way)."""
    return [s for s in system.friction if s.slip_after is not None]


def restitution_found(system) -> bool:
    """A `restitution ?` beside impact friction: the e a regime yields is only checked
    against [0, 1], so another regime may keep Coulomb's law with another e -- every
    combination is tried, and more than one admissible is refused, not picked."""
    return bool(impact_sites(system)) and any(u.kind == "restitution"
                                              for u in system.unknowns.values())


def violations(sol) -> list[tuple[object, str]]:
    """(site, why) for every impact friction contact whose solved impulses break Coulomb."""
    out = []
    sites = impact_sites(sol.system)
    for name, u in sol.system.unknowns.items() if sites else ():
        v = sol.values.get(name)
        if u.kind == "restitution" and v is not None and not -1e-9 <= v <= 1 + 1e-9:
            out.append((sites[0], f"the found {name} = {v:.6g} is outside [0, 1]"))
    for site in sites:
        if site.jn not in sol.values:
            continue
        try:
            why = site.law.violation(site, sol.values)
        except KeyError:  # a slip velocity not solved: nothing to judge it by
            continue
        if why:
            out.append((site, why))
    return out


def _combo_text(sites, combo) -> str:
    return ", ".join(f"{s.label} {r.value}" for s, r in zip(sites, combo))


def search(system, regimes: dict, solve_with, refused: ProblemError | None = None):
    """Every stick/slide combination of the impact friction contacts, solved; the one
    that keeps Coulomb's law everywhere is returned as (solution, results, regimes).
    None or several such combinations are errors that say so, never a silent pick;
    `refused` (the error of a regime that did not solve on the way) is raised when no
    combination solves at all."""
    sites = impact_sites(system)
    names = ", ".join(f"{s.label} ({s.transition})" for s in sites)
    span = sites[0].span if sites else None
    if len(sites) > MAX_SITES:
        raise ProblemError(
            f"the friction regimes of {names} did not settle, and {len(sites)} contacts are "
            f"too many to try every stick/slide combination (at most {MAX_SITES})", span,
            code="no-solution", notes=["give fewer rough contacts per impact, or state the "
                                       "regime (`rough` for no slip, `smooth`)"])
    found, failed = [], []
    for combo in product(CHOICES, repeat=len(sites)):
        trial = dict(regimes)
        trial.update({s.key: r.value for s, r in zip(sites, combo)})
        try:
            got, results = solve_with(trial)
        except ProblemError as exc:
            failed.append(f"{_combo_text(sites, combo)}: {exc.diagnostics[0].message}")
            continue
        bad = violations(got)
        if bad:
            failed.append(f"{_combo_text(sites, combo)}: " +
                          "; ".join(f"{s.label}: {why}" for s, why in bad))
            continue
        found.append((combo, got, results, trial))
    clean = [f for f in found if not f[1].deferred]
    if len(clean) == 1:
        return clean[0][1:]
    if len(clean) > 1:
        raise ProblemError(
            f"Coulomb's law allows {len(clean)} solutions for the friction contacts {names}: "
            + " | ".join(_combo_text(sites, f[0]) for f in clean), span, code="ambiguous",
            notes=["the rigid impact model with Coulomb friction does not decide between "
                   "them; state more (a measured velocity, or `rough`/`smooth`)"])
    if found:  # the physical regime contradicts a statement of the file
        raise found[0][1].deferred[0]
    if refused is not None:
        raise refused
    raise ProblemError(
        f"no stick/slide combination of the friction contacts {names} satisfies Coulomb's "
        "law", span, code="no-solution",
        notes=failed[:9] + ([f"... and {len(failed) - 9} more"] if len(failed) > 9 else []))
