"""Solve: values for the unknowns, block by block, with checks.

Linear blocks are solved with numpy after row and column equilibration (the
unknowns mix N*s, m/s and rad/s), and their condition number is reported. Nonlinear
blocks (energy phases) use damped Newton with branch hints from the file.
Friction contacts are solved as stick first and switched to sliding where
|J_t| > mu*J_n; where that does not settle on regimes that keep Coulomb's law,
regime_search tries every combination. The regime that held is reported.
"""
from __future__ import annotations

import math
import sys
from collections import ChainMap

from . import rowcode
from .analyse import Structure, analyse
from .compile import Equation, System, compile_scene
from .diagnostics import Diagnostic, ProblemError
from .elements.kinds import Component, KeyKind
from .block_memo import solve, solve_one  # linalg's, once per distinct block
from .bounds import (ROUNDOFF, _grad_size, error_of, propagate, slopes_and_size,
                     slopes_of)
from .expr import (
    E,
    NonLinear,
    affine,
    variables,
    affine_exact,
    diff,
    evaluate,
    evaluate_exact,
    magnitude,
    to_text,
)
from .linalg import SMALL, SingularError, exact_rank_test
from .numbers import fmt_num, fmt_tiny
from .records import record
from .scene import Scene

REL_TOL = 1e-9  # residual tolerance relative to the size of an equation's terms


@record
class BlockReport:
    index: int
    unknowns: list[str]
    equations: list[int]
    method: str  # linear | newton | explicit
    cond: float | None = None
    iterations: int = 0
    residual: float = 0.0
    matrix: list[list[float]] | None = None
    rhs: list[float] | None = None
    quality: object = None  # linalg.Quality of a linear block
    rejected: list | None = None  # Newton: roots the physics rejected, with the reasons
    unphysical: list | None = None  # Newton: why the only root found is not physical


@record
class CheckReport:
    name: str
    status: str  # ok | warning | error | info
    detail: str
    value: float | None = None


@record
class Solution:
    system: System
    structure: Structure
    values: dict[str, float]
    blocks: list[BlockReport]
    checks: list[CheckReport]
    diagnostics: list[Diagnostic]
    regimes: dict[str, str]
    answers: list[tuple[str, float, str, float]]  # name, display value, unit, SI value
    solved_all: bool = False
    precision: str = "float"
    size: dict | None = None  # each solved unknown's size (bounds.propagate)
    errors: dict | None = None  # each solved unknown's absolute error bound
    exact: dict | None = None  # exact mode: the linear blocks' values as rationals
    answer_errors: dict | None = None  # each answer's absolute error bound (SI)
    deferred: list | None = None  # inconsistencies found in a friction regime on trial
    snapped: set | None = None  # solved values that were round-off around zero, now 0


def solve_scene(scene: Scene, solve_all: bool = False, max_rounds: int = 8,
                precision: str = "float") -> Solution:
    """Compile, analyse and solve, iterating the friction regimes until they hold; where
    that does not settle on a solution that keeps Coulomb's law at every impact contact,
    every stick/slide combination is tried (regime_search)."""
    from . import regime_search

    regimes: dict[str, str] = {}
    tried: set[tuple] = set()
    rounds = 0
    refused = system = None  # a regime tried on the way that does not solve at all
    while True:
        try:
            sol, results = _solve_regimes(scene, regimes, solve_all, precision)
        except ProblemError as exc:
            system = _regime_system(scene, regimes)
            if system is None:
                raise
            refused = exc
            break
        rounds += 1
        changed = _update_regimes(sol, regimes)
        key = tuple(sorted(regimes.items()))
        if not changed or key in tried or rounds >= max_rounds:
            break
        tried.add(key)
    if refused is not None or changed or regime_search.violations(sol) or \
            regime_search.restitution_found(sol.system):
        sol, results, regimes = regime_search.search(
            system if refused is not None else sol.system, regimes,
            lambda r: _solve_regimes(scene, r, solve_all, precision), refused)
    assert sol is not None
    if sol.deferred:  # a check failed in the regime that held (earlier rounds were trials)
        raise sol.deferred[0]
    sol.regimes = dict(regimes)
    _hint_checks(sol)
    _law_checks(sol, results)
    _finite_answers(sol)
    return sol


def _regime_system(scene: Scene, regimes: dict) -> System | None:
    """The compiled system when it has impact friction contacts whose regime is still to
    choose (a stick assumption can leave `restitution ?` undetermined where sliding
    decides it), else None."""
    from .regime_search import impact_sites

    try:
        system = compile_scene(scene, regimes, {})
    except ProblemError:
        return None
    return system if impact_sites(system) else None


def _solve_regimes(scene: Scene, regimes: dict, solve_all: bool, precision: str):
    """One solve in the given friction regimes: (solution, the path-law contacts' results)."""
    impulses: dict = {}  # Poisson's and Stronge's contacts: (P_t, P_n) by site
    results: dict = {}
    while True:
        system = compile_scene(scene, regimes, impulses)
        # each residual's shape: taken by analyse, read by solve (a small one: walked)
        with rowcode.remembered(len(system.equations)):
            structure = analyse(system)
            pending = [s for s in system.path_laws if s.key not in impulses]
            if not pending:
                sol = _solve(system, structure, solve_all, precision,
                             defer=bool(system.friction))
                return sol, results
            # an impulse path starts from the state before its impact: solve only that
            # (the first pass's Newton rows for the contact decide nothing that is used),
            # one contact at a time, in the order the impacts happen
            from .contact_laws import next_site, resolve_site

            site, need, after = next_site(system, pending)
            values = _solve_only(system, structure, need, after, precision)
            results[site.key] = resolve_site(system, values, site, precision)
            impulses[site.key] = results[site.key].impulse


def _finite_answers(sol: Solution) -> None:
    """The last guard before anything is printed: an answer that is not a finite number
    (an overflow, a 0/0 the earlier checks missed) is an error at its `find` item, never
    a printed nan, inf or null."""
    spans = {f.name: f.span for f in sol.system.finds}
    bad = [Diagnostic("error", "not-finite", f"{name} is not a finite number (got {si!r}): "
                      "the data overflow or lose all precision in float64", spans.get(name),
                      ("check the magnitudes and units of the data it depends on",))
           for name, v, _u, si in sol.answers
           if not (math.isfinite(v) and math.isfinite(si))]
    if bad:
        raise ProblemError.many(bad)


def _solve_only(system: System, structure: Structure, names: set[str], after: set[str],
                precision: str) -> dict[str, float]:
    """Values of `names` alone (the blocks they need), none of which may need `after`."""
    from .contact_laws import not_before

    values: dict[str, float] = {}
    missing = structure.undetermined_for(sorted(names))
    if missing:
        raise not_before(system, missing, "is not determined")
    blocks = structure.needed_blocks(sorted(names))
    if any(set(structure.blocks[b].unknowns) & after for b in blocks):
        bad = [n for n in sorted(names)
               if any(set(structure.blocks[b].unknowns) & after
                      for b in structure.needed_blocks([n]))]
        raise not_before(system, bad, "is found only through the impact")
    for b in blocks:
        _solve_block(system, structure, structure.blocks[b], values, precision)
    return values


def _law_checks(sol: Solution, results: dict) -> None:
    """The path-law contacts' phases, and energy gained under Newton's law with friction."""
    from .contact_laws import energy_gain_checks, path_law_checks

    for name, status, detail in path_law_checks(sol.system, results) + \
            energy_gain_checks(sol.system, sol.values):
        sol.checks.append(CheckReport(name, status, detail))


def _update_regimes(sol: Solution, regimes: dict[str, str]) -> bool:
    """Switch violated stick assumptions to sliding (and wrong slide signs). True if changed."""
    changed = False
    v = sol.values
    for site in sol.system.friction:
        if site.jn not in v:
            continue
        jn = v[site.jn]
        jt = v.get(site.jt, 0.0) if site.jt else 0.0
        if site.regime == "stick":
            if abs(jt) > site.mu * jn * (1 + 1e-12) + 1e-300:
                regimes[site.key] = "slide+" if jt < 0 else "slide-"
                changed = True
        elif site.slip_expr is not None and not site.decided:
            try:
                slip = evaluate(site.slip_expr, v)
            except KeyError:
                continue
            want = "slide+" if slip > 0 else "slide-"
            if slip != 0 and want != site.regime:
                regimes[site.key] = want
                changed = True
    return changed


def _needed(system: System, structure: Structure, solve_all: bool,
            find_vars: set | None = None) -> list[str]:
    """The unknowns this solve needs, sorted. `find_vars`: the finds' unknowns, if known."""
    if solve_all or not system.finds:
        return [n for n in system.unknowns if n not in structure.under]
    return sorted(_needed_set(system, structure, find_vars))


def _needed_set(system: System, structure: Structure, find_vars: set | None,
                energies: bool = True) -> list[str]:
    """`_needed`'s unknowns in no particular order (what `needed_blocks` takes: sorting
    10^5 keys costs more than finding their blocks); without the impacts' energies'
    unknowns when `energies` is False (`_energy_names`)."""
    names: set[str] = set(find_vars) if find_vars is not None else set()
    if find_vars is None:
        for f in system.finds:
            variables(f.expr, names)
    # friction regimes and energy checks need their impulses and velocities
    for site in system.friction:
        names.add(site.jn)
        if site.jt:
            names.add(site.jt)
        if site.slip_after is not None:  # an impact's slip, before and after (Coulomb)
            variables(site.slip_expr, names)
            variables(site.slip_after, names)
    # stated principles and user equations are checked when redundant: solve what they need
    # every redundant equation is checked (an inconsistent file must never pass silently)
    for k in structure.redundant:
        names |= structure.incidence[k]
    # every integration runs (integration.py): an end it never reaches is an error
    for integ in system.integrations:
        names.update(integ.outputs)
    # every impact's impulses: the report's energy loss per contact, and a block whose
    # rows depend on each other (a pin and a contact joining the same bodies) is only
    # found inconsistent by solving it
    for name, u in system.unknowns.items():
        if u.kind in ("impulse", "angular-impulse"):
            names.add(name)
    if energies:
        _energy_names(system, names)
    return [n for n in names if n not in structure.under]


def _energy_names(system: System, names: set) -> set:
    """The report's energy check for each impact needs the velocities on both sides."""
    for t in system.transitions:
        if t.kind == "impact" and t.energy is not None:
            for T in t.energy:
                rowcode.variables_into(T, names, variables)
    return names


def _solve(system: System, structure: Structure, solve_all: bool,
           precision: str = "float", defer: bool = False) -> Solution:
    with rowcode.remembered():  # each equation's shape is read once
        try:
            return _solve_rounds(system, structure, solve_all, precision, defer)
        finally:
            if "momentum_cli.block_rows" in sys.modules:  # a large block's rows kept
                sys.modules["momentum_cli.block_rows"].forget()


def _solve_rounds(system: System, structure: Structure, solve_all: bool,
                  precision: str, defer: bool) -> Solution:
    eqs = system.equations
    diags: list[Diagnostic] = list(system.notes.items)
    checks: list[CheckReport] = []
    values: dict[str, float] = {}
    find_vars: set[str] = set()
    for f in system.finds:
        rowcode.variables_into(f.expr, find_vars, variables)
    wanted = sorted(find_vars) if system.finds and not solve_all else []
    reports: list[BlockReport] = []
    bounds: dict[str, float] = {}
    exact: dict | None = {} if precision == "exact" else None  # rationals of exact mode
    state = _Rounds()
    state.reports, state.exact = reports, exact
    state.find_vars = find_vars
    # rounds: solve the structure's blocks; where a block is numerically singular, or
    # the structurally under-determined part determines some unknowns numerically,
    # re-analyse with what is known and the dependent rows left out, and go on
    for _ in range(len(eqs) + 2):
        # pure checks first: equations whose every term is given (or already solved)
        for k in structure.constant_eqs:
            if k not in state.checked and k not in state.used:
                state.checked.add(k)
                _check_conflict(eqs[k], values, checks, system, structure, state, bounds,
                                constant=not structure.incidence[k])
        if not _solve_round(system, structure, solve_all, precision, values, reports, bounds,
                            state, wanted, exact):
            break
        structure = analyse(system, state.excluded, values)
    _check_under_part(system, structure, values, precision, state.used)
    missing = structure.undetermined_for(wanted)
    if missing and state.support and set(missing) <= state.free:
        # the structure would name more; the numbers leave only these free
        raise _singular(sorted((eqs[k] for k in state.support),
                               key=lambda e: (e.span.line if e.span else 0, e.index)),
                        missing, exact=True)
    if missing:
        raise _under_determined(system, structure, missing)
    # done with by the rounds: freed (and packed) before the error bounds' peak of memory
    bounds.clear()
    structure.pack()
    size, err = propagate(system, reports, values, exact is not None, state.fused)
    deferred: list[ProblemError] = []
    for k in structure.redundant:
        e = eqs[k]
        if all(v in values for v in structure.incidence[k]):
            try:
                _check_conflict(e, values, checks, system, structure, state,
                                size=size, err=err, exact=exact)
            except ProblemError as exc:
                # with friction, this round's regime may be a trial: decide after it holds
                if not defer or exc.diagnostics[0].code != "inconsistent":
                    raise
                deferred.append(exc)
    for rep in reports:
        for text in rep.rejected or []:
            checks.append(CheckReport(f"root rejected, block {', '.join(rep.unknowns[:3])}",
                                      "info", text))
        if rep.unphysical:
            checks.append(CheckReport(f"only root, block {', '.join(rep.unknowns[:3])}",
                                      "warning", "not physical: " + "; ".join(rep.unphysical)))
    snapped = _snap_roundoff(values, size, err, checks, exact)
    for k, e in enumerate(eqs):
        if e.kind in ("stated", "user") and (k in structure.redundant or k in structure.under_eqs):
            missing = sorted(v for v in structure.incidence[k] if v not in values)
            if missing:
                where = f"line {e.span.line}" if e.span else "the scene"
                checks.append(CheckReport(e.principle, "info",
                                          f"not checked ({where}): it needs "
                                          f"{', '.join(missing)}, which "
                                          f"{'is' if len(missing) == 1 else 'are'} not "
                                          "determined"))
    sol = Solution(system, structure, values, reports, checks, diags, {}, [], solve_all)
    sol.precision = precision
    sol.size, sol.errors, sol.exact = size, err, exact
    sol.deferred = deferred
    sol.snapped = snapped
    if not deferred:
        sol.answers = _answers(system, values, sol)
    return sol


def _snap_roundoff(values, size, err, checks, exact) -> set[str]:
    """A solved value within its error bound of zero, and round-off against the size of
    the terms that determine it, is zero: goldens show 0, not a platform's 1e-16."""
    snapped = []
    for name, x in values.items():
        if x != 0.0 and name in err and abs(x) <= min(err[name], ROUNDOFF * size[name]):
            values[name] = 0.0
            if exact is not None and name in exact:
                exact[name] = 0
            snapped.append(name)
    if snapped:
        checks.append(CheckReport(
            "round-off", "info", f"{', '.join(sorted(snapped))}: within "
            f"{'its' if len(snapped) == 1 else 'their'} error bound of zero, so 0"))
    return set(snapped)


class _Rounds:
    """What the solve rounds carry from one analysis to the next."""

    def __init__(self):
        self.excluded: set[int] = set()  # numerically dependent rows: checks, not solved
        self.used: set[int] = set()  # rows that determined values (never re-checked)
        self.checked: set[int] = set()
        self.split_tried: set[tuple] = set()
        self.support: set[int] = set()  # rows of the numeric dependencies found
        self.free: set[str] = set()  # unknowns a numeric rank test left undetermined
        self.reports: list = []  # the blocks solved so far (their sizes judge the checks)
        self.exact: dict | None = None
        self.find_vars: set | None = None  # the finds' unknowns (walked once per solve)
        self.fused: dict = {}  # id of a block's report -> (kind, shapes): block_kinds solved it


def _solve_round(system: System, structure: Structure, solve_all: bool, precision: str,
                 values, reports, bounds, state: _Rounds, wanted,
                 exact: dict | None = None) -> bool:
    """Solve the blocks this structure needs. True if the system must be re-analysed:
    a block was singular (its dependent rows are now left out) or the under-determined
    part determined some unknowns numerically."""
    from .numeric_rank import dependent_rows, inconsistent_rows

    plain = solve_all or not system.finds or not rowcode.ENABLED
    needed = _needed(system, structure, solve_all, state.find_vars) if plain else \
        _needed_set(system, structure, state.find_vars, energies=False)
    names = [n for n in needed if n not in structure.under]
    # the under-determined part matters when an answer needs it (or everything is asked)
    split = bool(structure.under) and (not wanted or bool(structure.undetermined_for(wanted)))
    if split:  # what the under-determined rows need, to rank them with numbers
        for k in _under_rows(structure):
            names.extend(v for v in structure.incidence[k]
                         if v not in structure.under and v not in values)
    order = structure.needed_blocks(names)
    if not plain and len(order) < len(structure.blocks):
        # the impacts' energies' velocities, walked only where they can add a block
        # (a scene whose answers and impulses need every block needs no walk of them)
        names.extend(n for n in _energy_names(system, set()) if n not in structure.under)
        order = structure.needed_blocks(names)
    # blocks of one unknown in one equation, in float (most blocks of a large scene):
    # `_solve_block`'s first step and `_add_bounds` in line; None goes the general way
    lane = rowcode.ENABLED and not system.integrations and exact is None and \
        precision == "float"
    blocks, used = structure.blocks, state.used
    # small float blocks of a kind met often: its generated code (block_kinds)
    kinds = _block_kinds() if lane and len(order) >= KINDS_FROM else None
    fused = state.fused
    at = retry = 0  # retry: where a run of one-unknown blocks may be tried again
    while at < len(order):
        b = order[at]
        at += 1
        block = blocks[b]
        if kinds is not None and 1 < len(block.unknowns) <= SMALL:
            got = kinds.take(block, system.equations, values, BlockReport)
            if got is not None:
                rep = got[0]
                reports.append(rep)
                used.update(block.equations)
                _add_bounds(rep, bounds)
                fused[id(rep)] = got[1]
                continue
        if lane and len(block.unknowns) == 1 and len(block.equations) == 1:
            if at > retry and "numpy" not in sys.modules:
                retry = len(order)  # runs of them as arrays only where numpy is loaded
            if at > retry:  # a long run of them together
                from .solve_ones import run as run_of_ones

                nxt, run, retry = run_of_ones(system, blocks, order, at - 1, values,
                                              _one_report)
                if run:
                    for blk, rep in run:
                        reports.append(rep)
                        used.add(blk.equations[0])
                        bounds[blk.unknowns[0]] = rep.quality.components[0]
                    at = nxt
                    continue
            got = kinds.take(block, system.equations, values, BlockReport) \
                if kinds is not None else None
            if got is not None:
                rep = got[0]
                fused[id(rep)] = got[1]
            else:
                rep = _solve_one(system, block, values)
            if rep is not None:
                reports.append(rep)
                used.add(block.equations[0])
                bounds[block.unknowns[0]] = rep.quality.components[0]
                continue
        try:
            rep = _solve_block(system, structure, block, values, precision, exact)
        except ProblemError as exc:
            if exc.diagnostics[0].code == "singular":
                bad = inconsistent_rows(system, block.equations, block.unknowns, values,
                                        exact=precision == "exact")
                if bad is not None:
                    raise _dependent_conflict(system, structure, state.used, values,
                                              *bad) from None
                dep, support = dependent_rows(system, block.equations, block.unknowns, values)
                if dep - state.excluded:
                    state.excluded |= dep
                    state.support = state.support or support  # the first: the cause
                    return True
                _blame_downstream(system, structure, b, values, exc)
            elif exc.diagnostics[0].code == "ill-conditioned" and precision != "exact":
                # singular to float64 but not exactly: a statement true only to round-off
                # (a stated direction that is perpendicular to a normal in decimals) is
                # a dependent row to check, not a reason to refuse the file
                dep, support = dependent_rows(system, block.equations, block.unknowns,
                                              values, exact=False)
                dep = {k for k in dep if system.equations[k].kind in ("stated", "user")}
                if dep - state.excluded:
                    state.excluded |= dep
                    state.support = state.support or support
                    return True
            raise
        reports.append(rep)
        state.used.update(block.equations)
        _add_bounds(rep, bounds)
    if split:
        return _split_under(system, structure, precision, values, reports, bounds, state)
    return False


KINDS_FROM = 64  # blocks in a round from which their kinds are counted (block_kinds.AFTER)


def _block_kinds():
    """The block_kinds module where this solve may use it (imported only then), or None."""
    from . import block_kinds

    return block_kinds if block_kinds.enabled() else None


def _check_under_part(system: System, structure: Structure, values, precision: str,
                      used: set[int]) -> None:
    """The under-determined part can still be inconsistent: rows whose left sides depend
    on each other (two momentum rows that see only the sum of a pin's and a contact's
    impulse) with numbers that disagree. Checked even when no answer needs that part."""
    from .numeric_rank import UNDER_LIMIT, inconsistent_rows

    if not structure.under:
        return
    ks = _under_rows(structure)
    rank = {n: i for i, n in enumerate(system.unknowns)}
    cols = sorted({v for k in ks for v in structure.incidence[k] if v in structure.under},
                  key=lambda n: rank.get(n, len(rank)))
    if not cols or len(cols) > UNDER_LIMIT:
        return
    bad = inconsistent_rows(system, ks, cols, values, exact=precision == "exact")
    if bad is not None:
        raise _dependent_conflict(system, structure, used, values, *bad)


def _dependent_conflict(system: System, structure: Structure, used: set[int], values,
                        row: int, support: set[int]) -> ProblemError:
    """Rows whose left sides depend on each other but whose numbers disagree: an
    inconsistency, named by every statement in it: those rows, and the rows that fixed
    the values they use (a stated velocity, a restitution law)."""
    eqs = system.equations
    e = eqs[row]
    known = {v for k in support for v in structure.incidence[k] if v in values}
    fixers = {k for k in used if structure.incidence[k] & known}
    rows = support | fixers
    parts: dict[int, list[str]] = {}
    for k in sorted(rows):
        q = eqs[k]
        if q.span is not None:
            parts.setdefault(q.span.line, []).append(q.principle)
        for name, line in _given_lines(q, system):
            parts.setdefault(line, []).append(f"given {name}")
    items = [f"line {line} ({'; '.join(dict.fromkeys(parts[line]))})" for line in sorted(parts)]
    whats = "; ".join(dict.fromkeys(eqs[k].principle for k in sorted(support)))
    return ProblemError(f"inconsistent: {e.principle} does not hold", e.span,
                        code="inconsistent",
                        notes=[f"together with {whats}, it has no solution",
                               "the conflicting statements (the smallest set): " +
                               ", ".join(items)])


def _under_rows(structure: Structure) -> list[int]:
    """The rows of the under-determined part, and the dependent rows that touch it."""
    return sorted(structure.under_eqs | {k for k in structure.redundant
                                         if structure.incidence[k] & structure.under})


def _add_bounds(rep: BlockReport, bounds) -> None:
    comps = rep.quality.components if rep.quality is not None else None
    for j, name in enumerate(rep.unknowns):
        # Newton blocks converge to ~1e-14 of their terms; allow for their conditioning
        bounds[name] = comps[j] if comps else max(rep.residual * 100, 1e-12)


def _split_under(system: System, structure: Structure, precision: str, values, reports,
                 bounds, state: _Rounds) -> bool:
    """Answer the unknowns the structurally under-determined rows determine numerically
    (the velocities after a contact declared twice; only the split of the impulse is
    free): solve the independent rows for their pivots, with the free columns at 0,
    and keep the pivots that every solution agrees on. True if anything was found."""
    from .numeric_rank import split_under

    ks = _under_rows(structure)
    key = (tuple(ks), tuple(sorted(structure.under)))
    if key in state.split_tried:
        return False
    state.split_tried.add(key)
    sp = split_under(system, structure.under, ks, values, precision == "exact")
    if sp is None:
        return False
    state.free.update(sp.free)
    state.support = state.support or sp.support  # the first dependency found: the cause
    if not sp.determined:
        return False
    piv = [sp.cols[p] for _, p in sp.basis]
    col = {n: j for j, n in enumerate(piv)}
    rows = [{col[sp.cols[j]]: v for j, v in sp.rows[k].items() if sp.cols[j] in col}
            for k, _ in sp.basis]
    rhs = [sp.rhs[k] for k, _ in sp.basis]
    beqs = [system.equations[k] for k, _ in sp.basis]
    x, quality = solve_linear(rows, rhs, beqs, piv, precision)
    trial = dict(values)
    trial.update(zip(piv, x))
    trial.update((n, 0.0) for n in sp.cols if n not in col)
    keep = [j for j, n in enumerate(piv) if n in set(sp.determined)]
    names = [piv[j] for j in keep]
    comps = quality.components
    quality = type(quality)(**{f: getattr(quality, f) for f in quality._fields})
    quality.components = [comps[j] for j in keep] if comps else None
    rep = BlockReport(len(reports), names, [k for k, _ in sp.basis], "linear", quality.cond, 0,
                      0.0, None, None, quality)
    for n in names:
        values[n] = trial[n]
    reports.append(rep)
    _add_bounds(rep, bounds)
    state.used.update(k for k, _ in sp.basis)
    # the dependent rows hold for every solution if they hold for this one
    free_bounds = dict(bounds)
    for j, n in enumerate(piv):
        free_bounds.setdefault(n, comps[j] if comps else 0.0)
    for k in sp.dependent:
        _check_conflict(system.equations[k], trial, [], system, structure, state,
                        free_bounds)
    state.excluded.update(sp.dependent)
    return True


def _check_conflict(e: Equation, values, checks, system, structure, state: _Rounds,
                    bounds: dict[str, float] | None = None, constant: bool = False,
                    size: dict | None = None, err: dict | None = None,
                    exact: dict | None = None) -> None:
    """`_check_equation`, and if the equation does not hold, name every statement of the
    smallest conflict it is part of (the rows a left null vector involves). Within the
    solve rounds (no propagated sizes yet) the blocks' relative `bounds` give the
    unknowns' absolute error bounds."""
    if size is None and state.reports:  # within the rounds: the sizes of what is solved
        size, err = propagate(system, state.reports, values, state.exact is not None,
                              state.fused)
    if err is None and bounds:
        err = {n: b * abs(values[n]) for n, b in bounds.items() if n in values}
    try:
        _check_equation(e, values, checks, system, structure, constant=constant,
                        size=size, err=err, exact=exact)
    except ProblemError as exc:
        d = exc.diagnostics[0]
        if d.code != "inconsistent":
            raise
        note = _conflict_note(e, values, system, state)
        if not note:
            raise
        raise ProblemError(d.message, d.span, code=d.code, notes=[*d.notes, note],
                           caret=d.caret) from None


def _conflict_note(e: Equation, values, system: System, state: _Rounds) -> str | None:
    from .numeric_rank import conflict_set

    used = sorted(state.used)
    if len(used) > 3000:
        return None
    ks = conflict_set(system, e.index, used, values)
    if len(ks) < 1:
        return None
    return _statements_note([system.equations[k] for k in ks], system)


def _statements_note(eqs, system: System) -> str | None:
    """'the conflicting statements (the smallest set): line N (what), ...' for `eqs`."""
    parts: dict[int, list[str]] = {}
    for q in eqs:
        if q.span is not None:
            parts.setdefault(q.span.line, []).append(q.principle)
        for name, line in _given_lines(q, system):
            parts.setdefault(line, []).append(f"given {name}")
    if not parts:
        return None
    items = []
    for line in sorted(parts):
        whats = list(dict.fromkeys(parts[line]))
        shown = "; ".join(whats[:3]) + (f"; and {len(whats) - 3} more" if len(whats) > 3 else "")
        items.append(f"line {line} ({shown})")
    return "the conflicting statements (the smallest set): " + ", ".join(items)


def _scale(e: Equation, values: dict[str, float]) -> float:
    try:
        return magnitude(e.residual, values)
    except (KeyError, ValueError, ZeroDivisionError, OverflowError):
        return 0.0


_UNIT_SCALES: list = [None, None]  # (values dict, its scales): one pass per solve


def _unit_scales(system: System, values: dict) -> dict[str, float]:
    """The largest magnitude among the solved values of each unit (m/s, rad/s, N*s) and
    the given state values (a rad/s answer that is round-off around 0 is still read
    against the scene's given angular velocities)."""
    if _UNIT_SCALES[0] is values and _UNIT_SCALES[1][0] == len(values):
        return _UNIT_SCALES[1][1]
    from .scene import STATE_QTYS

    out: dict[str, float] = {}
    for spec in system.scene.states.values():
        for (_body, qty), (x, _span) in spec.givens.items():
            unit = STATE_QTYS.get(qty, (None, None))[1]
            if unit is not None and isinstance(x, float) and math.isfinite(x):
                out[unit] = max(out.get(unit, 0.0), abs(x))
    for n, x in values.items():
        u = system.unknowns.get(n)
        if u is not None and isinstance(x, float) and math.isfinite(x):
            out[u.unit] = max(out.get(u.unit, 0.0), abs(x))
    _UNIT_SCALES[0], _UNIT_SCALES[1] = values, (len(values), out)
    return out


DECIDE = 1e-6  # a check whose error bound exceeds this fraction of its size cannot decide


def _check_equation(e: Equation, values, checks, system, structure, constant=False,
                    size: dict[str, float] | None = None, err: dict[str, float] | None = None,
                    exact: dict | None = None) -> None:
    """A redundant equation must hold to within what the solve can promise.

    It is judged against the size of the quantities in it (the terms that determine
    each unknown, not only its own value, which can be round-off around zero) and the
    error bound of each unknown it uses. In exact mode the residual is evaluated in
    rationals and only the rounding of the data remains. Where the bound is too wide
    to tell a real inconsistency from round-off, the check says so (a warning).
    """
    # the slopes and the size in one walk (`slopes` and `size_of`, bit for bit:
    # tests/test_bounds_fused.py)
    slope, scale = slopes_and_size(e.residual, values, size or {})
    try:
        r = float(evaluate_exact(e.residual, ChainMap(exact, values))) if exact is not None \
            else evaluate(e.residual, values)
    except (KeyError, ValueError, ZeroDivisionError, OverflowError):
        r = math.nan
    # the size of the quantities involved: an unknown that comes out exactly 0 (e = 0
    # against a wall) is still a velocity of a scene whose velocities are metres per
    # second, and a statement of it is read against that
    units = _unit_scales(system, values)
    scale = max(scale, sum(sl * units.get(system.unknowns[v].unit, 0.0)
                           for v, sl in slope.items() if v in system.unknowns))
    bound = error_of(slope, err or {})
    tol = ROUNDOFF * scale + bound
    ok = math.isfinite(r) and abs(r) <= tol or (scale == 0 and r == 0)
    where = f"line {e.span.line}" if e.span else "the scene"
    if ok:
        # (a bound that is not above 0 decides: the terms' own size need not be walked)
        if bound > DECIDE * scale or bound > 0.0 and \
                _undecided_terms(r, bound, _own_size(e, values)):
            checks.append(CheckReport(
                f"{e.principle}", "warning",
                f"cannot decide ({where}): residual {fmt_num(r, 3)} is within the error "
                f"bound {fmt_num(bound, 3)} of a {fmt_num(scale, 3)}-sized equation; "
                "solve with `--precision exact` to tell", r))
        elif e.kind in ("stated", "user", "consistency") or not constant:
            checks.append(CheckReport(f"{e.principle}", "ok",
                                      f"holds (redundant; {where}; residual {fmt_tiny(r)})", r))
        return
    others = set()
    for v in structure.incidence[e.index]:
        k = structure.match_var.get(v)
        if k is not None and system.equations[k].span:
            others.add(system.equations[k].span.line)
    notes = [f"{e.text()}  ->  {e.text(numeric=True)}  (off by {fmt_num(r, 4)})"]
    if others:
        notes.append("it conflicts with the equations from line" + ("s " if len(others) > 1 else
                     " ") + ", ".join(str(x) for x in sorted(others)))
    related = [e] + [system.equations[structure.match_var[v]]
                     for v in sorted(structure.incidence[e.index]) if v in structure.match_var]
    given = sorted({g for x in related for g in _given_lines(x, system)},
                   key=lambda kv: (kv[1], kv[0]))
    if given:
        notes.append("it uses the given value" + ("s " if len(given) > 1 else " ") +
                     ", ".join(f"{name} (line {line})" for name, line in given))
    if constant:
        notes.append("every quantity in it is given: one of the given values is inconsistent "
                     "with it")
    raise ProblemError(f"inconsistent: {e.principle} does not hold", e.span,
                       code="inconsistent", notes=notes)


def _undecided_terms(r: float, bound: float, own: float) -> bool:
    """The equation's own terms are real values (above the bound, not round-off zeros),
    known only to worse than DECIDE relative, and the residual is no round-off of them:
    a quantity that cancels (known to 40 %) stated 1e-3 off cannot be judged in float."""
    return bound < own and bound > DECIDE * own and abs(r) > 2 * ROUNDOFF * own


def _own_size(e: Equation, values) -> float:
    """The size of an equation's own terms at the solved values (0 if it cannot be had)."""
    try:
        return magnitude(e.residual, values)
    except (KeyError, ValueError, ZeroDivisionError, OverflowError):
        return 0.0


def _given_lines(e: Equation, system: System) -> list[tuple[str, int]]:
    """The given state values an equation uses, with the lines that give them."""
    found: dict[str, int] = {}
    for x in _given_states([e.lhs, e.rhs]):
        st = system.scene.states.get(x.name.state)
        g = st.givens.get((x.name.body, x.name.qty)) if st else None
        if g is not None:
            found[x.name] = g[1].line
    return sorted(found.items(), key=lambda kv: (kv[1], kv[0]))


def _given_states(exprs):
    """The given state quantities (`Known` nodes named by a state key) in expressions."""
    from .expr import Add, Fn, Known, Mul, Pow

    todo = list(exprs)
    while todo:
        x = todo.pop()
        t = type(x)
        if t is Known and getattr(x.name, "kind", None) == KeyKind.STATE:
            yield x
        elif t is Add:
            todo.extend(x.terms)
        elif t is Mul:
            todo.extend(x.factors)
        elif t is Pow:
            todo.append(x.base)
        elif t is Fn:
            todo.append(x.arg)


def _under_determined(system: System, structure: Structure, missing: list[str]) -> ProblemError:
    shown = missing[:8]
    more = f" and {len(missing) - 8} more" if len(missing) > 8 else ""
    notes = []
    kinds = {system.unknowns[m].kind for m in missing if m in system.unknowns}
    tips = []
    if "state" in kinds:
        tips.append("give the missing velocities or positions in their states")
    if "impulse" in kinds or "restitution" in kinds:
        tips.append("add a restitution coefficient or a post-impact velocity")
    if "duration" in kinds:
        tips.append("give a `duration`, an end condition (`stops`, `rolls on`) or a force of "
                    "known size")
    if "angular-impulse" in kinds:
        tips.append("add an end condition such as `A stops relative to B`")
    if tips:
        notes.append("; ".join(tips))
    for k in sorted(structure.under_eqs):
        eq = system.equations[k]
        if eq.principle.startswith("work-energy:") and len(system.scene.bodies) > 1:
            i, j = eq.group.split(" ", 1)[1].split(" -> ")
            notes.append(f"`{eq.group}` balances the energy of every body together: for "
                         f"some of them write `energy {i} -> {j} of {{BODY, ...}}` (groups "
                         f"that do not interact: `of {{A}}, {{B}}`)")
            break
    n_eq = len(structure.under_eqs)
    notes.append(f"the undetermined part has {len(structure.under)} unknowns and {n_eq} "
                 f"equation{'s' if n_eq != 1 else ''}")
    first_line = None
    for m in missing:
        u = system.unknowns.get(m)
        if u and u.state and u.body:
            st = system.scene.states.get(u.state)
            if st is not None:
                first_line = st.span
                break
    for m in missing if first_line is None else ():
        first_line = _transition_span(system, m) if "->" in m else None  # t@1->2, dx@...
        if first_line is not None:
            break
    word = "is" if len(missing) == 1 else "are"
    return ProblemError(f"under-determined: {', '.join(shown)}{more} {word} not determined",
                        first_line, code="under-determined", notes=notes, caret=False)


def _solve_block(system: System, structure: Structure, block, values,
                 precision: str = "float", exact: dict | None = None) -> BlockReport:
    if system.integrations:  # a phase integrated numerically (integration.py)
        from .integration import solve_integration

        integ = solve_integration(system, block, values)
        if integ is not None:  # its residual: the integrator's tolerance
            return BlockReport(block.index, block.unknowns, block.equations, "integrated",
                               residual=integ.rtol)
    names = block.unknowns
    if rowcode.ENABLED and len(names) == 1 and len(block.equations) == 1 and \
            exact is None and precision == "float":
        rep = _solve_one(system, block, values)
        if rep is not None:
            return rep
    eqs = [system.equations[k] for k in block.equations]
    bset = set(names)
    col = {n: j for j, n in enumerate(names)}
    rows, rhs = [], []
    got = _rows_as_arrays(system, block, col, values) if exact is None and \
        precision == "float" and len(eqs) == len(names) else None
    try:
        for e in eqs if got is None else ():
            # exact mode forms the rows in rationals too (no cancellation in the rhs)
            coef, const = rowcode.affine(e.residual, bset, values) if exact is None else \
                affine_exact(e.residual, bset, ChainMap(exact, values))
            rows.append({col[n]: v for n, v in coef.items() if v != 0.0})
            rhs.append(-const)
    except NonLinear:
        return _newton(system, block, eqs, names, values, structure)
    except (KeyError, ValueError, ZeroDivisionError, OverflowError) as exc:
        raise ProblemError(f"cannot evaluate {eqs[0].principle}: {exc}", eqs[0].span,
                           code="number") from None
    if got is not None:
        rows, rhs = got
    x, quality = solve_linear(rows, rhs, eqs, names, precision)
    for n, v in zip(names, x):
        values[n] = v
    if exact is not None and quality.exact is not None:
        exact.update(zip(names, quality.exact))
    n = len(names)
    matrix = [[float(row.get(j, 0.0)) for j in range(n)] for row in rows] if n <= 12 else None
    return BlockReport(block.index, names, block.equations, "linear", quality.cond, 0, 0.0,
                       matrix, [float(v) for v in rhs] if matrix is not None else None,
                       quality)


def _rows_as_arrays(system: System, block, col: dict, values):
    """A large square block's (rows, rhs) read per shape as arrays (`block_rows`: the
    banded LU loads numpy for it anyway), or None: its rows then one by one."""
    from . import linalg

    if len(col) < linalg.BIG:
        return None
    try:
        import numpy  # noqa: F401 - block_rows' arrays
    except ImportError:
        return None
    from . import block_rows

    return block_rows.rows(system.equations, block.equations, col, values)


def _solve_one(system: System, block, values) -> BlockReport | None:
    """`_solve_block` of one unknown in one linear equation, in float (most blocks of a
    large scene): the same row, solve and report without the general path's lists;
    None where that path has more to say (not linear, not finite, singular, a value
    missing), which then runs as it always does."""
    name = block.unknowns[0]
    try:
        coef, const = rowcode.affine(system.equations[block.equations[0]].residual,
                                     {name: 0}, values)
    except (NonLinear, KeyError, ValueError, ZeroDivisionError, OverflowError):
        return None
    a = coef.get(name, 0.0)
    b = -const
    if a == 0.0 or not (math.isfinite(a) and math.isfinite(b)):
        return None
    try:
        x, quality = solve_one(a, b)  # what solve_linear gives a 1x1 float block (shared)
    except SingularError:
        return None
    values[name] = x[0]
    return _one_report(block, a, b, x, quality)


def _one_report(block, a, b, x, quality) -> BlockReport:
    """The report of a block of one unknown solved as `_solve_one` solves it."""
    return BlockReport(block.index, block.unknowns, block.equations, "linear", quality.cond,
                       0, 0.0, [[float(a)]], [float(b)], quality)


def _all_finite(rows, rhs) -> bool:
    """Every coefficient (row by row) and then every right-hand side is finite."""
    isfinite = math.isfinite
    for row in rows:
        if not all(map(isfinite, row.values())):
            return False
    return all(map(isfinite, rhs))


def solve_linear(rows, rhs, eqs, names, precision: str = "float"):
    """Solve one linear block; a singular one is named by an exact rank test."""
    if not _all_finite(rows, rhs):
        raise ProblemError("the equations contain a number that is not finite", eqs[0].span,
                           code="number")
    try:
        return solve(rows, rhs, len(names), precision)
    except SingularError as exc:
        free = exc.free if exc.exact else exact_rank_test(rows, rhs, len(names))
        if free:
            raise _singular(eqs, [names[j] for j in free], exc.cond, exact=True) from None
        c = f" have condition number {fmt_num(exc.cond, 3)}" if math.isfinite(exc.cond) else \
            " are singular in float64"
        raise ProblemError(
            f"ill-conditioned beyond float64: the equations for {', '.join(names[:6])}"
            f"{'...' if len(names) > 6 else ''}{c}",
            eqs[0].span, code="ill-conditioned",
            notes=["the block is not singular in exact arithmetic: solve it with "
                   "`--precision exact`"]) from None


def _blame_downstream(system: System, structure: Structure, b: int, values, exc) -> None:
    """Name the unknowns a singular block really leaves free.

    A block can be singular because equations repeat (a contact declared twice): its
    own unknowns may then be fixed while the freedom lies in the blocks that use them
    (how the impulse splits between the two contacts). The exact null space of the
    block together with the linear blocks downstream of it says which. Raises the
    better error, or returns to let the block's own error stand.
    """
    down = {b}
    for blk in structure.blocks:  # blocks come in dependency order
        if blk.depends & down:
            down.add(blk.index)
    names = [n for k in sorted(down) for n in structure.blocks[k].unknowns]
    if len(names) > 3000:
        return
    col = {n: j for j, n in enumerate(names)}
    rows, rhs, eqs = [], [], []
    for k in sorted(down):
        for q in structure.blocks[k].equations:
            e = system.equations[q]
            try:
                coef, const = affine(e.residual, set(names), values)
            except (NonLinear, KeyError, ValueError, ZeroDivisionError, OverflowError):
                return
            rows.append({col[n]: v for n, v in coef.items() if v != 0.0})
            rhs.append(-const)
            eqs.append(e)
    free = exact_rank_test(rows, rhs, len(names))
    if free:
        raise _singular(eqs, [names[j] for j in free], None, exact=True) from None


def _singular(eqs, names, cond=None, exact=False) -> ProblemError:
    lines = sorted({e.span.line for e in eqs if e.span})
    c = f" (condition number {fmt_num(cond, 3)})" if cond is not None and math.isfinite(cond) \
        else ""
    how = "rank-deficient: " if exact else "singular: "
    return ProblemError(f"{how}the equations do not determine {', '.join(names)}{c}",
                        eqs[0].span, code="singular",
                        notes=[f"equations from line{'s' if len(lines) > 1 else ''} "
                               f"{', '.join(map(str, lines))} are dependent; a contact or "
                               "constraint may be declared twice, or a normal is parallel to "
                               "another"])


SPREAD = (0.7, -0.7, 2.0, -2.0, 0.3, -1.3, 1.1, -0.4)
DEDUPE_STARTS = True  # Newton runs once from each distinct start (False: from every one)
EARLY_STOP = True  # a start stops where it has met a root found before (False: runs on)


def _starts(system: System, names: list[str], values, eqs=()) -> list[list[float]]:
    """Starting points for Newton: from the hints, then guesses spread in sign and size
    (scaled by the given speeds: a root far from 1 is found too)."""
    S = 1.0
    for x in _given_states(e.residual for e in eqs):  # the given speeds' scale
        S = max(S, abs(x.value))
    base = []
    for n in names:
        u = system.unknowns[n]
        if u.kind == "restitution" and not u.hints:
            base.append([0.5, 0.9, 0.2])
            continue
        lo = max((v for rel, v, _ in u.hints if rel == ">"), default=None)
        hi = min((v for rel, v, _ in u.hints if rel == "<"), default=None)
        if lo is not None and hi is not None:
            base.append([(lo + hi) / 2, lo + (hi - lo) * 0.25, lo + (hi - lo) * 0.75])
        elif lo is not None:
            w = max(abs(lo), 1.0)
            base.append([lo + 0.5 * w, lo + 2 * w, lo + 0.05 * w])
        elif hi is not None:
            w = max(abs(hi), 1.0)
            base.append([hi - 0.5 * w, hi - 2 * w, hi - 0.05 * w])
        else:
            base.append(None)
    starts = [[b[min(k, len(b) - 1)] if b else SPREAD[k] for b in base] for k in range(3)]
    if S > 1.0 or len(names) > 1:  # sign patterns that differ between unknowns, at scale S
        for k in range(len(SPREAD)):
            starts.append([b[0] if b else S * SPREAD[(k + 3 * i) % len(SPREAD)]
                           for i, b in enumerate(base)])
    return starts


def _satisfies(system: System, names, x) -> bool:
    for n, v in zip(names, x):
        for rel, bound, _ in system.unknowns[n].hints:
            if system.unknowns[n].kind in ("impulse", "duration"):
                continue  # physical checks, reported separately
            if rel == ">" and not v > bound:
                return False
            if rel == "<" and not v < bound:
                return False
    return True


def _close(x, y) -> bool:
    return all(abs(a - b) <= 1e-7 * max(abs(a), abs(b)) + 1e-9 for a, b in zip(x, y))


def _newton(system: System, block, eqs: list[Equation], names: list[str], values,
            structure: Structure | None = None) -> BlockReport:
    """Every root from a spread of starts; the hints and the physics choose among them."""
    from .roots import problems, separating_hint

    from .lowered import lower

    F = [e.residual for e in eqs]
    J = [[diff(f, n) for n in names] for f in F]
    lowered = (lower([F]), lower(J))  # one call per evaluation, the same floats
    roots = []
    tried = set()  # a start met again (hinted unknowns repeat theirs) ends where it did
    for x0 in _starts(system, names, values, eqs):
        key = tuple((v, math.copysign(1.0, v)) for v in x0)
        if key in tried and DEDUPE_STARTS:
            continue
        tried.add(key)
        known = [y for y, _ in roots] if EARLY_STOP else ()
        r = _newton_from(F, J, names, values, x0, lowered, known)
        if r is None:
            continue
        x, iters = r
        if not any(_close(x, y) for y, _ in roots):
            roots.append((x, iters))
    lines = sorted({e.span.line for e in eqs if e.span})
    where = f"line{'s' if len(lines) > 1 else ''} {', '.join(map(str, lines))}"
    if not roots:
        raise ProblemError(f"no real solution for {', '.join(names)}: {eqs[0].principle} cannot "
                           "be satisfied", eqs[0].span, code="no-solution",
                           notes=[f"from {where}; check the given energies and heights (e.g. not "
                                  "enough energy to reach the given position)"])
    roots.sort(key=lambda r: r[0])  # the order of the starts must not matter
    hinted = [r for r in roots if _satisfies(system, names, r[0])]
    has_hint = any(system.unknowns[n].hints and system.unknowns[n].kind not in
                   ("impulse", "duration") for n in names)

    def show(x):
        big = max(abs(v) for v in x)  # round-off around zero prints as 0 (stable goldens)
        return ", ".join(f"{n} = {fmt_num(v if abs(v) > 1e-12 * big else 0.0, 4)}"
                         for n, v in zip(names, x))

    def listing(rs):
        return "; ".join(show(x) for x, _ in rs)

    if not hinted:
        raise ProblemError(f"no solution of {eqs[0].principle} satisfies the hints", eqs[0].span,
                           code="no-solution", notes=[f"solutions found: {listing(roots)}"])
    why: list[list[str]] = []
    if structure is not None:
        def trial(blk, env):
            _solve_block(system, structure, blk, env)

        broken: list[list[int]] = [[] for _ in hinted]
        why = [problems(system, structure, block, names, x, values, trial, b)
               for (x, _), b in zip(hinted, broken)]
    else:
        why = [[] for _ in hinted]
    physical = [r for r, w in zip(hinted, why) if not w]
    rejected = [f"{show(r[0])}: {'; '.join(w)}" for r, w in zip(hinted, why) if w]
    if not physical and len(hinted) > 1 and structure is not None:
        _overdetermined(system, eqs, hinted, why, broken, show)
    if not physical and len(hinted) > 1:
        raise ProblemError(f"no physical solution for {', '.join(names)}", eqs[0].span,
                           code="no-solution", notes=[f"rejected: {x}" for x in rejected])
    chosen = physical if physical else hinted
    if len(chosen) > 1 or (len(roots) > 1 and not has_hint and not rejected):
        hint = separating_hint(system, names, [x for x, _ in chosen])
        notes = [f"solutions: {listing(chosen)}"]
        if rejected:
            notes.append("rejected: " + " | ".join(rejected))
        if hint:
            notes.append(f"choose one with a hint: {hint}")
        raise ProblemError(f"more than one solution for {', '.join(names)}", eqs[0].span,
                           code="ambiguous", notes=notes)
    x, iters = chosen[0]
    for n, v in zip(names, x):
        values[n] = float(v)
    # the residual relative to the size of each equation's terms
    res = max(abs(evaluate(f, values)) / max(magnitude(f, values), 1e-300) for f in F)
    rep = BlockReport(block.index, names, block.equations, "newton", None, iters, res)
    rep.rejected = rejected if physical else []
    rep.unphysical = [] if physical else why[0]
    return rep


def _overdetermined(system: System, eqs, roots, why, broken, show) -> None:
    """A nonlinear block whose only physical root breaks a redundant statement of the
    file: that statement and the block's contradict each other (as a linear conflict)."""
    only = [i for i, w in enumerate(why) if broken[i] and len(w) == len(broken[i])]
    if len(only) != 1:
        return
    i = only[0]
    stated = [system.equations[k] for k in broken[i]
              if system.equations[k].kind in ("stated", "user")]
    if not stated:
        return
    e = stated[0]
    raise ProblemError(f"inconsistent: {e.principle} does not hold", e.span,
                       code="inconsistent",
                       notes=[f"the only physical root of the block ({show(roots[i][0])}): "
                              f"{'; '.join(why[i])}",
                              _statements_note([e, *eqs], system)])


def _newton_from(F, J, names, values, x0, lowered=(None, None), known=()):
    """Damped Newton from x0; (x, iterations) on convergence, else None. `lowered`:
    F's and J's `lowered.lower` functions (or None: evaluate walks the trees).

    `known`: roots found from earlier starts. An iterate that has come within a hundredth
    of `_close`'s tolerance of one of them, by a last step within a tenth of it, stops
    there: its limit would be dropped as that root's duplicate, and it is (x is `_close`
    to the root). Safe: Newton's next steps depend on the iterate alone, and from there
    the rest of the path is at most about the last step (quadratic convergence makes it
    far shorter; a double root converges linearly with ratio 1/2, the steps summing to
    about the last one), so the limit stays within 0.11 of the tolerance of that root."""
    from .linalg import lstsq_small

    env = dict(values)
    x = [float(v) for v in x0]
    fast_f, fast_j = lowered
    isfinite = math.isfinite

    def resid(xv):
        env.update(zip(names, xv))
        try:
            out = fast_f(env)[0] if fast_f is not None else [evaluate(f, env) for f in F]
        except (ValueError, ZeroDivisionError, OverflowError):
            return None
        return out if all(map(isfinite, out)) else None

    def norm(v):
        return math.sqrt(sum([a * a for a in v]))

    r = resid(x)
    if r is None:
        return None
    norm_r = norm(r)
    for it in range(1, 101):
        scale = max(1.0, max(map(abs, x)))
        if max(map(abs, r)) == 0.0:
            return x, it - 1
        try:
            Jm = fast_j(env) if fast_j is not None else \
                [[evaluate(d, env) for d in row] for row in J]
            dx = lstsq_small(Jm, [-v for v in r])
        except (ValueError, ZeroDivisionError, OverflowError, ArithmeticError):
            return None
        if not all(map(isfinite, dx)):
            return None
        step, norm0 = 1.0, norm_r
        while step > 1e-6:
            xn = [a + step * d for a, d in zip(x, dx)]
            rn = resid(xn)
            if rn is not None:
                norm_r = norm(rn)
                if norm_r < norm0 * (1 - 1e-4 * step):
                    break
            step /= 2
        else:
            resid(x)
            return (x, it) if norm0 <= 1e-10 * scale else None
        x, r = xn, rn
        moved = max(abs(step * d) for d in dx)
        if moved <= 1e-14 * scale:
            return x, it
        if known and moved <= 1e-8 * scale + 1e-10 and _near_known(x, step, dx, known):
            return x, it
    return (x, 100) if max(abs(v) for v in r) < 1e-9 * max(1.0, max(abs(v) for v in x)) else None


def _near_known(x, step, dx, known) -> bool:
    """`_newton_from`'s early stop: x within a hundredth of `_close`'s tolerance of a known
    root, component by component, and the last step within a tenth of it."""
    for y in known:
        for a, b, d in zip(x, y, dx):
            tol = 1e-7 * abs(b) + 1e-9
            if abs(a - b) > 0.01 * tol or abs(step * d) > 0.1 * tol:
                break
        else:
            return True
    return False


def _transition_span(system: System, name: str):
    """Where the transition (or burn, gain) of a duration `t@A->B` is declared."""
    key = name.partition("@")[2]
    sc = system.scene
    for t in list(sc.transitions) + list(sc.burns) + list(sc.gains):
        if f"{t.before}->{t.after}" == key:
            return t.span
    return None


def _hint_checks(sol: Solution) -> None:
    """Physical sanity: contacts push, durations are positive, friction regimes hold."""
    sysm, v = sol.system, sol.values
    for name, u in sysm.unknowns.items():
        if name not in v:
            continue
        if u.kind == "duration" and v[name] <= 0:
            raise ProblemError(f"{name} = {fmt_num(v[name], 4)} s: the end condition is not "
                               "reached forward in time", _transition_span(sysm, name),
                               code="no-solution",
                               notes=["check the signs of the given velocities and the slip "
                                      "direction"])
        if getattr(name, "comp", None) == Component.JN and v[name] < 0:
            sol.checks.append(CheckReport(f"contact {name}", "warning",
                                          f"normal impulse {fmt_num(v[name], 4)} N*s < 0: the "
                                          "contact would pull; the bodies are separating", v[name]))
        if u.kind == "state" and u.hints:
            for rel, bound, span in u.hints:
                if (rel == ">" and not v[name] > bound) or (rel == "<" and not v[name] < bound):
                    sol.diagnostics.append(Diagnostic(
                        "warning", "hint", f"{name} = {fmt_num(v[name], 4)} {u.unit}, but the "
                        f"file says {u.body}.{u.qty} {rel} {fmt_num(bound, 4)}", span,
                        ("the equations have only this solution: check the hint or the "
                         "givens",)))
    for site in sysm.friction:
        if site.jn not in v:
            continue
        jn = v[site.jn]
        jt = v.get(site.jt, 0.0) if site.jt else 0.0
        if site.regime == "no slip":  # a rough contact checked against `static MU`
            status, detail = site.law.static_check(jt, jn)
        elif site.regime == "stick":
            detail = (f"stick held: |J_t| = {fmt_num(abs(jt), 4)} <= mu*J_n = "
                      f"{fmt_num(site.mu * jn, 4)} N*s")
            status = "ok" if abs(jt) <= site.mu * jn * (1 + 1e-9) else "warning"
        else:
            detail = (f"sliding: J_t = -mu*J_n against the slip ({fmt_num(jt, 4)} N*s, "
                      f"mu = {fmt_num(site.mu, 3)})")
            status = "ok"
        sol.checks.append(CheckReport(f"friction at {site.label} ({site.transition})", status,
                                      detail))


def _answers(system: System, values, sol: Solution | None = None) -> list[tuple]:
    """The `find` values, in the solve's precision (rationals in exact mode: a derived
    difference keeps its digits), each with an absolute error bound that covers what is
    printed; of two forms of a quantity (T_lost) the one with the smaller bound is shown;
    a value within its bound of zero is zero (the checks say so)."""
    exact = sol.exact if sol is not None else None
    out, bounds = [], {}
    for f in system.finds:
        try:
            si, bound, small = _value(f.expr, values, sol)
        except KeyError as exc:
            raise ProblemError(f"{f.name} could not be computed: {exc.args[0]} is not solved",
                               f.span, code="internal") from None
        except (ValueError, ZeroDivisionError, OverflowError):
            raise ProblemError(f"{f.name} is not a finite number", f.span, code="number") \
                from None
        if f.alt is not None and exact is None:
            try:
                other = _value(f.alt, values, sol)
                if other[1] < bound:
                    si, bound, small = other
            except (KeyError, ValueError, ZeroDivisionError, OverflowError):
                pass
        if si != 0.0 and math.isfinite(si) and abs(si) <= min(bound, small):
            if sol is not None:
                sol.checks.append(CheckReport(
                    f"{f.name}", "info", "round-off: within its error bound of zero, so it is "
                    "0 (the digits are not significant)"))
            si = 0.0
        bounds[f.name] = bound
        out.append((f.name, si / f.factor, f.unit, si))
    if sol is not None:
        sol.answer_errors = bounds
    return out


def _big_sum():
    """terms_columns' walk of a long sum's terms as arrays, where numpy is loaded (by a
    large block's banded LU); else None (term by term)."""
    if "numpy" not in sys.modules:
        return None
    from .terms_columns import walk_sum

    return walk_sum


def _value(expr: E, values, sol: Solution | None) -> tuple[float, float, float]:
    """(value, absolute error bound, round-off level) of a derived expression."""
    exact = sol.exact if sol is not None else None
    size = sol.size if sol is not None and sol.size is not None else {}
    err = sol.errors if sol is not None and sol.errors is not None else {}
    got = rowcode.value_grad_size(expr, values, _grad_size, _big_sum()) \
        if exact is None else None
    if got is not None:  # a large sum (an energy): each term walked once for both
        si, dv, mag = got
        slope, scale = slopes_of(dv, mag, size)
    else:
        si = float(evaluate_exact(expr, ChainMap(exact, values))) if exact is not None else \
            rowcode.evaluate(expr, values)
        slope, scale = slopes_and_size(expr, values, size)
    small = ROUNDOFF * scale
    # rounding: of the final value in exact mode, of every term in float
    bound = error_of(slope, err) + (2 * 2.0**-53 * abs(si) if exact is not None else small)
    return si, bound, small


__all__ = ["solve_scene", "Solution", "analyse", "to_text", "E"]
